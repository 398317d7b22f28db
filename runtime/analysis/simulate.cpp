#include "analysis/simulate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <tuple>

#include "model/columns.hpp"
#include "numeric/reference_solver.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_mass_matrix.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"

namespace mechgen::sim {

using Eigen::VectorXd;

namespace {

double to_double(const GiNaC::ex& e) {
  const GiNaC::ex v = GiNaC::evalf(e);
  if (!GiNaC::is_a<GiNaC::numeric>(v) || !GiNaC::ex_to<GiNaC::numeric>(v).is_real())
    return std::nan("");
  return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

// Sub-steps that take the drivers from where the model's own motion assembles them (its step's
// t0, where the assembly hints hold) to a simulation's initial state: at most 0.02 (rad or m)
// per driver per piece.
int walk_pieces(const VectorXd& from, const VectorXd& to) {
  const double span = from.size() ? (to - from).cwiseAbs().maxCoeff() : 0;
  return std::max(1, static_cast<int>(std::ceil(span / 0.02)));
}

// A plant on a numeric solver, with what a kernel plant (below) takes from it: placing the
// solver without M and h (for the loads' power and a closed chain's first assembly), the body
// weights for the potential energy, the warm start of a spatial closed chain.
class NumericPlant : public Plant {
 public:
  virtual bool follow(double t, const VectorXd& q, const VectorXd& qd, std::string& why) = 0;
  // m g per massive body, with the name of its centre of mass' position columns (`<body>.x`...).
  virtual std::vector<std::pair<std::string, Eigen::Vector3d>> weights() const = 0;
  // After follow(): the solver's coordinates at the kernel's warm-start columns.
  virtual std::vector<double> start_values(const CompiledKernel&) const { return {}; }
};

class PlanarPlant : public NumericPlant {
 public:
  PlanarPlant(const Model& model, const std::vector<double>& parameters)
      : model_(model),
        subs_(model.substitutions(parameters)),
        solver_(model, parameters),
        columns_(column_names(model)),
        t0_(model.evaluate(model.step.t0, subs_)) {
    for (const Driver& d : model.drivers) drivers_.push_back(d.name);
  }
  const std::vector<std::string>& drivers() const override { return drivers_; }
  const std::vector<std::string>& columns() const override { return columns_; }

  void motion(double t, VectorXd& q, VectorXd& qd, VectorXd* qdd) const override {
    GiNaC::exmap at = subs_;
    at[model_.t] = t;
    const auto n = static_cast<Eigen::Index>(model_.drivers.size());
    q.resize(n);
    qd.resize(n);
    if (qdd) qdd->resize(n);
    for (Eigen::Index d = 0; d < n; ++d) {
      const Driver& dr = model_.drivers[static_cast<size_t>(d)];
      q[d] = to_double(dr.value.ex.subs(at));
      qd[d] = to_double(dr.value_d.subs(at));
      if (qdd) (*qdd)[d] = to_double(dr.value_dd.subs(at));
    }
  }

  bool place(double t, const VectorXd& q, const VectorXd& qd, numeric::MassBias& mb,
             std::string& why) override {
    if (!solve(t, q, qd, VectorXd::Zero(q.size()), why)) return false;
    if (!solver_.mass_matrix_bias(t, mb.M, mb.h)) {
      why = "Newton-Euler system singular (mass matrix)";
      return false;
    }
    return true;
  }

  double load_power(double t) const override { return solver_.applied_power(t); }
  bool follow(double t, const VectorXd& q, const VectorXd& qd, std::string& why) override {
    return solve(t, q, qd, VectorXd::Zero(q.size()), why);
  }
  std::vector<std::pair<std::string, Eigen::Vector3d>> weights() const override {
    const Eigen::Vector3d g(model_.evaluate(model_.gravity.x, subs_),
                            model_.evaluate(model_.gravity.y, subs_), 0);
    std::vector<std::pair<std::string, Eigen::Vector3d>> out;
    for (const Body& body : model_.bodies)
      if (!body.ground && body.mass.source != MassProperties::Source::none)
        out.emplace_back(body.name, model_.evaluate(body.mass.mass, subs_) * g);
    return out;
  }
  void restart() override {
    assembled_ = false;
    solver_.clear_driver_motion();
  }

  bool row(double t, const VectorXd& q, const VectorXd& qd, const VectorXd& qdd,
           std::vector<double>& out, double& kinetic, double& potential,
           std::string& why) override {
    if (!solve(t, q, qd, qdd, why, &out)) return false;
    kinetic = solver_.kinetic_energy();
    potential = solver_.potential_energy();
    return true;
  }

 private:
  bool solve(double t, const VectorXd& q, const VectorXd& qd, const VectorXd& qdd, std::string& why,
             std::vector<double>* out = nullptr) {
    if (!assembled_) {  // at the model's own configuration, then the drivers walked to q
      assembled_ = true;
      VectorXd q0, qd0;
      motion(t0_, q0, qd0, nullptr);
      const VectorXd zero = VectorXd::Zero(q.size());
      solver_.set_driver_motion(q0, zero, zero);
      solver_.assemble(t0_);
      const int pieces = walk_pieces(q0, q);
      for (int k = 1; k < pieces; ++k)
        if (!solve(t0_, q0 + (q - q0) * k / pieces, zero, zero, why)) return false;
    }
    solver_.set_driver_motion(q, qd, qdd);
    const numeric::Status status = solver_.solve(t, out ? *out : row_);
    if (status != numeric::Status::ok) {
      why = std::string("numeric solver: ") + numeric::to_string(status);
      return false;
    }
    return true;
  }

  const Model& model_;
  GiNaC::exmap subs_;
  numeric::ReferenceSolver solver_;
  std::vector<std::string> drivers_, columns_;
  std::vector<double> row_;
  double t0_ = 0;
  bool assembled_ = false;
};

class SpatialPlant : public NumericPlant {
 public:
  SpatialPlant(const SpatialModel& model, const std::vector<double>& parameters)
      : solver_(model, parameters),
        groups_(spatial::spatial_driver_groups(solver_)),
        columns_(spatial::spatial_column_names(model)),
        t0_(spatial::default_spatial_sweep(model, parameters).t0) {
    for (const spatial::SpatialDriverGroup& g : groups_) drivers_.push_back(g.name);
  }
  const std::vector<std::string>& drivers() const override { return drivers_; }
  const std::vector<std::string>& columns() const override { return columns_; }

  void motion(double t, VectorXd& q, VectorXd& qd, VectorXd* qdd) const override {
    VectorXd qp, qpd, qpdd;
    solver_.primary_motion(t, qp, qpd, qpdd);
    q.resize(qp.size());
    qd.resize(qp.size());
    if (qdd) qdd->resize(qp.size());
    for (size_t g = 0; g < groups_.size(); ++g) {
      const auto i = static_cast<Eigen::Index>(g);
      q[i] = qp[groups_[g].primary] + groups_[g].offset;
      qd[i] = qpd[groups_[g].primary];
      if (qdd) (*qdd)[i] = qpdd[groups_[g].primary];
    }
  }

  bool place(double t, const VectorXd& q, const VectorXd& qd, numeric::MassBias& mb,
             std::string& why) override {
    if (!solve(t, q, qd, VectorXd::Zero(q.size()), why)) return false;
    try {
      const numeric::MassBias primary = spatial::mass_matrix_bias(solver_, state_, to_primary(qd));
      const auto n = static_cast<Eigen::Index>(groups_.size());
      mb.M.resize(n, n);
      mb.h.resize(n);
      for (Eigen::Index a = 0; a < n; ++a) {
        mb.h[a] = primary.h[groups_[static_cast<size_t>(a)].primary];
        for (Eigen::Index b = 0; b < n; ++b)
          mb.M(a, b) = primary.M(groups_[static_cast<size_t>(a)].primary,
                                 groups_[static_cast<size_t>(b)].primary);
      }
    } catch (const std::exception& error) {
      why = error.what();
      return false;
    }
    return true;
  }

  double load_power(double) const override { return solver_.applied_power(state_); }
  void restart() override { state_.assembled = false; }
  bool follow(double t, const VectorXd& q, const VectorXd& qd, std::string& why) override {
    return solve(t, q, qd, VectorXd::Zero(q.size()), why);
  }
  std::vector<std::pair<std::string, Eigen::Vector3d>> weights() const override {
    const SpatialModel& model = solver_.model();
    const spatial::SpatialInstance& in = solver_.instance();
    const Eigen::Vector3d g(in.gravity[0], in.gravity[1], in.gravity[2]);
    std::vector<std::pair<std::string, Eigen::Vector3d>> out;
    for (size_t b = 0; b < model.bodies.size(); ++b)
      if (!model.bodies[b].ground && !model.bodies[b].is_virtual)
        out.emplace_back(model.bodies[b].name, in.mass[b] * g);
    return out;
  }
  std::vector<double> start_values(const CompiledKernel& kernel) const override {
    std::vector<double> values;
    for (int k = 0; k < kernel.start_count; ++k)
      values.push_back(state_.q[kernel.start_columns[k]]);
    return values;
  }

  bool row(double t, const VectorXd& q, const VectorXd& qd, const VectorXd& qdd,
           std::vector<double>& out, double& kinetic, double& potential,
           std::string& why) override {
    if (!solve(t, q, qd, qdd, why)) return false;
    try {
      out = spatial::spatial_sweep_row(solver_, groups_, state_,
                                       spatial::inverse_dynamics(solver_, state_));
    } catch (const std::exception& error) {
      why = error.what();
      return false;
    }
    const spatial::Energy e = spatial::energy(solver_, state_);
    kinetic = e.kinetic;
    potential = e.potential;
    return true;
  }

 private:
  // Group order (sweep columns, with the pose coordinates' offsets) -> graph().primary order.
  VectorXd to_primary(const VectorXd& v, bool offsets = false) const {
    VectorXd out(v.size());
    for (size_t g = 0; g < groups_.size(); ++g)
      out[groups_[g].primary] = v[static_cast<Eigen::Index>(g)] - (offsets ? groups_[g].offset : 0);
    return out;
  }
  bool solve(double t, const VectorXd& q, const VectorXd& qd, const VectorXd& qdd,
             std::string& why) {
    if (!state_.assembled) {  // at the model's own configuration, then the drivers walked to q
      VectorXd q0, qd0;
      motion(t0_, q0, qd0, nullptr);
      const VectorXd zero = VectorXd::Zero(q.size());
      const int pieces = walk_pieces(q0, q);
      for (int k = 0; k < pieces; ++k)
        if (!solve_at(t0_, q0 + (q - q0) * k / pieces, zero, zero, why)) return false;
    }
    return solve_at(t, q, qd, qdd, why);
  }
  bool solve_at(double t, const VectorXd& q, const VectorXd& qd, const VectorXd& qdd,
                std::string& why) {
    try {
      solver_.solve(t, to_primary(q, true), to_primary(qd), to_primary(qdd), state_);
    } catch (const std::exception& error) {
      why = std::string("spatial solver: ") + error.what();
      return false;
    }
    return true;
  }

  spatial::SpatialSolver solver_;
  std::vector<spatial::SpatialDriverGroup> groups_;
  std::vector<std::string> drivers_, columns_;
  spatial::SpatialState state_;
  double t0_ = 0;
};

// The drivers free through a generated kernel: M and h from its mass_bias entry at every stage,
// the rows from its driven evaluation (the sweep's columns), the kinetic energy 1/2 qd^T M qd
// (tested equal to the bodies' sum), the potential from the rows' centre-of-mass columns. The
// numeric plant beside it places its solver only where the kernel has nothing to say: a spatial
// closed chain's first assembly (and after restart()), whose coordinates seed the kernel's warm
// start so that its closed forms take the numeric solver's branch and then follow the state
// (every stage first evaluates the row, which carries the warm start: the mass_bias entry only
// copies it), and the applied loads' power of a model that has loads.
class KernelPlant : public Plant {
 public:
  KernelPlant(std::unique_ptr<NumericPlant> numeric, const CompiledKernel& kernel,
              std::vector<double> parameters, bool loads)
      : numeric_(std::move(numeric)),
        kernel_(kernel),
        parameters_(std::move(parameters)),
        loads_(loads),
        closed_(kernel.seed_start != nullptr && kernel.start_count > 0) {
    const std::vector<std::string>& columns = numeric_->columns();
    const std::vector<std::string>& drivers = numeric_->drivers();
    // The kernel's coordinates are its drivers in the order of their effort columns.
    std::vector<std::string> efforts;
    bool same = static_cast<int>(columns.size()) == kernel.column_count &&
                static_cast<int>(parameters_.size()) == kernel.parameter_count &&
                static_cast<int>(drivers.size()) == kernel.driver_count &&
                kernel.mass_bias_double != nullptr && kernel.evaluate_driven_double != nullptr;
    for (int c = 0; same && c < kernel.column_count; ++c) {
      const std::string name = kernel.column_names[c];
      same = columns[static_cast<size_t>(c)] == name;
      if (name.ends_with(".effort")) efforts.push_back(name.substr(0, name.size() - 7));
    }
    if (!same || efforts != drivers)
      throw std::runtime_error(std::string("the generated kernel of '") + kernel.model +
                               "' does not match the description (rebuild to regenerate it)");
    for (const auto& [body, weight] : numeric_->weights()) {
      Weight w{{}, weight};
      for (int a = 0; a < 3; ++a) {
        const std::string name = body + "." + "xyz"[a];
        const auto it = std::find(columns.begin(), columns.end(), name);
        w.column[a] = it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
      }
      weights_.push_back(w);
    }
    const size_t n = drivers.size();
    M_.resize(n * n);
    h_.resize(n);
    drivers_in_.resize(3 * n);
    row_.resize(columns.size());
  }
  ~KernelPlant() override {
    if (seeded_) kernel_.seed_start(nullptr);  // the kernel's own start for whoever comes next
  }
  KernelPlant(const KernelPlant&) = delete;
  KernelPlant& operator=(const KernelPlant&) = delete;

  const std::vector<std::string>& drivers() const override { return numeric_->drivers(); }
  const std::vector<std::string>& columns() const override { return numeric_->columns(); }
  void motion(double t, VectorXd& q, VectorXd& qd, VectorXd* qdd) const override {
    numeric_->motion(t, q, qd, qdd);
  }

  bool place(double t, const VectorXd& q, const VectorXd& qd, numeric::MassBias& mb,
             std::string& why) override {
    if (!mass_bias(t, q, qd, why)) return false;
    const auto n = q.size();
    mb.M = Eigen::Map<const Eigen::MatrixXd>(M_.data(), n, n);  // symmetric: layout immaterial
    mb.h = Eigen::Map<const VectorXd>(h_.data(), n);
    if (loads_ && !numeric_->follow(t, q, qd, why)) return false;
    return true;
  }

  double load_power(double t) const override { return loads_ ? numeric_->load_power(t) : 0; }

  bool row(double t, const VectorXd& q, const VectorXd& qd, const VectorXd& qdd,
           std::vector<double>& out, double& kinetic, double& potential,
           std::string& why) override {
    // M at (t, q, qd): the last placement's when it was there (simulate places before a row).
    if (!(placed_ && t == at_t_ && q == at_q_ && qd == at_qd_) && !mass_bias(t, q, qd, why))
      return false;
    const auto n = q.size();
    kinetic = 0.5 * qd.dot(Eigen::Map<const Eigen::MatrixXd>(M_.data(), n, n) * qd);
    out.resize(row_.size());
    if (!evaluate(t, q, qd, &qdd, out.data(), why)) return false;
    potential = 0;
    for (const Weight& w : weights_)
      for (int a = 0; a < 3; ++a)
        if (w.column[a] >= 0) potential -= w.mg[a] * out[static_cast<size_t>(w.column[a])];
    return true;
  }

  void restart() override {
    numeric_->restart();
    if (seeded_) kernel_.seed_start(nullptr);
    seeded_ = false;
    placed_ = false;
  }

 private:
  struct Weight {
    int column[3];       // the centre of mass' x, y, z columns (-1: none, planar z)
    Eigen::Vector3d mg;  // mass times gravity
  };

  // The kernel's drivers input (q, qd, qdd per driver); a closed chain's warm start seeded from
  // the numeric solver's assembly at the first call (and after restart()).
  bool prepare(double t, const VectorXd& q, const VectorXd& qd, const VectorXd* qdd,
               std::string& why) {
    for (Eigen::Index d = 0; d < q.size(); ++d) {
      drivers_in_[static_cast<size_t>(3 * d)] = q[d];
      drivers_in_[static_cast<size_t>(3 * d + 1)] = qd[d];
      drivers_in_[static_cast<size_t>(3 * d + 2)] = qdd ? (*qdd)[d] : 0;
    }
    if (!closed_ || seeded_) return true;
    if (!numeric_->follow(t, q, qd, why)) return false;
    const std::vector<double> values = numeric_->start_values(kernel_);
    kernel_.seed_start(values.data());
    seeded_ = true;
    return true;
  }
  bool evaluate(double t, const VectorXd& q, const VectorXd& qd, const VectorXd* qdd, double* out,
                std::string& why) {
    if (!prepare(t, q, qd, qdd, why)) return false;
    int group = -1;
    return check(
        kernel_.evaluate_driven_double(parameters_.data(), t, drivers_in_.data(), out, &group),
        group, why);
  }
  bool mass_bias(double t, const VectorXd& q, const VectorXd& qd, std::string& why) {
    placed_ = false;
    // A closed chain: the row first, which moves the warm start to this state.
    if (closed_ && !evaluate(t, q, qd, nullptr, row_.data(), why)) return false;
    if (!prepare(t, q, qd, nullptr, why)) return false;
    int group = -1;
    if (!check(kernel_.mass_bias_double(parameters_.data(), t, drivers_in_.data(), M_.data(),
                                        h_.data(), &group),
               group, why))
      return false;
    placed_ = true;
    at_t_ = t;
    at_q_ = q;
    at_qd_ = qd;
    return true;
  }
  bool check(int status, int group, std::string& why) const {
    if (status == 0) return true;
    why = std::string("generated kernel: ") +
          (status == 1   ? "unreachable"
           : status == 2 ? "singular (or a mass matrix not positive definite)"
                         : "non-finite result");
    if (group >= 0 && group < kernel_.group_count)
      why += std::string(" in group ") + kernel_.group_names[group];
    return false;
  }

  std::unique_ptr<NumericPlant> numeric_;
  const CompiledKernel& kernel_;
  std::vector<double> parameters_;
  bool loads_, closed_, seeded_ = false, placed_ = false;
  std::vector<Weight> weights_;
  std::vector<double> M_, h_, drivers_in_, row_;
  double at_t_ = 0;
  VectorXd at_q_, at_qd_;
};

// One driver's effort law with the parameters substituted: a function of t, q, qd.
struct Law {
  GiNaC::ex ex;
  bool given = false;
};

EffortFunction laws_function(std::vector<Law> laws, const Model& common) {
  const GiNaC::symbol t = common.t, q = common.driver_q, qd = common.driver_qd;
  return [laws = std::move(laws), t, q, qd](double time, const VectorXd& qv, const VectorXd& qdv,
                                            VectorXd& effort) {
    effort.setZero(static_cast<Eigen::Index>(laws.size()));
    for (size_t d = 0; d < laws.size(); ++d) {
      if (!laws[d].given) continue;
      const auto i = static_cast<Eigen::Index>(d);
      effort[i] = to_double(laws[d].ex.subs(GiNaC::lst{t == time, q == qv[i], qd == qdv[i]}));
    }
  };
}

bool named(const std::vector<std::string>& names, const std::string& name) {
  for (const std::string& n : names)
    if (n == name) return true;
  return false;
}

Law law_of(const GiNaC::exmap& subs, const std::string& name, const std::optional<Expr>& effort,
           const SourceLoc& loc, const std::vector<std::string>& free) {
  if (effort) return {effort->ex.subs(subs), true};
  if (named(free, name)) return {};
  const bool pose = name.find('.') != std::string::npos;  // a pose driver's coordinate
  throw ModelError(loc, "driver '" + name + "' has no effort law: " +
                            (pose ? "a pose driver's coordinates take none; "
                                  : "give it `effort:` (a law of t, q, qd), ") +
                            "drive it by a motor (--motor NAME --catalogue CSV) or track the "
                            "model's motion (--track)");
}

std::string time_text(double t) {
  char text[64];
  std::snprintf(text, sizeof text, "t = %.9g s", t);
  return text;
}

}  // namespace

std::unique_ptr<Plant> planar_plant(const Model& model, const std::vector<double>& parameters) {
  return std::make_unique<PlanarPlant>(model, parameters);
}

std::unique_ptr<Plant> spatial_plant(const SpatialModel& model,
                                     const std::vector<double>& parameters) {
  return std::make_unique<SpatialPlant>(model, parameters);
}

std::unique_ptr<Plant> planar_kernel_plant(const Model& model,
                                           const std::vector<double>& parameters,
                                           const CompiledKernel& kernel) {
  return std::make_unique<KernelPlant>(std::make_unique<PlanarPlant>(model, parameters), kernel,
                                       parameters, !model.forces.empty());
}

std::unique_ptr<Plant> spatial_kernel_plant(const SpatialModel& model,
                                            const std::vector<double>& parameters,
                                            const CompiledKernel& kernel) {
  return std::make_unique<KernelPlant>(std::make_unique<SpatialPlant>(model, parameters), kernel,
                                       parameters, !model.loads.empty());
}

EffortFunction model_effort_laws(const Model& model, const std::vector<double>& parameters,
                                 const std::vector<std::string>& free) {
  const GiNaC::exmap subs = model.substitutions(parameters);
  std::vector<Law> laws;
  for (const Driver& d : model.drivers) laws.push_back(law_of(subs, d.name, d.effort, d.loc, free));
  return laws_function(std::move(laws), model);
}

EffortFunction model_effort_laws(const SpatialModel& model, const std::vector<double>& parameters,
                                 const std::vector<std::string>& free) {
  const GiNaC::exmap subs = model.common.substitutions(parameters);
  std::vector<Law> laws;
  for (const SpatialDriver& d : model.drivers)
    laws.push_back(law_of(subs, d.name, d.effort, d.loc, free));
  for (const PoseDriver& pd : model.pose_drivers)
    for (const PoseCoordinate& c : pd.coordinates)
      if (c.value) laws.push_back(law_of(subs, pd.name + "." + c.name, std::nullopt, pd.loc, free));
  return laws_function(std::move(laws), model.common);
}

double MotorDrive::output_torque(double qd) const {
  const double speed = direction * qd * motor.gear_ratio;  // motor shaft, rad/s
  // At a fraction V of the rated voltage both the stall torque and the no-load speed scale by V.
  double torque = motor.peak_torque * (voltage - speed / motor.no_load_speed);
  torque = std::max(-motor.peak_torque, std::min(motor.peak_torque, torque));  // current limit
  return direction * torque * motor.gear_ratio * motor.efficiency;
}

double MotorDrive::reflected_inertia() const {
  return motor.rotor_inertia * motor.gear_ratio * motor.gear_ratio;
}

EffortFunction tracking_controller(std::shared_ptr<Plant> model, Control control, double kp,
                                   double kd, const VectorXd& inertia,
                                   const std::vector<bool>& passive,
                                   const EffortFunction& passive_laws) {
  std::vector<Eigen::Index> active_index, passive_index;
  for (Eigen::Index d = 0; d < inertia.size(); ++d)
    (d < static_cast<Eigen::Index>(passive.size()) && passive[static_cast<size_t>(d)]
         ? passive_index
         : active_index)
        .push_back(d);
  if (!passive_index.empty() && !passive_laws)
    throw std::invalid_argument("tracking_controller: passive drivers need their laws");
  return [model, control, kp, kd, inertia, active_index, passive_index, passive_laws](
             double t, const VectorXd& q, const VectorXd& qd, VectorXd& effort) {
    VectorXd qr, qdr, qddr;
    model->motion(t, qr, qdr, &qddr);
    const VectorXd servo = kp * (qr - q) + kd * (qdr - qd);
    VectorXd laws;
    if (!passive_index.empty()) passive_laws(t, q, qd, laws);
    if (control == Control::pd) {
      effort = inertia.cwiseProduct(servo);
      for (const Eigen::Index p : passive_index) effort[p] = laws[p];
      return;
    }
    numeric::MassBias mb;
    std::string why;
    if (!model->place(t, q, qd, mb, why)) {
      effort = VectorXd::Constant(q.size(), std::nan(""));
      return;
    }
    VectorXd qdd = qddr + servo;
    if (!passive_index.empty()) {
      // Collocated partial feedback linearisation (Spong): the active coordinates get the
      // servo's accelerations; the passive ones the accelerations their laws then give, from
      // their rows of M qdd + h = effort.
      const auto a = active_index, p = passive_index;
      const Eigen::MatrixXd Mpp = mb.M(p, p);
      const VectorXd rhs = laws(p) - mb.h(p) - mb.M(p, a) * qdd(a);
      const VectorXd passive_qdd = Mpp.ldlt().solve(rhs);
      qdd(p) = passive_qdd;
    }
    effort = mb.M * qdd + mb.h;
    for (const Eigen::Index p : passive_index) effort[p] = laws[p];
  };
}

std::string to_string(Integrator integrator) {
  return integrator == Integrator::rk4 ? "rk4" : "implicit-midpoint";
}

Integrator integrator_from_string(const std::string& name) {
  if (name == "rk4") return Integrator::rk4;
  if (name == "implicit-midpoint" || name == "midpoint") return Integrator::implicit_midpoint;
  throw std::invalid_argument("unknown integrator '" + name + "' (rk4 or implicit-midpoint)");
}

SimulationResult simulate(Plant& plant, const EffortFunction& effort,
                          const SimulationOptions& options) {
  SimulationResult result;
  result.columns = plant.columns();
  for (const char* c : {"E.kinetic", "E.potential", "W.efforts", "W.loads", "E.balance"})
    result.columns.push_back(c);
  const auto n = static_cast<Eigen::Index>(plant.drivers().size());
  const VectorXd extra =
      options.extra_inertia.size() == n ? options.extra_inertia : VectorXd::Zero(n);
  if (!(options.dt > 0) || !(options.t1 > options.t0))
    throw std::invalid_argument("simulate: need dt > 0 and t1 > t0");

  // The state: q, qd, work of the efforts, work of the loads.
  const Eigen::Index size = 2 * n + 2;
  VectorXd y(size);
  {
    VectorXd q, qd;
    plant.motion(options.t0, q, qd);
    if (options.initial) std::tie(q, qd) = *options.initial;
    if (options.from_rest) qd.setZero();
    y << q, qd, 0, 0;
  }
  const VectorXd start = y.head(n);
  // dy/dt at (t, y); false (with `why`) when the mechanism cannot be placed or M is singular.
  std::string why;
  auto derivative = [&](double t, const VectorXd& s, VectorXd& dy) {
    const VectorXd q = s.head(n), qd = s.segment(n, n);
    numeric::MassBias mb;
    if (!plant.place(t, q, qd, mb, why)) return false;
    mb.M.diagonal() += extra;
    VectorXd e;
    effort(t, q, qd, e);
    if (!e.allFinite()) {
      why = "an effort law is not a finite number";
      return false;
    }
    VectorXd qdd;
    if (!numeric::forward_accelerations(mb, e, qdd)) {
      why = "singular configuration: the mass matrix is not positive definite";
      return false;
    }
    dy.resize(size);
    dy << qd, qdd, e.dot(qd), plant.load_power(t);
    return true;
  };
  auto record = [&](double t, const VectorXd& s) {
    VectorXd dy;
    if (!derivative(t, s, dy)) return false;
    std::vector<double> row;
    double kinetic = 0, potential = 0;
    if (!plant.row(t, s.head(n), s.segment(n, n), dy.segment(n, n), row, kinetic, potential, why))
      return false;
    const VectorXd qd = s.segment(n, n);
    kinetic += 0.5 * qd.dot(extra.cwiseProduct(qd));
    const double balance = kinetic + potential - s[2 * n] - s[2 * n + 1];
    row.insert(row.end(), {kinetic, potential, s[2 * n], s[2 * n + 1], balance});
    result.rows.push_back(std::move(row));
    return true;
  };

  auto fail = [&](double t) {
    result.error = time_text(t) + ": " + why;
    return result;
  };
  if (!record(options.t0, y)) return fail(options.t0);
  const auto steps = static_cast<long>(std::ceil((options.t1 - options.t0) / options.dt - 1e-9));
  const double dt = (options.t1 - options.t0) / static_cast<double>(steps);
  // One step of length h from (t, y) into `next`; false with `failed_at` set when a stage fails.
  double failed_at = options.t0;
  VectorXd k1, k2, k3, k4;
  auto advance = [&](double t, const VectorXd& y0, double h, VectorXd& next) {
    if (options.integrator == Integrator::rk4) {
      failed_at = t;
      if (!derivative(t, y0, k1)) return false;
      failed_at = t + h / 2;
      if (!derivative(t + h / 2, y0 + h / 2 * k1, k2)) return false;
      if (!derivative(t + h / 2, y0 + h / 2 * k2, k3)) return false;
      failed_at = t + h;
      if (!derivative(t + h, y0 + h * k3, k4)) return false;
      next = y0 + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      return true;
    }
    // Implicit midpoint: y1 = y0 + h f(t + h/2, (y0 + y1)/2), solved for the midpoint
    // m = (y0 + y1)/2 by Newton: m - y0 - h/2 f(m) = 0, Jacobian by forward differences.
    const double tm = t + h / 2;
    failed_at = t;
    if (!derivative(t, y0, k1)) return false;
    failed_at = tm;
    VectorXd m = y0 + h / 2 * k1, f;  // explicit Euler half step as the start
    bool converged = false;
    for (int iteration = 0; iteration < 20 && !converged; ++iteration) {
      if (!derivative(tm, m, f)) return false;
      const VectorXd r = m - y0 - h / 2 * f;
      Eigen::MatrixXd J = Eigen::MatrixXd::Identity(size, size);
      for (Eigen::Index c = 0; c < 2 * n; ++c) {  // the works do not enter f
        const double e = 1e-7 * std::max(1.0, std::abs(m[c]));
        VectorXd mc = m, fc;
        mc[c] += e;
        if (!derivative(tm, mc, fc)) return false;
        J.col(c) -= h / 2 * (fc - f) / e;
      }
      const VectorXd step = J.partialPivLu().solve(r);
      m -= step;
      converged = step.head(2 * n).cwiseAbs().maxCoeff() <=
                  1e-12 * std::max(1.0, m.head(2 * n).cwiseAbs().maxCoeff());
    }
    if (!converged) {
      why = "implicit midpoint: Newton did not converge (reduce --dt)";
      return false;
    }
    if (!derivative(tm, m, f)) return false;
    next = y0 + h * f;
    return true;
  };

  // Uniform steps from `base` (t0, or the last periodic event); the last one ends at t1.
  double base = options.t0, t = options.t0;
  long k = 0;
  VectorXd next;
  while (options.t1 - t > 1e-9 * dt) {
    double h = std::min(dt, options.t1 - t);
    if (options.t1 - t - h < 1e-9 * dt) h = options.t1 - t;
    if (!advance(t, y, h, next)) return fail(failed_at);
    bool event = false;
    if (options.periodic_driver >= 0) {
      const Eigen::Index d = options.periodic_driver;
      if (std::abs(next[d] - start[d]) >= options.period) {
        // Land on the boundary (secant on the step length): the support exchange, where the
        // configuration moved back by the period is the same one.
        const double boundary = start[d] + std::copysign(options.period, next[d] - start[d]);
        double ha = 0, fa = y[d] - boundary, hb = h, fb = next[d] - boundary;
        for (int i = 0;
             i < 30 && std::abs(fb) > 1e-13 * std::max(1.0, std::abs(boundary)) && fb != fa; ++i) {
          const double hc = hb - fb * (hb - ha) / (fb - fa);
          if (!advance(t, y, hc, next)) return fail(failed_at);
          ha = hb;
          fa = fb;
          hb = hc;
          fb = next[d] - boundary;
        }
        h = hb;
        event = true;
      }
    }
    y = next;
    ++result.steps;
    ++k;
    const bool last = options.t1 - (t + h) <= 1e-9 * dt;
    t = last ? options.t1 : event ? t + h : base + dt * static_cast<double>(k);
    if (event) {
      y[options.periodic_driver] -= std::copysign(
          options.period, y[options.periodic_driver] - start[options.periodic_driver]);
      plant.restart();
      ++result.periods;
      base = t;
      k = 0;
    }
    if (event || last || result.steps % options.every == 0)
      if (!record(t, y)) return fail(t);
  }
  return result;
}

}  // namespace mechgen::sim
