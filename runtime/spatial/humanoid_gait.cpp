// Kajita's LIP walk fed to the virtual chains of a seed-001 humanoid (humanoid_gait.hpp).
#include "spatial/humanoid_gait.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace mechgen::spatial {

namespace {

double parameter(const SpatialSolver& solver, const std::string& name) {
  const auto& ps = solver.model().common.parameters;
  for (size_t k = 0; k < ps.size(); ++k)
    if (ps[k].name == name) return solver.parameters()[k];
  throw ModelError({solver.model().common.file, 0, 0},
                   "the gait needs a parameter '" + name +
                       "' (step_length, step_time, swing_height, steps) in the model");
}

int pose_driver(const SpatialModel& model, const std::string& name) {
  for (size_t k = 0; k < model.pose_drivers.size(); ++k)
    if (model.pose_drivers[k].name == name) return static_cast<int>(k);
  throw ModelError({model.common.file, 0, 0},
                   "the gait needs a pose driver '" + name + "' (a 3P3R virtual chain)");
}

}  // namespace

GaitSettings gait_settings(const SpatialSolver& solver) {
  GaitSettings s;
  s.step_length = parameter(solver, "step_length");
  s.step_time = parameter(solver, "step_time");
  s.swing_height = parameter(solver, "swing_height");
  s.steps = static_cast<int>(std::lround(parameter(solver, "steps")));
  if (!(s.step_time > 0) || s.steps < 1)
    throw ModelError({solver.model().common.file, 0, 0},
                     "the gait needs step_time > 0 and at least one step");
  return s;
}

CentreOfMass centre_of_mass(const SpatialSolver& solver, const SpatialState& state) {
  CentreOfMass c;
  const SpatialInstance& in = solver.instance();
  for (size_t b = 0; b < in.mass.size(); ++b) {
    const double m = in.mass[b];
    if (static_cast<int>(b) == solver.model().ground || m == 0) continue;
    const int bi = static_cast<int>(b);
    const V3 x = solver.point_position(state, bi, in.com[b]);
    c.mass += m;
    c.p = c.p + m * x;
    c.v = c.v + m * solver.point_velocity(state, bi, in.com[b]);
    c.a = c.a + m * solver.point_acceleration(state, bi, in.com[b]);
  }
  const double k = 1 / c.mass;
  c.p = k * c.p, c.v = k * c.v, c.a = k * c.a;
  return c;
}

Eigen::MatrixXd com_jacobian(const SpatialSolver& solver, const SpatialState& state) {
  const SpatialInstance& in = solver.instance();
  Eigen::MatrixXd J =
      Eigen::MatrixXd::Zero(3, static_cast<Eigen::Index>(solver.graph().primary.size()));
  double mass = 0;
  for (size_t b = 0; b < in.mass.size(); ++b) {
    if (static_cast<int>(b) == solver.model().ground || in.mass[b] == 0) continue;
    const int bi = static_cast<int>(b);
    J += in.mass[b] * solver.point_jacobian(state, bi, solver.point_position(state, bi, in.com[b]));
    mass += in.mass[b];
  }
  return J / mass;
}

HumanoidGait::HumanoidGait(const SpatialSolver& solver, const GaitSettings& settings,
                           const std::string& waist, const std::string& right_foot,
                           const std::string& left_foot)
    : solver_(solver), settings_(settings) {
  const SpatialModel& model = solver.model();
  for (const std::string* name : {&waist, &right_foot, &left_foot})
    drivers_.push_back(pose_driver(model, *name));
  // The standing pose: the model's own motion at its t0.
  const GiNaC::exmap subs = model.common.substitutions(solver.parameters());
  const double t0 = model.evaluate(model.common.step.t0, subs);
  SpatialState s;
  solver.solve(t0, s);
  Eigen::VectorXd qd, qdd;
  solver.primary_motion(t0, q0_, qd, qdd);
  for (const PoseDriver& pd : model.pose_drivers) {
    const V3 at{model.evaluate(pd.at.x, subs), model.evaluate(pd.at.y, subs),
                model.evaluate(pd.at.z, subs)};
    at0_.push_back(geometry::apply(s.D[static_cast<size_t>(pd.second)], at));
  }
  const CentreOfMass c = centre_of_mass(solver, s);
  com_offset_ = c.p - at0_[static_cast<size_t>(drivers_[0])];
  const double floor =
      0.5 * (at0_[static_cast<size_t>(drivers_[1])][2] + at0_[static_cast<size_t>(drivers_[2])][2]);
  zc_ = c.p[2] - floor;
  const double g = -solver.instance().gravity[2];
  if (!(g > 0) || !(zc_ > 0))
    throw ModelError({model.common.file, 0, 0},
                     "the LIP gait needs gravity along -z and the centre of mass above the feet");
  omega_ = std::sqrt(g / zc_);
}

