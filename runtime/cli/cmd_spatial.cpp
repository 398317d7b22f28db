// `mechgen check`, `info` and `sweep` on a spatial model (dimension: spatial): the structure
// (spanning tree, circuits, Davies' network matrix and its primary / secondary split), the
// assembly and redundancy, the info JSON of DESIGN.md's "Spatial models" and the numeric sweep.
#include "cli/cmd_spatial.hpp"

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>

#include "cli/model_info.hpp"
#include "model/spatial_graph.hpp"
#include "model/spatial_value_checks.hpp"
#include "ondemand/data_paths.hpp"
#include "ondemand/kernel_budget.hpp"
#include "ondemand/kernel_resolver.hpp"
#include "report/column_plot.hpp"
#include "report/csv_table.hpp"
#include "spatial/spatial_drawing.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_kernel_sweep.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"
#include "spatial_derivation.hpp"
#include "spatial_emitter.hpp"
#include "sweep/shard.hpp"
#include "sweep/sweep.hpp"

namespace mechgen::cli {

namespace {

using spatial::V3;

std::string vec_text(const V3& v) {
  return "[" + fixed(v[0], 6) + ", " + fixed(v[1], 6) + ", " + fixed(v[2], 6) + "]";
}

SpatialModel load_spatial(const std::string& path) {
  g_current_file = path;
  return read_spatial_model(path);
}

}  // namespace

int run_spatial_check(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  const SpatialModel model = load_spatial(path);
  const spatial::SpatialSolver solver(model, {});
  const SpatialGraph& g = solver.graph();
  const spatial::SpatialInstance& in = solver.instance();
  std::string out = path + ": spatial model '" + model.common.name + "'" +
                    (model.common.description.empty() ? "" : ": " + model.common.description) +
                    "\n";
  for (const std::string& note : model.notes) out += "note: " + note + "\n";
  std::vector<std::vector<std::string>> rows{{"name", "mass [kg]", "com (body frame)", "kind"}};
  for (size_t b = 0; b < model.bodies.size(); ++b)
    rows.push_back({model.bodies[b].name, model.bodies[b].ground ? "ground" : fixed(in.mass[b]),
                    model.bodies[b].ground ? "" : vec_text(in.com[b]),
                    model.bodies[b].is_virtual ? "virtual (massless)" : ""});
  out += "\nbodies (" + std::to_string(model.bodies.size()) + ")\n" + table(rows, "  ");
  rows = {{"name", "type", "first", "second", "coordinates", "s", "s0"}};
  for (size_t j = 0; j < model.joints.size(); ++j) {
    const SpatialJoint& joint = model.joints[j];
    const int c0 = g.joint_column[j];
    rows.push_back({joint.name + (joint.is_virtual ? " (virtual)" : ""), to_string(joint.type),
                    model.bodies[static_cast<size_t>(joint.first)].name,
                    model.bodies[static_cast<size_t>(joint.second)].name,
                    std::to_string(joint.columns.size()),
                    joint.columns.empty() ? "" : vec_text(in.axes[static_cast<size_t>(c0)].s),
                    vec_text(in.joint_point[j])});
  }
  out += "\njoints (" + std::to_string(model.joints.size()) + ")\n" + table(rows, "  ");
  rows = {{"name", "drives", "kind", "value", "range"}};
  for (const SpatialDriver& d : model.drivers)
    rows.push_back({d.name, model.joints[static_cast<size_t>(d.joint)].name, to_string(d.kind),
                    d.value.text,
                    d.range ? "[" + d.range->at(0).text + ", " + d.range->at(1).text + "]" : ""});
  for (const PoseDriver& pd : model.pose_drivers)
    for (const PoseCoordinate& c : pd.coordinates)
      rows.push_back({pd.name + "." + c.name,
                      model.bodies[static_cast<size_t>(pd.second)].name + " relative to " +
                          model.bodies[static_cast<size_t>(pd.first)].name,
                      c.name[0] == 'r' ? "angle (pose)" : "length (pose)",
                      c.value ? c.value->text : "free (secondary virtual joint)", ""});
  out += "\ndrivers\n" + table(rows, "  ");
  if (!model.loads.empty()) {
    rows = {{"name", "type", "on", "value (ground frame)"}};
    for (const SpatialLoad& f : model.loads)
      rows.push_back(
          {f.name, f.torque ? "torque" : "force",
           model.bodies[static_cast<size_t>(f.body)].name + (f.torque ? "" : " at " + f.point),
           "[" + f.value.x.text + ", " + f.value.y.text + ", " + f.value.z.text + "]"});
    out += "\nloads\n" + table(rows, "  ");
  }

  int virtual_primary = 0;
  for (const int c : g.primary)
    virtual_primary += g.columns[static_cast<size_t>(c)].pose_driver >= 0 ? 1 : 0;
  out += "\nstructure (Davies' method)\n" +
         table({{"joint coordinates", std::to_string(g.cols())},
                {"spanning tree", std::to_string(model.bodies.size() - 1) + " joints"},
                {"independent circuits", std::to_string(g.circuits())},
                {"network matrix N", std::to_string(g.rows()) + " x " + std::to_string(g.cols())},
                {"primary (driven)", std::to_string(g.primary.size()) + " (" +
                                         std::to_string(virtual_primary) + " virtual)"},
                {"secondary", std::to_string(g.secondary.size())}},
               "  ");
  std::string chords;
  for (const int j : g.chords)
    chords += (chords.empty() ? "" : ", ") + model.joints[static_cast<size_t>(j)].name;
  if (!chords.empty()) out += "  circuits closed by: " + chords + "\n";

  spatial::SpatialState state;
  const spatial::SpatialSweepOptions sweep = spatial::default_spatial_sweep(model);
  solver.solve(sweep.t0, state);
  const spatial::Redundancy r = spatial::redundancy(solver, state);
  const Eigen::MatrixXd N = solver.network(state);
  out += "\nassembly at t0 = " + fixed(sweep.t0) +
         ": circuits closed, N q' = " + fixed((N * state.qd).norm(), 3) + "\n";
  if (r.degree == 0) {
    out += "Newton-Euler: reactions and efforts unique\n";
  } else {
    std::string joints;
    const char* names[6] = {"fx", "fy", "fz", "mx", "my", "mz"};
    for (size_t j = 0; j < model.joints.size(); ++j) {
      if (r.joint_unique[j]) continue;
      std::string components;
      for (size_t k = 0; k < 6; ++k)
        if (!r.component_unique[j][k])
          components += (components.empty() ? "" : " ") + std::string(names[k]);
      joints += (joints.empty() ? "" : ", ") + model.joints[j].name + " (" + components + ")";
    }
    out += "redundant constraints: degree " + std::to_string(r.degree) +
           "; reactions not unique at: " + joints + "\n" +
           "caveat: those joints' reactions are reported as the minimum-norm solution (statics "
           "alone does not fix them); driver efforts are " +
           (r.efforts_unique ? "unique" : "NOT unique") + "\n";
  }
  // What the generator makes of it (docs/spatial_kernels.md).
  try {
    const gen::SpatialDerivation d = gen::derive_spatial(model, g);
    const std::string compiled =
        ondemand::current_compiled_kernel(model) ? " (compiled into this mechgen)" : "";
    const size_t newton = d.closure_start.size(), secondary = g.secondary.size();
    if (!d.closed_chain)
      out += "generated kernel: tree, " + std::to_string(d.groups.size()) +
             " bodies by product of exponentials, rates outward, Newton-Euler inward" + compiled +
             "\n";
    else
      out += "generated kernel: closed chain, " + std::to_string(secondary) +
             " secondary coordinates (" + std::to_string(secondary - newton) + " in closed form, " +
             std::to_string(newton) +
             " by Newton-Raphson), Davies' rates by a fixed-pivot elimination, efforts "
             "by virtual power, reactions through N_s transposed" +
             compiled + "\n";
    // The closed-form groups and the closure (docs/spatial_kernels.md).
    for (const int k : d.closed_form_groups) out += "  " + d.plan[static_cast<size_t>(k)] + "\n";
    for (const std::string& line : d.plan)
      if (line.rfind("closure:", 0) == 0) out += "  " + line + "\n";
    // The kernel as its first use generates it (the derivation above), in memory: its size.
    const auto start = std::chrono::steady_clock::now();
    const gen::GenerateOptions options{model.common.file, "", ondemand::templates_dir(), false, ""};
    const std::vector<gen::EmittedFile> files = gen::emit_spatial_files(model, d, options);
    out += ondemand::kernel_cost_report(
        files, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
        !compiled.empty());
  } catch (const std::runtime_error& e) {
    const std::string why = e.what();
    out += "generated kernel: none (" + why.substr(why.find("error: ") + 7) + ")\n";
  }
  std::cout << out;
  return 0;
}

int run_spatial_info(const Args& args) {
  const SpatialModel model = load_spatial(args.single_positional("MODEL.yaml"));
  const spatial::SpatialSolver solver(model, {});
  const SpatialGraph& g = solver.graph();
  if (!args.has("--json")) {
    std::cout << model.common.name << " (spatial): " << model.bodies.size() << " bodies, "
              << model.joints.size() << " joints, " << g.circuits() << " circuits, N " << g.rows()
              << " x " << g.cols() << ", " << spatial::spatial_column_names(model).size()
              << " sweep columns\n";
    return 0;
  }
  std::cout << spatial_model_info_json(model, solver);
  return 0;
}

int run_spatial_sweep(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  const bool generated = solver_option(args) != "numeric";
  // The planar sweep's checks (cmd_sweep.cpp), so no option is taken and then ignored: a spatial
  // sweep is one sequential run (each sample starts from the previous one), so --threads is
  // checked and has nothing to share out; a shard writes its part of the whole run's rows.
  if (!args.has("--out") && !args.has("--summary"))
    throw UsageError("missing --out FILE.csv (or --summary)");
  if (args.integer("--threads", 0) < 0) throw UsageError("--threads must be at least 0");
  const Shard shard = shard_option(args);
  if (!shard.whole() && (!args.has("--out") || args.has("--summary")))
    throw UsageError("--shard writes a part with --out FILE.csv (and no --summary)");
  const SpatialModel model = load_spatial(path);
  // The current compiled-in kernel, else one built on demand (never one of another description).
  const CompiledKernel* kernel = generated ? &ondemand::kernel_for(model) : nullptr;
  std::vector<double> parameters = model.common.default_parameters();
  apply_overrides(model, args.all("--set"), parameters);
  spatial::SpatialSweepOptions options = spatial::default_spatial_sweep(model, parameters);
  options.samples = args.integer("--samples", options.samples);
  if (options.samples < 1) throw UsageError("--samples must be at least 1");
  options.t0 = args.number("--t0", options.t0);
  options.t1 = args.number("--t1", options.t1);
  options.mass_matrix = args.has("--mass-matrix");
  const auto start = std::chrono::steady_clock::now();
  const spatial::SpatialSweepResult result =
      kernel ? spatial::run_spatial_kernel_sweep(model, options, *kernel)
             : spatial::run_spatial_sweep(model, options);
  const double elapsed = seconds_since(start);
  for (const std::string& warning : result.warnings)
    std::cerr << path << ": warning: " << warning << "\n";
  SweepResult part{result.columns, {}};
  const auto [first, end] = shard_range(shard, result.rows.size());
  part.rows.assign(result.rows.begin() + static_cast<std::ptrdiff_t>(first),
                   result.rows.begin() + static_cast<std::ptrdiff_t>(end));
  std::cout << "sweep " << model.common.name << ": "
            << (kernel ? "generated spatial kernel, " : "numeric spatial solver, ")
            << options.samples << " samples, " << result.columns.size() << " columns, "
            << fixed(elapsed * 1e3, 3) << " ms";
  if (args.has("--out")) {
    const std::string out = args.get("--out");
    g_current_file = out;
    write_csv(out, part, part_line(shard));
    if (!shard.whole())
      std::cout << ", part " << shard.index << "/" << shard.count << " (" << part.rows.size()
                << " rows)";
    std::cout << " -> " << out;
  }
  std::cout << "\n";
  if (args.has("--summary")) {
    const ColumnRanges ranges = column_ranges(part);
    std::vector<std::vector<std::string>> rows{{"column", "min", "max", "unit"}};
    for (size_t c = 0; c < ranges.columns.size(); ++c)
      rows.push_back({ranges.columns[c], fixed(ranges.min[c], 8), fixed(ranges.max[c], 8),
                      report::column_unit(ranges.columns[c])});
    std::cout << table(rows, "  ");
  }
  return 0;
}

int run_spatial_draw(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  if (!args.has("--out")) throw UsageError("missing --out FILE.svg");
  if (args.has("--at") == args.has("--animate"))
    throw UsageError("give either --at T or --animate");
  if (args.has("--steps")) throw UsageError("--steps: walking is for planar bipeds");
  if (solver_option(args) != "numeric" && args.has("--solver"))
    throw UsageError("--solver: a spatial model is drawn by the numeric solver");
  const SpatialModel model = load_spatial(path);
  std::vector<double> parameters = model.common.default_parameters();
  apply_overrides(model, args.all("--set"), parameters);
  const spatial::SpatialSolver solver(model, parameters);
  const spatial::SpatialSweepOptions step = spatial::default_spatial_sweep(model, parameters);
  const std::vector<std::string> trace = comma_list(args, "--trace");
  std::vector<double> whole;  // the step: the animation's frames and the traced paths
  const int n = std::min(step.samples, 120);
  for (int i = 0; i < n; ++i)
    whole.push_back(step.t0 + (step.t1 - step.t0) * i / std::max(1, n - 1));
  try {  // the traced names, checked before any solving (no times)
    spatial::spatial_frames(solver, {}, trace);
  } catch (const std::invalid_argument& error) {
    throw UsageError(std::string("--trace: ") + error.what());
  }
  spatial::SpatialFrames frames;
  if (args.has("--at")) {
    // The solver continues along the step from t0, so the branch is the step's.
    const double at = args.number("--at", step.t0);
    std::vector<double> times;
    for (int i = 0; i <= 20; ++i) times.push_back(step.t0 + (at - step.t0) * i / 20);
    frames = spatial::spatial_frames(solver, times);
    // The still: the last frame only, with the paths over the step.
    frames.times = {frames.times.back()};
    frames.bodies = {frames.bodies.back()};
    frames.joints = {frames.joints.back()};
    if (!trace.empty()) {
      const spatial::SpatialFrames paths = spatial::spatial_frames(solver, whole, trace);
      frames.trace_names = paths.trace_names;
      frames.traces = paths.traces;
    }
  } else {
    frames = spatial::spatial_frames(solver, whole, trace);
  }
  spatial::SpatialDrawingOptions options;
  options.width = args.integer("--width", options.width);
  if (options.width < 200) throw UsageError("--width must be at least 200");
  options.title = args.get("--title", "");
  if (!options.title.empty())  // what is drawn, as the planar drawing says it
    options.title += args.has("--at") ? " (t = " + fixed(frames.times.back(), 6) + " s)"
                                      : " (one step, " + fixed(step.t1 - step.t0, 4) + " s)";
  options.labels = args.has("--labels");
  const std::string out = args.get("--out");
  g_current_file = out;
  std::ofstream file(out);
  file << spatial::draw_spatial(frames, options);
  if (!file) throw std::runtime_error(out + ": cannot write");
  std::string views;
  for (const std::string& id : spatial::spatial_views(frames))
    views += (views.empty() ? "" : ", ") + id;
  std::cout << "drew " << model.common.name << " (" << frames.times.size()
            << (frames.times.size() == 1 ? " frame" : " frames") << ", views: " << views << ") -> "
            << out << "\n";
  return 0;
}

}  // namespace mechgen::cli
