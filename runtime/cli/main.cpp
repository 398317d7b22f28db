// mechgen: the command line of ../../../shared/DESIGN.md. One function per sub-command, one small
// argument parser shared by all; every error is one line on stderr and exit code 1.
#include <yaml-cpp/exceptions.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "branch_choice.hpp"
#include "cli/cmd_spatial.hpp"
#include "cli/command.hpp"
#include "cli/model_info.hpp"
#include "generate.hpp"
#include "model/columns.hpp"
#include "model/mechanism_graph.hpp"
#include "model/model.hpp"
#include "model/solve_plan.hpp"
#include "model/support_model.hpp"
#include "numeric/reference_solver.hpp"
#include "ondemand/data_paths.hpp"
#include "ondemand/kernel_budget.hpp"
#include "ondemand/kernel_resolver.hpp"
#include "report/atomic_output.hpp"
#include "report/column_plot.hpp"
#include "report/csv_table.hpp"
#include "report/svg_plot.hpp"
#include "sweep/compiled_kernel.hpp"
#include "sweep/summary.hpp"
#include "sweep/sweep.hpp"

#ifndef MECHGEN_VERSION
#error "MECHGEN_VERSION must be the project's version (set by runtime/cli/CMakeLists.txt)"
#endif
#ifndef MECHGEN_SOURCE_DIR
#error "MECHGEN_SOURCE_DIR must name the source tree (set by runtime/cli/CMakeLists.txt)"
#endif

