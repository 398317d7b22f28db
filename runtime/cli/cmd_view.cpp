// mechgen view: the mechanism in 3D in a browser, from a sweep table or a fresh sweep (one HTML
// file with three.js inlined; runtime/report/html_view.hpp).
#include <iostream>
#include <stdexcept>

#include "analysis/walking.hpp"
#include "cli/command.hpp"
#include "model/spatial_model.hpp"
#include "ondemand/kernel_resolver.hpp"
#include "report/atomic_output.hpp"
#include "report/csv_table.hpp"
#include "report/gltf_export.hpp"
#include "report/html_view.hpp"
#include "report/planar_view_scene.hpp"
#include "report/view_columns.hpp"
#include "spatial/spatial_kernel_sweep.hpp"
#include "spatial/spatial_sweep.hpp"
#include "spatial/spatial_view_scene.hpp"
#include "sweep/sweep.hpp"

namespace mechgen::cli {

namespace {

const char* const kViewHelp =
    R"(usage: mechgen view MODEL.yaml [--csv SWEEP.csv | [--solver generated|numeric] [--samples N]
                    [--t0 T0] [--t1 T1] [--steps N [--ramp SECONDS]]] [--set NAME=VALUE]...
                    [--trace POINT[,POINT...]]... [--plot COLUMN[,COLUMN...]]... [--title TEXT]
                    [--out FILE.html] [--gltf FILE.glb]

The mechanism in 3D, planar or spatial, as one self-contained HTML page (three.js from Debian's
libjs-three inlined: it opens from file:// with no network and no file beside it): bodies from
their mass shapes (bars, boxes, plates; an explicit mass as the translucent box of its principal
inertias; massless links as thin lines), joints by type along their axes, named points, the
ground frame (x red, y green, z blue) and a floor grid. The motion is the table's: each body's
centre of mass and orientation (planar B.x, B.y, B.th; spatial B.x..B.z, B.qw..B.qz) per row,
shown as they are (interpolated between rows only). Drag to orbit, right-drag to pan, wheel to
zoom; play, pause and a time slider; beside it a plot of chosen columns with a cursor at the
slider's time.
  --csv FILE          the table to show: a sweep of this model (mechgen sweep, the same --set
                      values), a planar walk, or mechgen humanoid-gait's gait.csv
  (no --csv)          a sweep of the model's step (--solver, --samples, --t0, --t1 as in
                      mechgen sweep), or with --steps N a planar walk of N steps (as mechgen walk)
  --trace POINTS      the paths of these named points (comma separated, repeatable), dashed, a
                      ball following each; any NAME with NAME.x, NAME.y (and NAME.z) columns
  --plot COLUMNS      the plotted columns (comma separated, repeatable); default: every driver
                      effort, else the first 8 joint torques
  --out FILE.html     the page; #t=T in its address opens it paused at time T
  --gltf FILE.glb     the same bodies with the motion as a glTF 2.0 animation (binary glTF, for
                      Blender and other viewers; float32, +Y up, times shifted to start at 0
                      only when they start before 0)
At least one of --out and --gltf.
)";

report::CsvTable planar_table(const Model& model, const std::vector<double>& parameters,
                              const Args& args, std::string& what) {
  if (args.has("--steps")) {
    analysis::WalkOptions walk;
    walk.parameters = parameters;
    walk.steps = args.integer("--steps", 1);
    if (walk.steps < 1) throw UsageError("--steps must be at least 1");
    walk.ramp = args.number("--ramp", 0);
    if (walk.ramp < 0) throw UsageError("--ramp must be at least 0");
    analysis::WalkResult result = analysis::walk(model, walk);
    what = std::to_string(walk.steps) + " steps walking";
    return {"", std::move(result.columns), std::move(result.rows)};
  }
  const SweepOptions options = sweep_options(model, parameters, args);
  SweepResult result = run_sweep(model, options);
  what = options.solver + " solver, " + std::to_string(options.samples) + " samples";
  return {"", std::move(result.columns), std::move(result.rows)};
}

