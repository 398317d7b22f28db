// mechgen workspace: Monte Carlo over a spatial model's driver ranges -> extents, sagittal (X-Z)
// and frontal (Y-Z) density images (SVG) and a CSV summary (seed 002's workspace analysis).
#include <exception>
#include <fstream>
#include <iostream>
#include <string>

#include "analysis/workspace.hpp"
#include "cli/command.hpp"
#include "cli/model_info.hpp"
#include "model/spatial_value_checks.hpp"
#include "ondemand/kernel_resolver.hpp"
#include "spatial/spatial_drawing.hpp"
#include "spatial/spatial_sweep.hpp"

namespace mechgen::cli {

namespace {

const char* const kWorkspaceHelp =
    R"(usage: mechgen workspace MODEL.yaml [--samples N] [--seed S] [--threads N] [--point P]
                         [--bins N] [--set NAME=VALUE]... [--fix DRIVER=Q]... [--out PREFIX]
                         [--solver generated|numeric]

Monte Carlo workspace of a spatial model (dimension: spatial): every driver's coordinate drawn
uniformly from its `range:` (sample k's draw depends on S and k only, not on the thread count),
the mechanism placed at each draw, and the named point's position collected.
  --solver S    generated (default): the model's generated kernel, positions only (closed-form
                groups where the graph has them), in blocks on every thread; numeric: the
                reference solver from the step's t0 pose
  --samples N   draws (default 100000)
  --seed S      random seed (default 1)
  --threads N   worker threads (default: every core)
  --point P     the point (default: the model's last named point, e.g. the foot)
  --bins N      image cells along the longer side (default 160)
  --fix D=Q     hold driver D at coordinate Q instead of sampling it (e.g. the quadruped leg's
                side-swing cylinder at l3=0: theta10 = 0, the leg's own plane)
  --out PREFIX  writes PREFIX_sagittal.svg, PREFIX_frontal.svg (density images with a colour
                scale, the mechanism at the step's t0 drawn over them), PREFIX.csv (default
                out/<model>)
Prints the extents, the longest horizontal and vertical chords of the sagittal image on 10 mm
cells (a stride and a lift read the way the seed reads its point cloud: through cells that hold
samples) and the CPU time per sample.
)";

int run_workspace_command(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  g_current_file = path;
  if (!is_spatial_description(path))
    throw UsageError("workspace needs a spatial model (dimension: spatial)");
  const SpatialModel model = read_spatial_model(path);
  analysis::WorkspaceOptions o;
  o.parameters = model.common.default_parameters();
  apply_overrides(model, args.all("--set"), o.parameters);
  o.samples = args.integer("--samples", 100000);
  if (o.samples < 1) throw UsageError("--samples must be at least 1");
  const long seed = args.integer("--seed", 1);
  if (seed < 0) throw UsageError("--seed must not be negative");
  o.seed = static_cast<std::uint64_t>(seed);
  o.threads = static_cast<int>(args.integer("--threads", 0));
  if (o.threads < 0) throw UsageError("--threads must not be negative");
  o.bins = static_cast<int>(args.integer("--bins", 160));
  if (o.bins < 4) throw UsageError("--bins must be at least 4");
  o.point = args.get("--point", "");
  for (const std::string& f : args.all("--fix")) {
    const size_t eq = f.find('=');
    if (eq == std::string::npos) throw UsageError("--fix expects DRIVER=VALUE, got '" + f + "'");
    try {
      o.fixed.emplace_back(f.substr(0, eq), std::stod(f.substr(eq + 1)));
    } catch (const std::exception&) {
      throw UsageError("--fix " + f + ": the value is not a number");
    }
  }
  const std::string solver = args.get("--solver", "generated");
  if (solver != "generated" && solver != "numeric")
    throw UsageError("--solver must be generated or numeric, got '" + solver + "'");
  // (A pose-driven model is refused by run_workspace itself, at the driver.)
  if (solver == "generated" && model.pose_drivers.empty()) o.kernel = &ondemand::kernel_for(model);
  const std::string prefix = args.get("--out", "out/" + model.common.name);
  const analysis::WorkspaceResult r = analysis::run_workspace(model, o);
  auto write = [](const std::string& file, const std::string& text) {
    std::ofstream out(file);
    out << text;
    if (!out) throw UsageError("cannot write " + file);
  };
  // The mechanism at its reference pose (the step's start), over both images for scale.
  const spatial::SpatialSolver reference(model, o.parameters);
  const double t0 = spatial::default_spatial_sweep(model, o.parameters).t0;
  analysis::Outline outline{spatial::spatial_frames(reference, {t0}).bodies.front(),
                            "at its reference pose, t = " + fixed(t0, 6) + " s"};
  for (const auto& [view, projection] :
       {std::pair{"sagittal", &r.sagittal}, std::pair{"frontal", &r.frontal}})
    write(
        prefix + "_" + view + ".svg",
        analysis::density_svg(*projection,
                              model.common.name + ": point " + r.point + ", " + view +
                                  " projection (" + projection->h_name + "-" + projection->v_name +
                                  "), " + std::to_string(r.assembled) + " samples",
                              outline));
  write(prefix + ".csv", analysis::workspace_csv(r));
  const char* axis[3] = {"X", "Y", "Z"};
  std::vector<std::vector<std::string>> rows{{"axis", "min [m]", "max [m]", "extent [m]"}};
  for (size_t c = 0; c < 3; ++c)
    rows.push_back({axis[c], fixed(r.lo[c], 4), fixed(r.hi[c], 4), fixed(r.hi[c] - r.lo[c], 4)});
  std::cout << "workspace " << model.common.name << ": point " << r.point << ", " << r.assembled
            << " of " << r.samples << " samples assembled, " << r.threads << " threads, "
            << fixed(r.seconds, 3) << " s wall ("
            << fixed(r.cpu_seconds / static_cast<double>(r.samples) * 1e6, 1)
            << " us CPU per sample, " << (r.generated ? "generated kernel" : "numeric solver")
            << ")\n"
            << table(rows, "  ") << "sagittal (X-Z), on cells of "
            << fixed(r.sagittal.chord_cell * 1e3, 1) << " mm: longest horizontal chord "
            << fixed(r.sagittal.h_chord, 3) << " m at Z = " << fixed(r.sagittal.h_chord_at, 3)
            << " m, longest vertical chord " << fixed(r.sagittal.v_chord, 3)
            << " m at X = " << fixed(r.sagittal.v_chord_at, 3) << " m\n-> " << prefix
            << "_sagittal.svg, " << prefix << "_frontal.svg, " << prefix << ".csv\n";
  return 0;
}

}  // namespace

Command workspace_command() {
  return {"workspace",
          "Monte Carlo workspace of a spatial model -> density SVGs and CSV",
          kWorkspaceHelp,
          {{"--samples", "", true},
           {"--seed", "", true},
           {"--threads", "", true},
           {"--point", "", true},
           {"--bins", "", true},
           {"--set", "", true, true},
           {"--fix", "", true, true},
           {"--out", "-o", true},
           {"--solver", "", true}},
          &run_workspace_command};
}

}  // namespace mechgen::cli