namespace mechgen::cli {

namespace {

// ---- mechgen check ------------------------------------------------------------------------------

const char* const kCheckHelp =
    R"(usage: mechgen check MODEL.yaml

Validates a mechanism description and prints what mechgen understood of it: parameters, bodies
(mass and inertia at the default parameters), joints, drivers and loads; the structure (mobility
by Gruebler's count against the drivers, independent loops, Newton-Euler unknowns and equations);
the assembly at t0 by the numeric solver (this catches redundant constraints and assembly hints
that do not assemble); and the solve plan the generator follows: the reference body frame, each
group in order, closed form (with the branch the generator picks) or iterative (Newton-Raphson in
the kernel, for groups such as an Assur triad that have no closed form); and the kernel's size
(its header generated in memory, as its first use would: exact) with the expected time and memory
of its first-use compile (an estimate: time within a factor of 4, more on a machine loaded past its
cores; memory within a factor of 2), and a warning when the header is over --max-kernel-mb
(MECHGEN_MAX_KERNEL_MB, default 8), whose first use is then refused.

Problems are reported as FILE:LINE:COL: error: MESSAGE on stderr, exit code 1.
)";

constexpr double kMaxMassProperty = 1e100;

int run_check(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  if (is_spatial_description(path)) return run_spatial_check(args);
  const Model model = load_model(path);
  const std::vector<double> defaults = model.default_parameters();
  const GiNaC::exmap subs = model.substitutions(defaults);
  std::string out;

  out += path + ": model '" + model.name + "'" +
         (model.description.empty() ? "" : ": " + model.description) + "\n";

  std::vector<std::vector<std::string>> rows{{"name", "default", "unit", "as written", "doc"}};
  for (const Parameter& p : model.parameters)
    rows.push_back({p.name, number_text(p.value), p.unit, p.written, p.doc});
  const std::vector<double> derived = model.derived_values(defaults);
  for (size_t i = 0; i < model.derived.size(); ++i) {
    const DerivedParameter& d = model.derived[i];
    rows.push_back({d.name, number_text(derived[i]), d.unit, "= " + d.value.text, d.doc});
  }
  out += "\nparameters (" + std::to_string(model.parameters.size()) +
         (model.derived.empty()
              ? ""
              : ", and " + std::to_string(model.derived.size()) + " derived from them") +
         "; SI units)\n" + table(rows, "  ");

  rows = {{"name", "mass [kg]", "inertia [kg m^2]", "assembly hint [rad]"}};
  for (const Body& body : model.bodies) {
    if (body.ground) {
      rows.push_back({body.name, "ground", "", ""});
      continue;
    }
    const auto [mass, inertia] = mass_properties(model, body, subs);
    // Forces and moments multiply masses by lengths and accelerations, and Newton-Euler squares
    // them: a magnitude past 1e100 overflows double precision (NaN) somewhere in the dynamics.
    if (!(std::abs(mass) <= kMaxMassProperty && std::abs(inertia) <= kMaxMassProperty))
      throw ModelError(body.loc, "body '" + body.name + "': mass " + number_text(mass) +
                                     " kg, inertia " + number_text(inertia) +
                                     " kg m^2: too large for the dynamics in double precision "
                                     "(at most 1e100)");
    rows.push_back({body.name, fixed(mass), fixed(inertia),
                    body.assembly_angle ? body.assembly_angle->text : "(none: 0)"});
  }
  out += "\nbodies (" + std::to_string(model.bodies.size()) + ": 1 ground, " +
         std::to_string(model.moving_body_count()) + " moving)\n" + table(rows, "  ");

  rows = {{"name", "type", "first", "second", "point"}};
  for (const Joint& j : model.joints)
    rows.push_back({j.name, to_string(j.type), model.bodies[static_cast<size_t>(j.first)].name,
                    model.bodies[static_cast<size_t>(j.second)].name, j.point});
  out += "\njoints (" + std::to_string(model.joints.size()) + ")\n" + table(rows, "  ");

  rows = {{"name", "kind", "joint", "value"}};
  for (const Driver& d : model.drivers)
    rows.push_back(
        {d.name, to_string(d.kind), model.joints[static_cast<size_t>(d.joint)].name, d.value.text});
  out += "\ndrivers (" + std::to_string(model.drivers.size()) + ")\n" + table(rows, "  ");

  if (!model.forces.empty()) {
    rows = {{"name", "type", "on"}};
    for (const ForceElement& f : model.forces) {
      const char* type = f.type == ForceType::spring_damper ? "spring_damper"
                         : f.type == ForceType::force       ? "force"
                                                            : "torque";
      std::string on = model.bodies[static_cast<size_t>(f.body_a)].name;
      if (!f.point_a.empty()) on += " at " + f.point_a;
      if (f.type == ForceType::spring_damper)
        on += " - " + model.bodies[static_cast<size_t>(f.body_b)].name + " at " + f.point_b;
      rows.push_back({f.name, type, on});
    }
    out += "\nloads (" + std::to_string(model.forces.size()) + ")\n" + table(rows, "  ");
  }

  const StructureReport s = analyze_structure(model);
  out += "\nstructure\n";
  out +=
      table({{"mobility (Gruebler)", "3 x " + std::to_string(s.moving_bodies) +
                                         " moving bodies - " + std::to_string(s.constraints) +
                                         " joint constraints = " + std::to_string(s.mobility) +
                                         " = drivers (" + std::to_string(s.drivers) + "): ok"},
             {"independent loops", std::to_string(s.loops) + " (" +
                                       std::to_string(model.joints.size()) + " joints - " +
                                       std::to_string(s.moving_bodies) + " moving bodies)"},
             {"Newton-Euler",
              std::to_string(s.ne_unknowns) + " unknowns (" + std::to_string(s.constraints) +
                  " reaction components + " + std::to_string(s.drivers) + " driver effort(s)), " +
                  std::to_string(s.ne_equations) + " equations (3 per moving " + "body)"}},
            "  ");
  std::cout << out << std::flush;
  out.clear();

  // The numeric solver assembles at t0: redundant constraints and hints that do not assemble
  // throw ModelError here, at the offending line.
  const double t0 = model.evaluate(model.step.t0, subs);
  numeric::ReferenceSolver solver(model, defaults);
  solver.assemble(t0);
  double worst = 0;
  std::string worst_body = "-";
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    if (model.bodies[b].ground || !model.bodies[b].assembly_angle) continue;
    const double hint = model.evaluate(*model.bodies[b].assembly_angle, subs);
    const double off = std::abs(wrap_angle(solver.poses()[b].th - hint));
    if (off >= worst) worst = off, worst_body = model.bodies[b].name;
  }
  out += "\nassembly at t0 = " + number_text(t0) + " s (numeric solver, default parameters)\n";
  out +=
      table({{"constraints", std::to_string(solver.constraint_count()) + " equations of rank " +
                                 std::to_string(solver.constraint_rank()) + ", " +
                                 std::to_string(solver.coordinate_count()) + " coordinates"},
             {"farthest from its hint", worst_body + ": " + fixed(worst, 3) + " rad (tolerance " +
                                            number_text(model.assembly_tolerance) + ")"}},
            "  ");

