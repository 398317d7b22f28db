// The spatial sweep through a generated kernel (spatial_kernel_sweep.hpp).
#include "spatial/spatial_kernel_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "model/symbolic_lock.hpp"
#include "numeric/mass_bias.hpp"
#include "numeric/time_expression.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"

namespace mechgen::spatial {

double spatial_sample_time(const SpatialSweepOptions& o, int i) {
  if (o.samples == 1) return o.t0;
  if (i == o.samples - 1) return o.t1;
  return o.t0 + (o.t1 - o.t0) * i / (o.samples - 1);
}

namespace {

// A joint coordinate's column: `<joint>.q`, or `<joint>.q1`... of a multi-axis joint.
bool is_coordinate_column(const std::string& name) {
  const std::string field = name.substr(name.rfind('.') + 1);
  return field == "q" ||
         (field.size() == 2 && field[0] == 'q' && field[1] >= '1' && field[1] <= '9');
}

// A model with table drivers: the kernel's own driver motion holds only their placeholders (the
// tables' first values), so each row goes through the kernel's driven entry with the motion
// computed here, (q, qd, qdd) per kernel input in the order of the generator's
// spatial_primary_inputs: the tables' splines and the other drivers' laws. Inactive (the kernel's
// own motion) for a model without tables.
class DrivenMotion {
 public:
  DrivenMotion(const SpatialModel& model, const std::vector<double>& parameters) {
    bool tables = false;
    for (const SpatialDriver& d : model.drivers) tables = tables || d.table.has_value();
    if (!tables) return;
    const std::lock_guard<std::recursive_mutex> hold(symbolic_lock());
    const GiNaC::exmap subs = model.common.substitutions(parameters);
    auto law = [&](const GiNaC::ex& q, const GiNaC::ex& qd, const GiNaC::ex& qdd) {
      for (const GiNaC::ex* e : {&q, &qd, &qdd}) {
        motion_.emplace_back(e->subs(subs), model.common.t);
        symbolic_ = symbolic_ || !motion_.back().compiled();
      }
    };
    for (const SpatialDriver& d : model.drivers) {
      if (!d.table) {
        law(d.value.ex, d.value_d, d.value_dd);
        continue;
      }
      for (int k = 0; k < 3; ++k) motion_.emplace_back(d.table->spline, k);
    }
    for (const PoseDriver& pd : model.pose_drivers)
      for (const PoseCoordinate& c : pd.coordinates)
        if (c.value) law(c.value->ex, c.value_d, c.value_dd);
    values_.resize(motion_.size());
  }
  bool active() const { return !motion_.empty(); }
  size_t inputs() const { return motion_.size() / 3; }
  const double* at(double t) {
    std::unique_lock<std::recursive_mutex> hold(symbolic_lock(), std::defer_lock);
    if (symbolic_) hold.lock();  // a law TimeExpression evaluates through GiNaC
    for (size_t k = 0; k < motion_.size(); ++k) values_[k] = motion_[k](t);
    return values_.data();
  }

 private:
  std::vector<numeric::TimeExpression> motion_;
  std::vector<double> values_;
  bool symbolic_ = false;
};

// One row of the kernel at time t: its own driver motion, or the driven one of a model with
// table drivers (DrivenMotion).
class KernelRows {
 public:
  KernelRows(const CompiledKernel& kernel, const SpatialSweepOptions& options, DrivenMotion& motion)
      : kernel_(kernel), parameters_(options.parameters.data()), motion_(motion) {}
  int operator()(double t, double* row, int* group) const {
    return motion_.active()
               ? kernel_.evaluate_driven_double(parameters_, t, motion_.at(t), row, group)
               : kernel_.evaluate_double(parameters_, t, row, group);
  }
  int mass_bias(double t, double* M, double* h, int* group) const {
    return kernel_.mass_bias_double(parameters_, t, motion_.active() ? motion_.at(t) : nullptr, M,
                                    h, group);
  }

