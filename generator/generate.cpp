#include "generate.hpp"

#include <filesystem>
#include <fstream>

#include "kernel_fingerprint.hpp"
#include "model/model.hpp"
#include "model/solve_plan.hpp"
#include "numeric/reference_solver.hpp"
#include "report/atomic_output.hpp"
#include "spatial_emitter.hpp"

namespace mechgen::gen {

std::string display_path(const std::string& path) {
  const std::string generic = std::filesystem::path(path).lexically_normal().generic_string();
  const auto at = generic.rfind("models/");
  return at == std::string::npos ? std::filesystem::path(generic).filename().string()
                                 : generic.substr(at);
}

namespace {
// The assembled configuration at t0 (default parameters): it picks each group's branch.
std::vector<BodyPose> assembled_pose(const Model& model) {
  const std::vector<double> defaults = model.default_parameters();
  numeric::ReferenceSolver solver(model, defaults);
  solver.assemble(model.evaluate(model.step.t0, model.substitutions(defaults)));
  std::vector<BodyPose> pose;
  for (const auto& p : solver.poses()) pose.push_back({p.x, p.y, p.th});
  return pose;
}

// The instants of the staged program's sample configurations: the assembly at t0 and four more
// spread inside the part of the step that the mechanism reaches from it (not on the step's end,
// where a model may sit on a dead point). A model may reach only part of its step (its kernel
// then says `unreachable` beyond), but the derivation's numeric checks need real configurations:
// the numeric solver walks the step on a fine grid until it fails.
std::vector<double> reachable_sample_times(const Model& model) {
  const std::vector<double> defaults = model.default_parameters();
  const GiNaC::exmap params = model.substitutions(defaults);
  const double t0 = model.evaluate(model.step.t0, params);
  const double t1 = model.evaluate(model.step.t1, params);
  constexpr int kGrid = 200;
  numeric::ReferenceSolver solver(model, defaults);
  solver.assemble(t0);
  std::vector<double> row;
  double reached = t0;
  for (int i = 1; i <= kGrid; ++i) {
    const double t = t0 + (t1 - t0) * i / kGrid;
    if (solver.solve(t, row) != numeric::Status::ok) break;
    reached = t;
  }
  std::vector<double> times{t0};
  for (int i = 0; i < 4; ++i) times.push_back(t0 + (reached - t0) * (0.13 + 0.74 * i / 3));
  return times;
}

// The staged program's sample configurations, shared by generate() and branch_notes().
StagedProgram make_program(const Model& model,
                           const std::vector<Derivation::DriverInputs>& inputs) {
  return StagedProgram(make_samples(model, inputs, reachable_sample_times(model)));
}
}  // namespace

std::vector<std::string> branch_notes(const Model& model, std::vector<BranchChoice>* branches) {
  const SolvePlan plan = make_solve_plan(model);
  const auto inputs = make_driver_inputs(model);
  StagedProgram program = make_program(model, inputs);
  Derivation d = derive(model, plan, assembled_pose(model), inputs, program);
  if (branches) *branches = std::move(d.branches);
  return d.notes;
}

GenerateResult generate(const GenerateOptions& options) {
  if (is_spatial_description(options.model_path)) return generate_spatial(options);
  if (!options.support.empty())
    throw std::runtime_error(options.model_path +
                             ": error: --support stands a spatial model (dimension: spatial) on "
                             "one of its bodies; this description is planar");
  return generate(read_model(options.model_path), options);
}

std::vector<EmittedFile> emit_files(const Model& model, const GenerateOptions& options,
                                    std::vector<std::string>* notes,
                                    std::vector<BranchChoice>* branches) {
  const SolvePlan plan = make_solve_plan(model);
  const auto inputs = make_driver_inputs(model);
  StagedProgram program = make_program(model, inputs);
  Derivation derivation = derive(model, plan, assembled_pose(model), inputs, program);

  EmitOptions emit;
  emit.templates_dir = options.templates_dir;
  emit.source = display_path(options.model_path);
  emit.command = "build/mechgen generate " + emit.source + (options.bake ? " --bake" : "");
  emit.bake = options.bake;
  emit.fingerprint = kernel_fingerprint(model, options.templates_dir, options.bake);
  std::vector<EmittedFile> files = emit_kernel(model, plan, derivation, program, emit);
  if (notes) *notes = derivation.notes;
  if (branches) *branches = std::move(derivation.branches);
  return files;
}

GenerateResult generate(const Model& model, const GenerateOptions& options) {
  GenerateResult result{model.name, {}, {}};
  const std::vector<EmittedFile> files = emit_files(model, options, &result.notes);
  std::filesystem::create_directories(options.output_dir);
  for (const EmittedFile& file : files) {
    const std::string path = (std::filesystem::path(options.output_dir) / file.name).string();
    report::write_file_atomically(path, file.text);  // never a half-written kernel
    result.written.push_back(path);
  }
  return result;
}

}  // namespace mechgen::gen