  const SolvePlan plan = make_solve_plan(model);
  const std::string reference = model.bodies[static_cast<size_t>(plan.reference)].name;
  out += "\nsolve plan\n  reference body frame: " + reference;
  out += plan.reference == model.ground
             ? " (the ground)\n"
             : " (shape solved in its frame, then placed on the ground body " +
                   model.bodies[static_cast<size_t>(model.ground)].name + ")\n";
  std::vector<std::string> notes;
  std::vector<gen::BranchChoice> branches;
  std::string derivation_problem, kernel_cost;
  if (plan.complete()) {
    try {
      // The kernel as its first use generates it, in memory: its notes, branches and size.
      const auto start = std::chrono::steady_clock::now();
      const gen::GenerateOptions options{model.file, "", ondemand::templates_dir(), false, ""};
      const std::vector<gen::EmittedFile> files =
          gen::emit_files(model, options, &notes, &branches);
      kernel_cost = ondemand::kernel_cost_report(
          files, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
          ondemand::current_compiled_kernel(model) != nullptr);
    } catch (const ModelError&) {
      throw;
    } catch (const std::exception& error) {
      derivation_problem = error.what();
    }
  }
  for (size_t g = 0; g < plan.groups.size(); ++g) {
    std::string line = "  " + std::to_string(g + 1) + ". " + describe(model, plan.groups[g]) +
                       "; frame " + reference +
                       (is_iterative(plan.groups[g].kind) ? "" : "; closed form");
    const std::string prefix = plan.groups[g].name + ":";
    for (const std::string& note : notes)
      if (note.rfind(prefix, 0) == 0) line += ";" + note.substr(prefix.size());
    out += line + "\n";
  }
  const std::vector<std::string> unpinned = gen::unpinned_branch_warnings(model, branches);
  for (const std::string& warning : unpinned) out += "  warning: " + warning + "\n";
  const auto iterative = std::count_if(plan.groups.begin(), plan.groups.end(),
                                       [](const SolveGroup& g) { return is_iterative(g.kind); });
  if (plan.complete() && iterative > 0) {
    out += "  closed form: no, " + std::to_string(iterative) +
           " iterative group(s) solved by Newton-Raphson in the kernel; every body located in " +
           std::to_string(plan.groups.size()) + " groups\n";
  } else if (plan.complete()) {
    out += "  closed form: yes, every body located in " + std::to_string(plan.groups.size()) +
           " groups\n";
  } else {
    std::string unsolved;
    for (int b : plan.unsolved) unsolved += " " + model.bodies[static_cast<size_t>(b)].name;
    out += "  closed form: no; no closed-form group reaches" + unsolved +
           " (sweep with --solver numeric)\n";
  }
  out += kernel_cost;
  std::cout << out;
  if (!derivation_problem.empty()) {
    std::cout << "  branches: not derived\n" << std::flush;
    std::cerr << path << ": warning: the generator cannot derive this model: " << derivation_problem
              << "\n";
  }
  std::cout << "\nok: " << path
            << (unpinned.empty() ? std::string()
                                 : " (" + std::to_string(unpinned.size()) +
                                       " branch(es) chosen without a hint: see the warnings)")
            << "\n";
  return 0;
}

// ---- mechgen info -------------------------------------------------------------------------------

const char* const kInfoHelp =
    R"(usage: mechgen info MODEL.yaml [--json]

Model metadata. With --json, JSON on stdout (README.md, "Command line"): name, gravity,
parameters with their default values (derived ones under derived_parameters), bodies (mass and inertia about the centre of mass at the defaults,
ground flag), named points, joints (name, type, first, second, point) and drivers (name, joint,
kind). Numbers are written with as many digits as it takes to read back the same double.
Without --json, a short text summary.
)";