int HumanoidGait::step_index(double t) const {
  const int k = static_cast<int>(std::floor(t / settings_.step_time));
  return std::clamp(k, 0, settings_.steps - 1);
}

int HumanoidGait::support(double t) const {
  return step_index(t) % 2;
}

V3 HumanoidGait::footprint(int side, int k) const {
  V3 p = at0_[static_cast<size_t>(drivers_[static_cast<size_t>(1 + side)])];
  p[0] += k * settings_.step_length;
  return p;
}

HumanoidGait::Motion HumanoidGait::foot(int side, double t) const {
  const int k = step_index(t);
  Motion m;
  if (k % 2 == side) {
    m.p = footprint(side, k);
    return m;
  }
  // Swing from footprint k - 1 to k + 1.
  const double T = settings_.step_time, u = (t - k * T) / T, h = settings_.swing_height;
  const double L2 = 2 * settings_.step_length;
  const double s = u * u * u * (10 - 15 * u + 6 * u * u);
  const double ds = 30 * u * u * (1 - u) * (1 - u) / T;
  const double dds = (60 * u - 180 * u * u + 120 * u * u * u) / (T * T);
  const double f = u * (1 - u);  // lift: 64 h f^3
  const double df = (1 - 2 * u) / T, ddf = -2 / (T * T);
  m.p = footprint(side, k - 1);
  m.p[0] += L2 * s;
  m.p[2] += 64 * h * f * f * f;
  m.v[0] = L2 * ds;
  m.v[2] = 64 * h * 3 * f * f * df;
  m.a[0] = L2 * dds;
  m.a[2] = 64 * h * (6 * f * df * df + 3 * f * f * ddf);
  return m;
}

HumanoidGait::Motion HumanoidGait::com(double t) const {
  const int k = step_index(t);
  const double T = settings_.step_time, tau = t - k * T, w = omega_;
  const V3 p = footprint(k % 2, k);
  const double mid = 0.5 * (footprint(0, 0)[1] + footprint(1, 0)[1]);
  const double ch = std::cosh(w * T), sh = std::sinh(w * T);
  // Forward: from L/2 behind the support foot to L/2 ahead; sideways: from the mid-line towards
  // the foot and back, both periodic with continuous velocity at the switches.
  const double x0 = -settings_.step_length / 2,
               vx0 = w * (settings_.step_length / 2) * (1 + ch) / sh;
  const double py = p[1] - mid, y0 = -py, vy0 = w * py * (ch - 1) / sh;
  const double c = std::cosh(w * tau), s = std::sinh(w * tau);
  Motion m;
  m.p = {p[0] + x0 * c + vx0 / w * s, p[1] + y0 * c + vy0 / w * s, zc_ + p[2]};
  m.v = {x0 * w * s + vx0 * c, y0 * w * s + vy0 * c, 0};
  m.a = {w * w * (m.p[0] - p[0]), w * w * (m.p[1] - p[1]), 0};
  return m;
}

V3 HumanoidGait::planned_com(double t) const {
  return com(t).p;
}

V3 HumanoidGait::planned_zmp(double t) const {
  const int k = step_index(t);
  return footprint(k % 2, k);
}