 private:
  const CompiledKernel& kernel_;
  const double* parameters_;
  DrivenMotion& motion_;
};

// Seeds the kernel's warm start on this thread for one sweep, and restores its defaults after.
class StartSeed {
 public:
  StartSeed(const SpatialModel& model, const SpatialSweepOptions& options,
            const CompiledKernel& kernel, const KernelRows& rows)
      : kernel_(kernel), rows_(rows) {
    if (kernel.seed_start == nullptr || kernel.start_count == 0) return;
    // The numeric assembly reads the shared model's GiNaC expressions: one thread at a time
    // (Python threads, a grid's runs); the sweep's own kernel calls after it run unlocked.
    const std::lock_guard<std::recursive_mutex> hold(symbolic_lock());
    SpatialState state;
    std::optional<SpatialSolver> solver;
    try {
      solver.emplace(model, options.parameters);
      solver->solve(spatial_sample_time(options, 0), state);
    } catch (const std::exception&) {
      kernel.seed_start(nullptr);  // no assembly at t0: the kernel's own start and report
      return;
    }
    std::vector<double> values;
    for (int k = 0; k < kernel.start_count; ++k) values.push_back(state.q[kernel.start_columns[k]]);
    name_branch_changes(options, values);
    kernel.seed_start(values.data());
    refuse_another_start(model, options, *solver, state);
  }
  const std::string& warning() const { return warning_; }
  ~StartSeed() {
    if (kernel_.seed_start != nullptr) kernel_.seed_start(nullptr);
  }
  StartSeed(const StartSeed&) = delete;
  StartSeed& operator=(const StartSeed&) = delete;

 private:
  // The joints whose coordinates at t0 differ (mod 2 pi) between the kernel's own start (the
  // assembly at the default parameters) and the run's assembly: a --set moved those to another
  // branch, which the user should know of.
  void name_branch_changes(const SpatialSweepOptions& options, const std::vector<double>& values) {
    const auto n = static_cast<size_t>(kernel_.column_count);
    std::vector<double> own(n), run(n);
    int group = -1;
    const double t0 = spatial_sample_time(options, 0);
    kernel_.seed_start(nullptr);
    const int own_status = rows_(t0, own.data(), &group);
    kernel_.seed_start(values.data());
    const int run_status = rows_(t0, run.data(), &group);
    if (own_status != 0 || run_status != 0) return;
    std::string joints;
    for (size_t c = 0; c < n; ++c) {
      const std::string name = kernel_.column_names[c];
      const size_t dot = name.rfind('.');
      if (!is_coordinate_column(name) ||
          !(std::abs(std::remainder(own[c] - run[c], 2 * M_PI)) > 1e-6))
        continue;
      const std::string joint = "'" + name.substr(0, dot) + "'";
      if (joints.find(joint) == std::string::npos) joints += (joints.empty() ? "" : ", ") + joint;
    }
    if (!joints.empty())
      warning_ =
          "with these parameters the assembly at t0 is on another branch than the "
          "generated kernel's own start (the assembly at the default parameters) for " +
          joints + ": both solvers start from the numeric assembly and follow it";
  }

  // A closed form has one root fewer than the numeric solver's Newton-Raphson can reach (a
  // cylinder whose rod passes back through its barrel, at negative length: quadruped_leg_swing
  // with b < 0): seeded with that assembly, the kernel still lands elsewhere. Both would run and
  // disagree, so the kernel refuses, naming the joints and both values (issue 28).
  void refuse_another_start(const SpatialModel& model, const SpatialSweepOptions& options,
                            const SpatialSolver& solver, const SpatialState& state) const {
    std::vector<double> numeric;
    try {
      numeric = spatial_sweep_row(solver, spatial_driver_groups(solver), state,
                                  inverse_dynamics(solver, state));
    } catch (const std::exception&) {
      return;  // the sweep's first sample reports it
    }
    const auto n = static_cast<size_t>(kernel_.column_count);
    std::vector<double> generated(n);
    int group = -1;
    if (numeric.size() < n || rows_(spatial_sample_time(options, 0), generated.data(), &group) != 0)
      return;
    std::string joints;
    for (size_t c = 0; c < n; ++c) {
      const std::string name = kernel_.column_names[c];
      if (!is_coordinate_column(name) ||
          !(std::abs(generated[c] - numeric[c]) > 1e-6 * std::max(1.0, std::abs(numeric[c]))))
        continue;
      char values[96];
      std::snprintf(values, sizeof values, " (%.6g against %.6g)", generated[c], numeric[c]);
      joints += (joints.empty() ? "'" : ", '") + name + "'" + values;
    }
    if (joints.empty()) return;
    kernel_.seed_start(nullptr);  // the destructor of an unfinished constructor does not run
    throw ModelError(
        {model.common.file, 0, 0},
        "with these parameters the generated kernel cannot start on the numeric solver's "
        "assembly at t0: its closed forms reach " +
            joints +
            ": the assembly is on a branch the kernel does not have (e.g. a cylinder at "
            "negative length); use --solver numeric, or assembly hints on another branch");
  }