int run_info(const Args& args) {
  if (is_spatial_description(args.single_positional("MODEL.yaml"))) return run_spatial_info(args);
  const Model model = load_model(args.single_positional("MODEL.yaml"));
  if (!args.has("--json")) {
    const StructureReport s = analyze_structure(model);
    std::cout << model.name << (model.description.empty() ? "" : ": " + model.description) << "\n"
              << table({{"parameters", std::to_string(model.parameters.size())},
                        {"bodies", std::to_string(model.bodies.size()) + " (1 ground)"},
                        {"points", std::to_string(model.named_points().size())},
                        {"joints", std::to_string(model.joints.size())},
                        {"drivers", std::to_string(model.drivers.size())},
                        {"loads", std::to_string(model.forces.size())},
                        {"loops", std::to_string(s.loops)},
                        {"sweep columns", std::to_string(column_names(model).size())}},
                       "  ");
    return 0;
  }

  std::cout << model_info_json(model);
  return 0;
}

// ---- mechgen generate ---------------------------------------------------------------------------

const char* const kGenerateHelp =
    R"(usage: mechgen generate MODEL.yaml [-o DIR] [--bake] [--templates DIR] [--support BODY]

Derives the model's kinematics and dynamics symbolically and writes its kernels.
  -o, --output DIR   where to write (default: generated/<name>/ under the current folder)
  --bake             bake the default parameter values into the kernel as constants
  --templates DIR    the templates to emit through (default: mechgen's own)
  --support BODY     spatial: the single-support kernel <name>_support_<BODY> (BODY welded to the
                     floor at its placement, virtual chains dropped, every real joint driven:
                     joint torques and the floor wrench; docs/spatial_kernels.md)
Parameters stay run-time values unless --bake is given. The kernel carries a fingerprint of the
description it was generated from. Sweeps need no generate step: `--solver generated` builds and
caches the kernel of a model that is not compiled into mechgen on its first use.
)";

int run_generate(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  g_current_file = path;
  // A spatial description generates through generator/spatial_emitter (gen::generate dispatches).
  const std::string support = args.get("--support", "");
  const std::string name = !is_spatial_description(path) ? load_model(path).name
                           : support.empty()
                               ? read_spatial_model(path).common.name
                               : weld_support(read_spatial_model(path), support).common.name;
  gen::GenerateOptions options;
  options.model_path = path;
  options.support = support;
  options.output_dir = args.get("--output", (std::filesystem::path("generated") / name).string());
  options.templates_dir = args.get("--templates", ondemand::templates_dir());
  options.bake = args.has("--bake");
  const auto start = std::chrono::steady_clock::now();
  const gen::GenerateResult result = gen::generate(options);
  std::cout << "generated '" << result.model << "' in " << fixed(seconds_since(start), 3) << " s\n";
  for (const std::string& note : result.notes) std::cout << "  " << note << "\n";
  for (const std::string& file : result.written) std::cout << "  wrote " << file << "\n";
  return 0;
}

// ---- mechgen plot -------------------------------------------------------------------------------

const char* const kPlotHelp =
    R"(usage: mechgen plot FILE.csv --x COLUMN --y COLUMN[,COLUMN...] --out FILE.svg
                   [--title TEXT] [--xlabel TEXT] [--ylabel TEXT] [--equal]
                   [--limit [max:|min:]VALUE[,LABEL]]...

Line plot of sweep columns against one column, as a self-contained SVG. --y may be repeated or
list several columns separated by commas. Axis labels and units are derived from the column names
unless given. --equal: one scale on both axes, so an x-y path (--x C.x --y C.y) keeps its shape.
More than 8 series are split into panels stacked one above the other (at most 8 each); a series
lying exactly over another is dashed so both show; a walk's CSV (mechgen walk: its support
column) plotted against t has each change of support foot as a dashed vertical line. Stress
columns ([Pa] in mechgen loads --over-time) are plotted in MPa, as loads prints them.
  --limit [max:|min:]VALUE[,LABEL]
                       a limit (a yield stress, the end of a stroke) in the plot's y units: a
                       dashed line; the side beyond it shaded above a max:, below a min:;
                       repeatable
)";