void HumanoidGait::primary_motion(double t, Eigen::VectorXd& q, Eigen::VectorXd& qd,
                                  Eigen::VectorXd& qdd) const {
  const SpatialModel& model = solver_.model();
  const SpatialGraph& g = solver_.graph();
  const auto n = static_cast<Eigen::Index>(g.primary.size());
  q = q0_;
  qd = Eigen::VectorXd::Zero(n);
  qdd = Eigen::VectorXd::Zero(n);
  Motion waist = com(t);
  waist.p = waist.p - com_offset_;
  const V3 waist0 = at0_[static_cast<size_t>(drivers_[0])];
  for (Eigen::Index k = 0; k < n; ++k) {
    const SpatialColumn& col = g.columns[static_cast<size_t>(g.primary[static_cast<size_t>(k)])];
    if (col.pose_driver < 0) continue;  // a joint driver keeps the model's standing value
    const std::string& name = model.pose_drivers[static_cast<size_t>(col.pose_driver)]
                                  .coordinates[static_cast<size_t>(col.pose_coordinate)]
                                  .name;
    if (name.size() != 1) continue;  // rotations: as standing
    const auto i = static_cast<size_t>(name[0] - 'x');
    Motion m;
    if (col.pose_driver == drivers_[0]) {
      m = waist;
    } else if (col.pose_driver == drivers_[1] || col.pose_driver == drivers_[2]) {
      m = foot(col.pose_driver == drivers_[1] ? 0 : 1, t);
    } else {  // carried with the waist
      m = waist;
      m.p = at0_[static_cast<size_t>(col.pose_driver)] + (waist.p - waist0);
    }
    q[k] += m.p[i] - at0_[static_cast<size_t>(col.pose_driver)][i];
    qd[k] = m.v[i];
    qdd[k] = m.a[i];
  }
}

void HumanoidGait::solve(double t, SpatialState& s) const {
  const SpatialGraph& g = solver_.graph();
  Eigen::VectorXd q, qd, qdd;
  primary_motion(t, q, qd, qdd);
  // Per axis, the translation coordinates (positions in graph().primary) of the waist and of the
  // pose drivers carried with it: they move together.
  std::array<std::vector<Eigen::Index>, 3> w;
  for (size_t k = 0; k < g.primary.size(); ++k) {
    const SpatialColumn& col = g.columns[static_cast<size_t>(g.primary[k])];
    if (col.pose_driver < 0 || col.pose_coordinate >= 3 || col.pose_driver == drivers_[1] ||
        col.pose_driver == drivers_[2])
      continue;
    w[static_cast<size_t>(col.pose_coordinate)].push_back(static_cast<Eigen::Index>(k));
  }
  const Motion target = com(t);
  auto waist_block = [&](const Eigen::MatrixXd& J) {
    Eigen::Matrix3d Jw = Eigen::Matrix3d::Zero();
    for (size_t i = 0; i < 3; ++i)
      for (const Eigen::Index k : w[i]) Jw.col(static_cast<Eigen::Index>(i)) += J.col(k);
    return Jw;
  };
  auto add = [&](Eigen::VectorXd& x, const Eigen::Vector3d& d) {
    for (size_t i = 0; i < 3; ++i)
      for (const Eigen::Index k : w[i]) x[k] += d[static_cast<Eigen::Index>(i)];
  };
  auto eigen = [](const V3& v) { return Eigen::Vector3d(v[0], v[1], v[2]); };
  double error = 0;
  for (int iteration = 0; iteration < 30; ++iteration) {
    solver_.solve(t, q, qd, qdd, s);
    const Eigen::Vector3d e = eigen(target.p - centre_of_mass(solver_, s).p);
    error = e.norm();
    if (error < 1e-14) break;
    add(q, waist_block(com_jacobian(solver_, s)).partialPivLu().solve(e));
  }
  if (!(error < 1e-11))
    throw ModelError({solver_.model().common.file, 0, 0},
                     "the waist cannot put the centre of mass on the gait's pendulum at t = " +
                         std::to_string(t));
  // c' = J q_p' and c'' = J q_p'' + (terms in q_p'): both linear in the waist's rates.
  const Eigen::Matrix3d Jw = waist_block(com_jacobian(solver_, s));
  add(qd, Jw.partialPivLu().solve(eigen(target.v - centre_of_mass(solver_, s).v)));
  solver_.rates(s, qd, qdd);
  add(qdd, Jw.partialPivLu().solve(eigen(target.a - centre_of_mass(solver_, s).a)));
  solver_.rates(s, qd, qdd);
}

}  // namespace mechgen::spatial