  const CompiledKernel& kernel_;
  const KernelRows& rows_;
  std::string warning_;
};

}  // namespace

SpatialSweepResult run_spatial_kernel_sweep(const SpatialModel& model,
                                            const SpatialSweepOptions& options,
                                            const CompiledKernel& kernel) {
  SpatialSweepResult result;
  result.columns = spatial_column_names(model);
  const SourceLoc file{model.common.file, 0, 0};
  bool same = static_cast<int>(result.columns.size()) == kernel.column_count &&
              static_cast<int>(options.parameters.size()) == kernel.parameter_count;
  for (int c = 0; same && c < kernel.column_count; ++c)
    same = result.columns[static_cast<size_t>(c)] == kernel.column_names[c];
  if (!same)
    throw ModelError(file, "the generated kernel of '" + model.common.name +
                               "' does not match the description (rebuild to regenerate it)");
  // The kernel's closed forms take the root nearest its warm start: started from the numeric
  // solver's assembly at this run's parameters and t0, both solvers take the same branch there
  // and then follow the motion (issue 28). Without an assembly the kernel starts from its
  // defaults (the assembly at the default parameters) and reports what it finds.
  check_table_times(model, options);
  DrivenMotion motion(model, options.parameters);
  if (motion.active() && (kernel.evaluate_driven_double == nullptr ||
                          kernel.driver_count != static_cast<int>(motion.inputs())))
    throw ModelError(file, "the generated kernel of '" + model.common.name +
                               "' has no driven entry for its table drivers (rebuild to "
                               "regenerate it)");
  const KernelRows rows(kernel, options, motion);
  StartSeed seed(model, options, kernel, rows);
  if (!seed.warning().empty()) result.warnings.push_back(seed.warning());
  bool newton_closure = false;
  for (int g = 0; g < kernel.group_count; ++g)
    newton_closure = newton_closure || std::string(kernel.group_names[g]) == "closure";
  // --mass-matrix: the kernel's mass_bias entry at each row's motion, in the drivers' column
  // order (their `<a>.effort` columns, which is the kernel's coordinate order).
  std::vector<std::string> drivers;
  const std::string effort = ".effort";
  for (const std::string& c : result.columns)
    if (c.size() > effort.size() && c.compare(c.size() - effort.size(), effort.size(), effort) == 0)
      drivers.push_back(c.substr(0, c.size() - effort.size()));
  const size_t n = drivers.size();
  if (options.mass_matrix) {
    if (static_cast<int>(n) != kernel.driver_count || kernel.mass_bias_double == nullptr)
      throw ModelError(file, "the generated kernel of '" + model.common.name +
                                 "' has no mass matrix of its drivers (rebuild to regenerate it)");
    for (std::string& c : numeric::mass_bias_columns(drivers)) result.columns.push_back(c);
  }
  std::vector<double> M(n * n), h(n);
  // Samples farther apart than the model's own step: the kernel is also called between them, at
  // most that step apart, so that its warm start follows the motion as the numeric solver's
  // halved steps do (3 samples over quadruped_leg's step took the other root at t1 before).
  SpatialSweepOptions own;
  {
    const std::lock_guard<std::recursive_mutex> hold(symbolic_lock());  // the step's expressions
    own = default_spatial_sweep(model, options.parameters);
  }
  const double own_step =
      own.samples > 1 ? std::abs(own.t1 - own.t0) / (own.samples - 1) : std::abs(own.t1 - own.t0);
  std::vector<double> between(static_cast<size_t>(kernel.column_count));
  for (int i = 0; i < options.samples; ++i) {
    double t = spatial_sample_time(options, i);
    int status = 0, group = -1;
    bool between_samples = false;
    if (i > 0 && own_step > 0) {
      // A call between the samples that fails is reported at its own time: the kernel's next
      // call would start afresh from the assembly at t0, not from the motion followed so far.
      const double from = spatial_sample_time(options, i - 1);
      const int steps = static_cast<int>(std::ceil(std::abs(t - from) / own_step - 1e-9));
      for (int k = 1; k < steps && status == 0; ++k) {
        const double between_t = from + (t - from) * k / steps;
        status = rows(between_t, between.data(), &group);
        if (status != 0) t = between_t, between_samples = true;
      }
    }
    std::vector<double> row(static_cast<size_t>(kernel.column_count));
    if (status == 0) status = rows(t, row.data(), &group);
    if (status == 0 && options.mass_matrix) {
      status = rows.mass_bias(t, M.data(), h.data(), &group);
      for (size_t a = 0; a < n; ++a)
        for (size_t b = a; b < n; ++b) row.push_back(M[a * n + b]);
      for (size_t a = 0; a < n; ++a) row.push_back(h[a]);
    }
    if (status != 0) {
      // As the planar sweep words it (runtime/sweep/sweep.cpp): sample, time, status, group.
      char time[32];
      std::snprintf(time, sizeof time, "%.17g", t);
      std::ostringstream m;
      m << "generated kernel: " << (between_samples ? "on the way to sample " : "sample ") << i + 1
        << " of " << options.samples << ", t = " << time << ": "
        << (status == 1   ? "unreachable"
            : status == 2 ? "singular"
                          : "non-finite result");
      if (group >= 0 && group < kernel.group_count) m << " in group " << kernel.group_names[group];
      m << (status == 1   ? " (the mechanism cannot assemble there with these parameters)"
            : status == 3 ? " (a singular geometry divides by zero, e.g. a length or offset set "
                            "to 0 or two axes made parallel; or the parameters or the motion are "
                            "too large for double precision)"
            : group >= 0 && group < kernel.group_count &&
                    std::string(kernel.group_names[group]) == "closure"
                ? " (the configuration is singular there, or the elimination order the kernel "
                  "fixed at generation loses its precision there; --solver numeric pivots at run "
                  "time)"
                : " (the configuration is singular there)");
      // A Newton closure starts from the previous call: calls far apart fail there too, but the
      // kernel is already called at least every model step, so once the samples are several
      // times denser than that, more samples do not help; what remains is the closure's rows
      // and elimination order, fixed at generation over the step and the drivers' ranges.
      const double spacing = options.samples > 1
                                 ? std::abs(options.t1 - options.t0) / (options.samples - 1)
                                 : own_step;
      const bool dense = spacing <= own_step / 4;
      if (status != 2 && i > 0 && newton_closure && !dense)
        m << "; or the samples are too far apart for the closure's Newton steps from the "
             "previous one: use more samples, or --solver numeric (it halves its steps)";
      else if (i > 0 && newton_closure && dense)
        m << "; the samples are already dense, so more will not help: if --solver numeric "
             "runs here, the closure rows or elimination order the kernel fixed at generation "
             "(over the model's step and its drivers' `range:`) lose rank here: give the "
             "drivers a `range:` that covers this motion and regenerate, or use --solver "
             "numeric";
      throw ModelError(file, m.str());
    }
    result.rows.push_back(std::move(row));
  }
  return result;
}

}  // namespace mechgen::spatial