int run_plot(const Args& args) {
  const std::string path = args.single_positional("FILE.csv");
  if (!args.has("--x")) throw UsageError("missing --x COLUMN");
  if (!args.has("--y")) throw UsageError("missing --y COLUMN");
  if (!args.has("--out")) throw UsageError("missing --out FILE.svg");
  report::ColumnPlotOptions options;
  options.x = args.get("--x");
  options.y = comma_list(args, "--y");
  for (const std::string& limit : args.all("--limit")) {
    using Side = report::PlotSpec::Limit::Side;
    const Side side = limit.rfind("max:", 0) == 0   ? Side::max
                      : limit.rfind("min:", 0) == 0 ? Side::min
                                                    : Side::line;
    const size_t start = side == Side::line ? 0 : 4, comma = limit.find(',');
    options.limits.push_back({Args::parse_number(limit.substr(start, comma - start), "--limit"),
                              comma == std::string::npos ? "" : limit.substr(comma + 1), side});
  }
  options.title = args.get("--title");
  options.x_label = args.get("--xlabel");
  options.y_label = args.get("--ylabel");
  options.equal_scale = args.has("--equal");
  g_current_file = path;
  const report::CsvTable table = report::read_csv(path, report::Cells::any);  // gaps in a plot
  const std::string svg = report::render_svg(report::column_plot(table, options));
  const std::string out = args.get("--out");
  g_current_file = out;
  report::write_file_atomically(out, svg);
  std::cout << "plot: " << options.y.size() << " series, " << table.rows.size() << " samples -> "
            << out << "\n";
  return 0;
}

// ---- mechgen summary ----------------------------------------------------------------------------

const char* const kSummaryHelp =
    R"(usage: mechgen summary FILE.csv [--body NAME] [--model MODEL.yaml]

The figures of a sweep that size a motor and describe a gait:
  every driver <d> (columns <d>.effort, <d>.qd): peak effort (largest magnitude, signed, and when),
  RMS effort, mean power (effort x qd averaged over time), peak power, work over the run;
  one body's centre of mass or one named point (--body NAME): travel in x (end minus start) and
  height variation in y (max minus min, and relative to the mean when the mean height is larger);
  without --body, l13 when present, else the first body, and only when the run travels (net x
  travel above the height variation, as a walking hip): a mechanism turning in place gets none;
  the largest joint force magnitude |(fx, fy)| and its joint.
Averages are over time (trapezoidal rule in t). The driver kinds (hence the effort units: N m for
an angle, N for a length) come from --model, else from the model of models/ whose sweep columns
are exactly the table's, else from the columns (an angle driver's q is a difference of body
angles).
)";

// The model of the source tree whose sweep columns are exactly `header`, if exactly one is.
std::optional<Model> model_with_columns(const std::vector<std::string>& header) {
  std::optional<Model> found;
  std::error_code error;
  const std::filesystem::path models = std::filesystem::path(MECHGEN_SOURCE_DIR) / "models";
  for (const auto& entry : std::filesystem::directory_iterator(models, error)) {
    if (entry.path().extension() != ".yaml") continue;
    try {
      Model candidate = read_model(entry.path().string());
      if (column_names(candidate) != header) continue;
      if (found) return std::nullopt;  // ambiguous
      found = std::move(candidate);
    } catch (const std::exception&) {
      // A description that does not read is simply not a match.
    }
  }
  return found;
}

int run_summary(const Args& args) {
  const std::string path = args.single_positional("FILE.csv");
  SummaryOptions options;
  options.body = args.get("--body");
  std::optional<Model> model;
  if (args.has("--model")) {
    model = load_model(args.get("--model"));
    options.model = &*model;
  }
  g_current_file = path;
  const report::CsvTable table = report::read_csv(path);
  if (!model) {
    model = model_with_columns(table.header);
    options.model = model ? &*model : nullptr;
  }
  std::cout << format_summary(summarize(table, options));
  if (!args.has("--model") && model)
    std::cout << "(driver kinds from models/" << model->name
              << ".yaml, whose sweep columns are this table's)\n";
  return 0;
}

// ---- dispatch -----------------------------------------------------------------------------------