report::CsvTable spatial_table(const SpatialModel& model, const std::vector<double>& parameters,
                               const Args& args, std::string& what) {
  if (args.has("--steps")) throw UsageError("--steps: walking is for planar bipeds");
  const bool generated = solver_option(args) != "numeric";
  spatial::SpatialSweepOptions options = spatial::default_spatial_sweep(model, parameters);
  options.samples = args.integer("--samples", options.samples);
  if (options.samples < 1) throw UsageError("--samples must be at least 1");
  options.t0 = args.number("--t0", options.t0);
  options.t1 = args.number("--t1", options.t1);
  spatial::SpatialSweepResult result =
      generated ? spatial::run_spatial_kernel_sweep(model, options, ondemand::kernel_for(model))
                : spatial::run_spatial_sweep(model, options);
  what = std::string(generated ? "generated" : "numeric") + " spatial solver, " +
         std::to_string(options.samples) + " samples";
  return {"", std::move(result.columns), std::move(result.rows)};
}

int run_view(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  if (!args.has("--out") && !args.has("--gltf"))
    throw UsageError("missing --out FILE.html (or --gltf FILE.glb)");
  if (args.has("--gltf")) report::check_output_path(args.get("--gltf"));
  if (args.has("--csv"))
    for (const char* option : {"--solver", "--samples", "--t0", "--t1", "--steps", "--ramp"})
      if (args.has(option))
        throw UsageError(std::string(option) + " makes a sweep: not with --csv");
  if (args.has("--ramp") && !args.has("--steps")) throw UsageError("--ramp needs --steps");
  const std::vector<std::string> trace = comma_list(args, "--trace");
  const std::vector<std::string> plot = comma_list(args, "--plot");
  const bool spatial = is_spatial_description(path);
  g_current_file = path;
  std::optional<SpatialModel> spatial_model;
  std::optional<Model> planar_model;
  std::vector<double> parameters;
  if (spatial) {
    spatial_model = read_spatial_model(path);
    parameters = spatial_model->common.default_parameters();
    apply_overrides(spatial_model->common, args.all("--set"), parameters);
  } else {
    planar_model = load_model(path);
    parameters = planar_model->default_parameters();
    apply_overrides(*planar_model, args.all("--set"), parameters);
  }
  const Model& common = spatial ? spatial_model->common : *planar_model;

  std::string what;
  report::CsvTable table;
  if (args.has("--csv")) {
    g_current_file = args.get("--csv");
    table = report::read_csv(args.get("--csv"));
    what = table.path;
  } else {
    table = spatial ? spatial_table(*spatial_model, parameters, args, what)
                    : planar_table(*planar_model, parameters, args, what);
  }
  if (table.rows.empty()) throw UsageError("the table has no rows to show");

  report::ViewScene scene;
  try {
    if (spatial) {
      const spatial::SpatialSolver solver(*spatial_model, parameters);
      scene = spatial::spatial_view_scene(solver, table);
    } else {
      scene = report::planar_view_scene(*planar_model, parameters, table);
    }
    report::add_table_columns(table, spatial, trace, plot, scene);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  const double t0 = scene.times.front(), t1 = scene.times.back();
  scene.title = args.get(
      "--title", common.name + (common.description.empty() ? "" : ": " + common.description) +
                     " (t = " + fixed(t0, 4) + " .. " + fixed(t1, 4) + " s, " +
                     std::to_string(scene.times.size()) + " frames)");
  std::string written;
  for (const char* option : {"--out", "--gltf"}) {
    if (!args.has(option)) continue;
    const std::string out = args.get(option);
    g_current_file = out;
    report::write_file_atomically(out, std::string(option) == "--out"
                                           ? report::render_html_view(scene)
                                           : report::gltf_binary(scene));
    written += (written.empty() ? " -> " : ", ") + out;
  }
  std::cout << "view " << common.name << ": " << what << ", " << scene.bodies.size() << " bodies, "
            << scene.times.size() << " frames" << written << "\n";
  return 0;
}

}  // namespace

Command view_command() {
  return {"view",
          "the mechanism in 3D in a browser (one HTML file), animated from a sweep",
          kViewHelp,
          {{"--csv", "", true},
           {"--solver", "", true},
           {"--samples", "", true},
           {"--t0", "", true},
           {"--t1", "", true},
           {"--steps", "", true},
           {"--ramp", "", true},
           {"--set", "", true, true},
           {"--trace", "", true, true},
           {"--plot", "", true, true},
           {"--title", "", true},
           {"--out", "-o", true},
           {"--gltf", "", true}},
          &run_view};
}

}  // namespace mechgen::cli