const std::vector<Command>& commands() {
  static const std::vector<Command> list{
      {"check",
       "validate a model; print its structure, assembly and solve plan",
       kCheckHelp,
       {},
       &run_check},
      {"info",
       "model metadata (--json: JSON on stdout)",
       kInfoHelp,
       {{"--json", "", false}},
       &run_info},
      {"generate",
       "write a model's kernels (default generated/<name>/)",
       kGenerateHelp,
       {{"--output", "-o", true},
        {"--bake", "", false},
        {"--templates", "", true},
        {"--support", "", true}},
       &run_generate},
      sweep_command(),
      {"plot",
       "SVG line plot of CSV columns",
       kPlotHelp,
       {{"--x", "", true},
        {"--y", "", true, true},
        {"--out", "-o", true},
        {"--title", "", true},
        {"--xlabel", "", true},
        {"--ylabel", "", true},
        {"--equal", "", false},
        {"--limit", "", true, true}},
       &run_plot},
      {"summary",
       "motor torque, power and gait figures of a sweep CSV",
       kSummaryHelp,
       {{"--body", "", true}, {"--model", "", true}},
       &run_summary},
      loads_command(),
      zmp_command(),
      grid_command(),
      merge_command(),
      size_motor_command(),
      walk_command(),
      draw_command(),
      workspace_command(),
      follow_command(),
      humanoid_gait_command(),
      view_command(),
      simulate_command(),
      import_command(),
      export_command(),
  };
  return list;
}

std::string main_help() {
  std::string text =
      "usage: mechgen COMMAND [ARGS...]    (mechgen COMMAND --help for each)\n\n"
      "Planar and spatial mechanisms (open chains, closed loops) from a YAML description to\n"
      "kinematics and dynamics kernels, sweeps, loads, drawings and 3D views.\n"
      "mechgen --version prints the version.\n\n"
      "commands:\n";
  std::vector<std::vector<std::string>> rows;
  for (const Command& c : commands()) rows.push_back({c.name, c.summary});
  text += table(rows, "  ");
  std::string models;
  for (const std::string& m : compiled_kernel_models()) models += " " + m;
  text += "\ncompiled kernels:" + (models.empty() ? std::string(" none") : models) + "\n";
  text +=
      "Any other model (or one edited since the build) gets its kernel generated, compiled and\n"
      "cached on first use; --cache DIR (any command) or MECHGEN_CACHE moves the cache from\n"
      "$XDG_CACHE_HOME/mechgen (~/.cache/mechgen). The compiler is MECHGEN_CXX, else CXX, else\n"
      "c++ (a program and its arguments, separated by spaces). A kernel whose header is over\n"
      "--max-kernel-mb MB (MECHGEN_MAX_KERNEL_MB, default 8; 0: none) is refused before the\n"
      "compiler starts, with its expected compile time and memory (also in `mechgen check`);\n"
      "the compiler is stopped after --compile-timeout S (MECHGEN_COMPILE_TIMEOUT, default 4x\n"
      "the expected time, at least 600 s) and limited to --compile-memory-mb MB of address\n"
      "space (MECHGEN_COMPILE_MEMORY_MB, default the machine's memory); 0 lifts either. See\n"
      "README.md, \"The kernel cache\".\n";
  return text;
}

// Prints an error that carries no source location as "FILE: error: MESSAGE".
void print_error(const std::string& message) {
  std::cerr << (g_current_file.empty() ? "mechgen" : g_current_file) << ": error: " << message
            << "\n";
}

// The options every command takes, anywhere on its line (--NAME VALUE or --NAME=VALUE), each
// passed on as an environment variable: the on-demand kernel cache and its compile budget
// (ondemand/kernel_budget.hpp).
struct GlobalOption {
  const char* name;
  const char* variable;
  const char* value;  // what the value is, for the error
};
constexpr GlobalOption kGlobalOptions[] = {
    {"--cache", "MECHGEN_CACHE", "a folder"},
    {"--max-kernel-mb", "MECHGEN_MAX_KERNEL_MB", "a size in MB"},
    {"--compile-timeout", "MECHGEN_COMPILE_TIMEOUT", "a number of seconds"},
    {"--compile-memory-mb", "MECHGEN_COMPILE_MEMORY_MB", "a size in MB"},
};

// Takes the global options out of `words`, setting their variables.
void take_global_options(std::vector<std::string>& words) {
  for (size_t i = 0; i < words.size(); ++i)
    for (const GlobalOption& option : kGlobalOptions) {
      const std::string name = option.name, joined = name + "=";
      std::string value;
      if (words[i] == name) {
        if (i + 1 == words.size()) throw UsageError(name + " needs " + option.value);
        value = words[i + 1];
        words.erase(words.begin() + static_cast<long>(i), words.begin() + static_cast<long>(i) + 2);
      } else if (words[i].rfind(joined, 0) == 0) {
        value = words[i].substr(joined.size());
        words.erase(words.begin() + static_cast<long>(i));
      } else {
        continue;
      }
      if (value.empty()) throw UsageError(name + " needs " + option.value);
      ::setenv(option.variable, value.c_str(), 1);
      --i;
      break;
    }
}

int dispatch(int argc, char** argv) {
  std::vector<std::string> words(argv + 1, argv + argc);
  try {
    take_global_options(words);
  } catch (const UsageError& error) {
    std::cerr << "mechgen: error: " << error.what() << "\n";
    return 1;
  }
  if (words.empty()) {
    std::cerr << main_help();
    return 1;
  }
  const std::string name = words.front();
  if (name == "--version" || name == "version") {
    std::cout << "mechgen " << MECHGEN_VERSION << "\n";
    return 0;
  }
  std::vector<std::string> names{"--help", "--version", "help", "version"};
  for (const Command& c : commands()) names.push_back(c.name);
  if (name == "--help" || name == "-h" || name == "help") {
    if (words.size() > 1) {
      for (const Command& c : commands())
        if (words[1] == c.name) {
          std::cout << c.help;
          return 0;
        }
      std::cerr << "mechgen: error: " << unknown_word("command", words[1], names)
                << " (see mechgen --help)\n";
      return 1;
    }
    std::cout << main_help();
    return 0;
  }
  for (const Command& c : commands()) {
    if (name != c.name) continue;
    try {
      const Args args({words.begin() + 1, words.end()}, c.options);
      if (args.help()) {
        std::cout << c.help;
        return 0;
      }
      // Every output path is checked before any computation (the files are written atomically).
      for (const char* option : {"--out", "--over-time", "--diagram-out", "--plot"})
        if (!(c.out_is_folder && std::string(option) == "--out"))
          for (const std::string& path : args.all(option)) report::check_output_path(path);
      return c.run(args);
    } catch (const UsageError& error) {
      std::cerr << "mechgen " << c.name << ": error: " << error.what() << " (see mechgen " << c.name
                << " --help)\n";
      return 1;
    }
  }
  std::cerr << "mechgen: error: "
            << unknown_word(name.rfind('-', 0) == 0 ? "option" : "command", name, names)
            << " (see mechgen --help)\n";
  return 1;
}

}  // namespace
}  // namespace mechgen::cli

int main(int argc, char** argv) {
  using mechgen::cli::print_error;
  try {
    return mechgen::cli::dispatch(argc, argv);
  } catch (const mechgen::ModelError& error) {
    std::cerr << error.what() << "\n";  // already "FILE:LINE:COL: error: MESSAGE"
  } catch (const mechgen::report::CsvError& error) {
    // "FILE:LINE: MESSAGE" or "FILE: MESSAGE" -> "FILE:LINE: error: MESSAGE"
    const std::string what = error.what();
    const auto split = what.find(": ");
    if (split == std::string::npos)
      print_error(what);
    else
      std::cerr << what.substr(0, split) << ": error: " << what.substr(split + 2) << "\n";
  } catch (const YAML::Exception& error) {
    std::cerr << mechgen::cli::g_current_file << ":" << error.mark.line + 1 << ":"
              << error.mark.column + 1 << ": error: " << error.msg << "\n";
  } catch (const std::exception& error) {  // GiNaC and the standard library throw these
    print_error(error.what());
  } catch (...) {
    print_error("unexpected internal error");
  }
  return 1;
}
