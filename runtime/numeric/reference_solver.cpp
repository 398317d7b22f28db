#include "numeric/reference_solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>
#include <stdexcept>

namespace mechgen::numeric {

namespace {

using Eigen::Matrix2d;
using Eigen::MatrixXd;
using Eigen::Vector2d;
using Eigen::VectorXd;

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// Rotation by +90 degrees: perp(v) = k x v.
Vector2d perp(const Vector2d& v) {
  return {-v.y(), v.x()};
}
// z component of a x b.
double cross(const Vector2d& a, const Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}
// A body angle as reported: in (-pi, pi] (the solver's own coordinates stay continuous).
double reported_angle(double th) {
  const double a = std::remainder(th, 2 * std::numbers::pi);
  return a <= -std::numbers::pi ? a + 2 * std::numbers::pi : a;
}
Matrix2d rotation(double th) {
  const double c = std::cos(th), s = std::sin(th);
  Matrix2d r;
  r << c, -s, s, c;
  return r;
}

std::string number(double v) {
  std::ostringstream out;
  out.precision(6);
  out << v;
  return out.str();
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (size_t i = 0; i < names.size(); ++i) {
    if (i) out += ", ";
    out += names[i];
  }
  return out;
}

}  // namespace

const char* to_string(Status status) {
  switch (status) {
    case Status::ok:
      return "ok";
    case Status::diverged:
      return "diverged";
    case Status::branch_jump:
      return "branch_jump";
    case Status::singular_kinematics:
      return "singular_kinematics";
    case Status::singular_dynamics:
      return "singular_dynamics";
  }
  return "unknown";
}

// ---------------------------------------------------------------------------------------------
// TimeFunction

namespace {

// The parameters as the exact rationals their doubles stand for. GiNaC folds the numbers of a
// substituted sum or product in its operand order, which follows type_info addresses and so moves
// with address-space randomisation; floats folded in a different order round differently in each
// process, exact rationals do not (issue 27 item 3: the same input gives the same bytes).
GiNaC::ex exact_rational(double x) {
  if (!std::isfinite(x) || x == 0) return GiNaC::numeric(x);
  int exponent = 0;
  const double fraction = std::frexp(x, &exponent);  // x = fraction 2^exponent, |fraction| < 1
  const long mantissa = static_cast<long>(std::ldexp(fraction, 53));
  return GiNaC::numeric(mantissa) * GiNaC::pow(GiNaC::numeric(2), exponent - 53);
}

GiNaC::exmap exact_values(const GiNaC::exmap& subs) {
  GiNaC::exmap exact;
  for (const auto& [key, value] : subs)
    exact[key] = GiNaC::is_a<GiNaC::numeric>(value) && GiNaC::ex_to<GiNaC::numeric>(value).is_real()
                     ? exact_rational(GiNaC::ex_to<GiNaC::numeric>(value).to_double())
                     : value;
  return exact;
}

}  // namespace

ReferenceSolver::TimeFunction::TimeFunction(const GiNaC::ex& e, const GiNaC::exmap& subs,
                                            const GiNaC::symbol& t, SourceLoc loc, std::string what)
    : loc_(std::move(loc)), what_(std::move(what)) {
  GiNaC::ex substituted;
  try {
    // A map of symbols: exact lookups, linear in the parameter count (see Model::evaluate).
    substituted = e.subs(exact_values(subs), GiNaC::subs_options::no_pattern |
                                                 GiNaC::subs_options::pattern_is_not_product);
  } catch (const std::exception& error) {
    throw ModelError(loc_, what_ + " cannot be evaluated: " + error.what());
  }
  ex_ = TimeExpression(substituted, t);
  constant_ = false;
  if (!ex_.depends_on_time()) {
    value_ = (*this)(0.0);
    constant_ = true;
  }
}

double ReferenceSolver::TimeFunction::operator()(double t) const {
  if (constant_) return value_;
  double v = 0;
  try {
    v = ex_(t);
  } catch (const std::exception& error) {
    throw ModelError(loc_,
                     what_ + " cannot be evaluated at t = " + number(t) + ": " + error.what());
  }
  if (!std::isfinite(v))
    throw ModelError(loc_,
                     what_ + " does not evaluate to a finite real number at t = " + number(t));
  return v;
}

// ---------------------------------------------------------------------------------------------
// Construction: every time-independent number, once per parameter set.

ReferenceSolver::ReferenceSolver(const Model& model, std::vector<double> parameters,
                                 Options options)
    : model_(model), parameters_(std::move(parameters)), options_(options) {
  const SourceLoc file_loc{model.file, 0, 0};
  if (parameters_.size() != model.parameters.size())
    throw ModelError(file_loc, "the solver was given " + std::to_string(parameters_.size()) +
                                   " parameter values for " +
                                   std::to_string(model.parameters.size()) + " parameters");
  subs_ = model.substitutions(parameters_);
  layout_ = column_layout(model);
  points_ = model.named_points();

  auto eval = [&](const Expr& e, const std::string& what) {
    const double v = model.evaluate(e, subs_);
    if (!std::isfinite(v)) throw ModelError(e.loc, what + " is not a finite number");
    return v;
  };
  auto vec = [&](const Vec2Expr& v, const std::string& what) {
    return Vector2d(eval(v.x, what), eval(v.y, what));
  };
  auto local = [&](int body, const std::string& point, const SourceLoc& loc) -> Vector2d {
    if (body < 0 || body >= static_cast<int>(model.bodies.size()))
      throw ModelError(loc, "invalid body index " + std::to_string(body));
    const BodyPoint* p = model.bodies[body].find_point(point);
    if (!p)
      throw ModelError(loc, "body '" + model.bodies[body].name + "' has no point '" + point + "'");
    return vec(p->local, "point '" + point + "' of body '" + model.bodies[body].name + "'");
  };
  auto time_function = [&](const Expr& e, const std::string& what) {
    return TimeFunction(e.ex, subs_, model.t, e.loc, what);
  };

  gravity_ = vec(model.gravity, "gravity");

  // Bodies and the characteristic length (scales angles against lengths in every rank decision).
  double length = 0;
  bodies_.resize(model.bodies.size());
  for (size_t i = 0; i < model.bodies.size(); ++i) {
    const Body& body = model.bodies[i];
    BodyData& data = bodies_[i];
    for (const BodyPoint& p : body.points)
      length = std::max(length, vec(p.local, "point '" + p.name + "'").cwiseAbs().maxCoeff());
    if (body.ground) continue;
    data.slot = 3 * moving_++;
    if (body.mass.source != MassProperties::Source::none) {
      data.mass = eval(body.mass.mass, "mass of body '" + body.name + "'");
      data.inertia = eval(body.mass.inertia, "inertia of body '" + body.name + "'");
      data.com = vec(body.mass.com, "centre of mass of body '" + body.name + "'");
      length = std::max(length, data.com.cwiseAbs().maxCoeff());
    }
  }

  int unknowns = 0;
  for (size_t j = 0; j < model.joints.size(); ++j) {
    const Joint& joint = model.joints[j];
    JointData data;
    data.type = joint.type;
    data.first = joint.first;
    data.second = joint.second;
    data.p2 = local(joint.second, joint.point, joint.loc);
    data.row = static_cast<int>(rows_.size());
    data.unknown = unknowns;
    const int index = static_cast<int>(j);
    if (joint.type == JointType::revolute) {
      data.p1 = local(joint.first, joint.point, joint.loc);
      rows_.push_back({Row::joint_x, index});
      rows_.push_back({Row::joint_y, index});
      unknowns += 2;
      ne_names_.push_back(joint.name + ".fx");
      ne_names_.push_back(joint.name + ".fy");
    } else {
      if (joint.first < 0 || joint.first >= static_cast<int>(model.bodies.size()))
        throw ModelError(joint.loc, "invalid body index " + std::to_string(joint.first));
      data.p1 = vec(joint.line.through, "line of joint '" + joint.name + "'");
      const Vector2d direction = vec(joint.line.direction, "line of joint '" + joint.name + "'");
      if (!(direction.norm() > 0))
        throw ModelError(joint.line.direction.x.loc,
                         "the line direction of joint '" + joint.name + "' is zero");
      data.u1 = direction.normalized();
      data.n1 = perp(data.u1);
      length = std::max(length, data.p1.cwiseAbs().maxCoeff());
      rows_.push_back({Row::joint_line, index});
      unknowns += 1;
      ne_names_.push_back(joint.name + ".n");
      if (joint.type == JointType::prismatic) {
        data.angle = eval(joint.angle, "angle of joint '" + joint.name + "'");
        rows_.push_back({Row::joint_angle, index});
        unknowns += 1;
        ne_names_.push_back(joint.name + ".m");
      }
    }
    joints_.push_back(data);
  }

  for (size_t d = 0; d < model.drivers.size(); ++d) {
    const Driver& driver = model.drivers[d];
    if (driver.joint < 0 || driver.joint >= static_cast<int>(joints_.size()))
      throw ModelError(driver.loc, "driver '" + driver.name + "' has no joint");
    const JointType type = joints_[driver.joint].type;
    if (driver.kind == DriverKind::angle && type != JointType::revolute)
      throw ModelError(driver.loc, "driver '" + driver.name +
                                       "' of kind angle needs a revolute joint, not a " +
                                       to_string(type));
    if (driver.kind == DriverKind::length && type == JointType::revolute)
      throw ModelError(driver.loc, "driver '" + driver.name +
                                       "' of kind length needs a prismatic or pin_in_slot joint");
    DriverData data;
    data.kind = driver.kind;
    data.joint = driver.joint;
    const std::string what = "driver '" + driver.name + "'";
    data.f = time_function(driver.value, what);
    data.fd = TimeFunction(driver.value_d, subs_, model.t, driver.value.loc,
                           "time derivative of " + what);
    data.fdd = TimeFunction(driver.value_dd, subs_, model.t, driver.value.loc,
                            "second time derivative of " + what);
    data.row = static_cast<int>(rows_.size());
    data.unknown = unknowns++;
    rows_.push_back({Row::driver, static_cast<int>(d)});
    ne_names_.push_back(driver.name + ".effort");
    drivers_.push_back(std::move(data));
  }

  for (const ForceElement& force : model.forces) {
    ForceData data;
    data.type = force.type;
    data.a = force.body_a;
    const std::string what = "force '" + force.name + "'";
    switch (force.type) {
      case ForceType::spring_damper:
        data.b = force.body_b;
        data.pa = local(force.body_a, force.point_a, force.loc);
        data.pb = local(force.body_b, force.point_b, force.loc);
        data.k = time_function(force.stiffness, "stiffness of " + what);
        data.c = time_function(force.damping, "damping of " + what);
        data.free_length = time_function(force.free_length, "free length of " + what);
        break;
      case ForceType::force:
        data.pa = local(force.body_a, force.point_a, force.loc);
        data.fx = time_function(force.force.x, what);
        data.fy = time_function(force.force.y, what);
        break;
      case ForceType::torque:
        if (force.body_a < 0 || force.body_a >= static_cast<int>(model.bodies.size()))
          throw ModelError(force.loc, "invalid body index " + std::to_string(force.body_a));
        data.torque = time_function(force.torque, what);
        break;
    }
    forces_.push_back(std::move(data));
  }

  length_ = length > 0 ? length : 1.0;
  const int n = 3 * moving_;
  row_scale_ = VectorXd::Ones(static_cast<int>(rows_.size()));
  for (size_t r = 0; r < rows_.size(); ++r) {
    const Row& row = rows_[r];
    if (row.kind == Row::joint_angle ||
        (row.kind == Row::driver && drivers_[row.index].kind == DriverKind::angle))
      row_scale_[static_cast<int>(r)] = length_;
  }
  col_scale_ = VectorXd::Ones(n);
  for (int s = 2; s < n; s += 3) col_scale_[s] = 1.0 / length_;

  q_ = qd_ = qdd_ = VectorXd::Zero(n);
  poses_.assign(model.bodies.size(), Pose{0, 0, 0});
  for (const auto& [name, body] : points_) {
    point_local_.push_back(local(body, name, model.bodies[body].loc));
  }
}

std::string ReferenceSolver::row_name(int r) const {
  const Row& row = rows_[r];
  switch (row.kind) {
    case Row::joint_x:
      return model_.joints[row.index].name + ".x";
    case Row::joint_y:
      return model_.joints[row.index].name + ".y";
    case Row::joint_line:
      return model_.joints[row.index].name + ".n";
    case Row::joint_angle:
      return model_.joints[row.index].name + ".angle";
    case Row::driver:
      return model_.drivers[row.index].name;
  }
  return {};
}

std::vector<std::string> ReferenceSolver::constraint_names() const {
  std::vector<std::string> names;
  for (size_t r = 0; r < rows_.size(); ++r) names.push_back(row_name(static_cast<int>(r)));
  return names;
}

// ---------------------------------------------------------------------------------------------
// Kinematics

ReferenceSolver::Kinematic ReferenceSolver::body_state(int body, const VectorXd& q,
                                                       const VectorXd* qd,
                                                       const VectorXd* qdd) const {
  Kinematic k;
  const int s = bodies_[body].slot;
  if (s < 0) {
    k.r = k.v = k.a = Vector2d::Zero();
    k.th = k.w = k.al = 0;
    k.R = Matrix2d::Identity();
    return k;
  }
  k.r = q.segment<2>(s);
  k.th = q[s + 2];
  k.R = rotation(k.th);
  if (qd) {
    k.v = qd->segment<2>(s);
    k.w = (*qd)[s + 2];
  } else {
    k.v = Vector2d::Zero();
    k.w = 0;
  }
  if (qdd) {
    k.a = qdd->segment<2>(s);
    k.al = (*qdd)[s + 2];
  } else {
    k.a = Vector2d::Zero();
    k.al = 0;
  }
  return k;
}

std::vector<ReferenceSolver::Kinematic> ReferenceSolver::states(const VectorXd& q,
                                                                const VectorXd* qd,
                                                                const VectorXd* qdd) const {
  std::vector<Kinematic> out(bodies_.size());
  for (size_t b = 0; b < bodies_.size(); ++b) out[b] = body_state(static_cast<int>(b), q, qd, qdd);
  return out;
}

void ReferenceSolver::residual(const VectorXd& q, double t, VectorXd& phi) const {
  phi.resize(static_cast<int>(rows_.size()));
  const std::vector<Kinematic> st = states(q);
  for (const JointData& j : joints_) {
    const Kinematic &k1 = st[j.first], &k2 = st[j.second];
    const Vector2d d = k2.r + k2.R * j.p2 - k1.r - k1.R * j.p1;
    if (j.type == JointType::revolute) {
      phi.segment<2>(j.row) = d;
    } else {
      phi[j.row] = d.dot(k1.R * j.n1);
      if (j.type == JointType::prismatic) phi[j.row + 1] = k2.th - k1.th - j.angle;
    }
  }
  for (const DriverData& dr : drivers_) {
    const JointData& j = joints_[dr.joint];
    const Kinematic &k1 = st[j.first], &k2 = st[j.second];
    if (dr.kind == DriverKind::angle) {
      phi[dr.row] = k2.th - k1.th - drive(dr, 0, t);
    } else {
      const Vector2d d = k2.r + k2.R * j.p2 - k1.r - k1.R * j.p1;
      phi[dr.row] = d.dot(k1.R * j.u1) - drive(dr, 0, t);
    }
  }
  phi.array() *= row_scale_.array();
}

void ReferenceSolver::jacobian(const VectorXd& q, MatrixXd& jac) const {
  jac.setZero(static_cast<int>(rows_.size()), 3 * moving_);
  const std::vector<Kinematic> st = states(q);
  auto add = [&](int row, int body, const Vector2d& dr, double dth) {
    const int s = bodies_[body].slot;
    if (s < 0) return;
    jac(row, s) += dr.x();
    jac(row, s + 1) += dr.y();
    jac(row, s + 2) += dth;
  };
  // d/dq of (r2 + R2 p2 - r1 - R1 o1) . (R1 v) for a unit vector v of the first body.
  auto line_row = [&](int row, const JointData& j, const Vector2d& v) {
    const Kinematic &k1 = st[j.first], &k2 = st[j.second];
    const Vector2d r2p2 = k2.R * j.p2, r1o1 = k1.R * j.p1;
    const Vector2d d = k2.r + r2p2 - k1.r - r1o1, vw = k1.R * v;
    add(row, j.second, vw, vw.dot(perp(r2p2)));
    add(row, j.first, -vw, -vw.dot(perp(r1o1)) + d.dot(perp(vw)));
  };
  auto angle_row = [&](int row, const JointData& j) {
    add(row, j.second, Vector2d::Zero(), 1.0);
    add(row, j.first, Vector2d::Zero(), -1.0);
  };
  for (const JointData& j : joints_) {
    if (j.type == JointType::revolute) {
      const Kinematic &k1 = st[j.first], &k2 = st[j.second];
      const Vector2d r2p2 = k2.R * j.p2, r1p1 = k1.R * j.p1;
      add(j.row, j.second, Vector2d(1, 0), perp(r2p2).x());
      add(j.row + 1, j.second, Vector2d(0, 1), perp(r2p2).y());
      add(j.row, j.first, Vector2d(-1, 0), -perp(r1p1).x());
      add(j.row + 1, j.first, Vector2d(0, -1), -perp(r1p1).y());
    } else {
      line_row(j.row, j, j.n1);
      if (j.type == JointType::prismatic) angle_row(j.row + 1, j);
    }
  }
  for (const DriverData& dr : drivers_) {
    const JointData& j = joints_[dr.joint];
    if (dr.kind == DriverKind::angle)
      angle_row(dr.row, j);
    else
      line_row(dr.row, j, j.u1);
  }
  jac.array().colwise() *= row_scale_.array();
  jac.array().rowwise() *= col_scale_.transpose().array();
}

void ReferenceSolver::velocity_rhs(double t, VectorXd& nu) const {
  nu.setZero(static_cast<int>(rows_.size()));
  for (const DriverData& dr : drivers_) nu[dr.row] = drive(dr, 1, t);
  nu.array() *= row_scale_.array();
}

void ReferenceSolver::gamma(const VectorXd& q, const VectorXd& qd, double t, VectorXd& g) const {
  g.setZero(static_cast<int>(rows_.size()));
  const std::vector<Kinematic> st = states(q, &qd);
  // gamma of (r2 + R2 p2 - r1 - R1 o1) . (R1 v): everything of its second derivative but the
  // accelerations, negated.
  auto line_gamma = [&](const JointData& j, const Vector2d& v) {
    const Kinematic &k1 = st[j.first], &k2 = st[j.second];
    const Vector2d r2p2 = k2.R * j.p2, r1o1 = k1.R * j.p1;
    const Vector2d d = k2.r + r2p2 - k1.r - r1o1, vw = k1.R * v;
    const Vector2d dd = k2.v + k2.w * perp(r2p2) - k1.v - k1.w * perp(r1o1);
    return k2.w * k2.w * vw.dot(r2p2) - k1.w * k1.w * vw.dot(r1o1) - 2 * k1.w * dd.dot(perp(vw)) +
           k1.w * k1.w * d.dot(vw);
  };
  for (const JointData& j : joints_) {
    if (j.type == JointType::revolute) {
      const Kinematic &k1 = st[j.first], &k2 = st[j.second];
      g.segment<2>(j.row) = k2.w * k2.w * (k2.R * j.p2) - k1.w * k1.w * (k1.R * j.p1);
    } else {
      g[j.row] = line_gamma(j, j.n1);
      // prismatic angle row: gamma = 0
    }
  }
  for (const DriverData& dr : drivers_) {
    const JointData& j = joints_[dr.joint];
    g[dr.row] = drive(dr, 2, t) + (dr.kind == DriverKind::length ? line_gamma(j, j.u1) : 0.0);
  }
  g.array() *= row_scale_.array();
}

ReferenceSolver::Factor ReferenceSolver::factor(const VectorXd& q) const {
  Factor f;
  jacobian(q, f.jac);
  const int n = static_cast<int>(f.jac.cols());
  if (f.jac.rows() == n) {
    // Well-conditioned (the usual case): partial pivoting, its determinant sign, full rank.
    f.partial.compute(f.jac);
    if (f.partial.rcond() > options_.rank_tolerance) {
      int sign = static_cast<int>(f.partial.permutationP().determinant());
      for (int i = 0; i < n; ++i)
        if (f.partial.matrixLU()(i, i) < 0) sign = -sign;
      f.rank = n;
      f.det_sign = sign;
      return f;
    }
  }
  // Ill-conditioned or rectangular: the numerical rank from full pivoting.
  f.full = true;
  f.lu.setThreshold(options_.rank_tolerance);
  f.lu.compute(f.jac);
  f.rank = std::min(static_cast<int>(f.lu.rank()), n - (f.jac.rows() == n ? 1 : 0));
  return f;
}

VectorXd ReferenceSolver::solve_kinematic(const Factor& f, const VectorXd& rhs) const {
  VectorXd y;
  if (!f.full)
    y = f.partial.solve(rhs);
  else if (f.jac.rows() == f.jac.cols())
    y = f.lu.solve(rhs);
  else
    y = f.jac.completeOrthogonalDecomposition().solve(rhs);
  return col_scale_.asDiagonal() * y;
}

bool ReferenceSolver::rates(const Factor& f, const VectorXd& q, double t, VectorXd& qd,
                            VectorXd& qdd) const {
  if (f.rank < 3 * moving_) return false;
  VectorXd rhs;
  velocity_rhs(t, rhs);
  qd = solve_kinematic(f, rhs);
  gamma(q, qd, t, rhs);
  qdd = solve_kinematic(f, rhs);
  return qd.allFinite() && qdd.allFinite();
}

ReferenceSolver::Newton ReferenceSolver::newton(VectorXd& q, double t, int max_iterations,
                                                bool line_search) const {
  // Converged when the residual is at round-off level, or when a step no larger than the tolerance
  // has just been taken and the residual is within it: after such a step the error is of the
  // order of the step squared, so positions come out at full precision for one extra iteration.
  Newton result;
  const double tol = options_.tolerance * length_;
  VectorXd phi, trial_phi;
  MatrixXd jac;
  residual(q, t, phi);
  result.residual = phi.size() ? phi.lpNorm<Eigen::Infinity>() : 0.0;
  for (result.iterations = 0;; ++result.iterations) {
    if (!std::isfinite(result.residual)) return result;
    if (result.residual <= 1e-3 * tol) {
      result.converged = true;
      return result;
    }
    if (result.iterations == max_iterations) return result;
    jacobian(q, jac);
    VectorXd y;
    if (jac.rows() == jac.cols() && !line_search) {
      // Partial pivoting is enough for a Newton step from a good prediction; a singular Jacobian
      // shows as a non-finite step, and the rank decisions are made at the solution. Assembly
      // (line search) starts from rough hints, where the Jacobian may be singular: it takes the
      // minimum-norm least-squares step instead.
      y = jac.partialPivLu().solve(phi);
    } else {
      y = jac.completeOrthogonalDecomposition().solve(phi);
    }
    if (!y.allFinite()) return result;
    const VectorXd dq = col_scale_.asDiagonal() * y;
    double alpha = 1;
    if (!line_search) {
      q -= dq;
      residual(q, t, phi);
    } else {
      const double merit = phi.norm();
      VectorXd trial;
      for (int halving = 0;; ++halving) {
        trial = q - alpha * dq;
        residual(trial, t, trial_phi);
        if (trial_phi.norm() < (1 - 1e-4 * alpha) * merit || halving >= 12) break;
        alpha /= 2;
      }
      q = trial;
      phi = trial_phi;
    }
    result.residual = phi.lpNorm<Eigen::Infinity>();
    if (alpha * y.lpNorm<Eigen::Infinity>() <= tol && result.residual <= tol) {
      result.converged = true;
      ++result.iterations;
      return result;
    }
  }
}

bool ReferenceSolver::chord(VectorXd& q, double t, const Factor& f) const {
  // Newton with the Jacobian of a nearby configuration (the previous sample's, already factorised):
  // linear convergence at a rate |dJ| |J^-1|, each iteration costing a residual and two triangular
  // solves instead of a factorisation. Gives up as soon as a step fails to halve the previous one
  // while still above the tolerance.
  if (f.full || f.jac.rows() != f.jac.cols() || f.rank != f.jac.cols()) return false;
  const double tol = options_.tolerance * length_;
  VectorXd phi;
  double previous = std::numeric_limits<double>::infinity();
  for (int it = 0; it < 2 * options_.max_iterations; ++it) {
    residual(q, t, phi);
    const double res = phi.lpNorm<Eigen::Infinity>();
    if (!std::isfinite(res)) return false;
    if (res <= 1e-3 * tol) return true;
    const VectorXd y = f.partial.solve(phi);
    const double step = y.lpNorm<Eigen::Infinity>();
    if (!std::isfinite(step)) return false;
    q -= col_scale_.asDiagonal() * y;
    const bool slow = step > 0.5 * previous;
    // Converged: a step within the tolerance that either is far below it (the remaining error is
    // a fraction of the step) or no longer shrinks (round-off floor).
    if (step <= tol && (step <= 1e-3 * tol || slow)) return true;
    if (slow) return false;
    previous = step;
  }
  return false;
}

ReferenceSolver::Step ReferenceSolver::step_to(double t_from, double t_to, const VectorXd& q0,
                                               const VectorXd& qd0, const VectorXd& qdd0,
                                               int det_sign0, const Factor* previous, VectorXd& q,
                                               Factor& f) const {
  const double dt = t_to - t_from;
  const VectorXd predicted = q0 + dt * qd0 + (0.5 * dt * dt) * qdd0;
  q = predicted;
  if (!previous || !chord(q, t_to, *previous)) {
    q = predicted;
    if (!newton(q, t_to, options_.max_iterations, false).converged) return Step::diverged;
  }
  for (int s = 2; s < q.size(); s += 3) {
    if (std::abs(q[s] - q0[s]) > options_.branch_jump_angle &&
        std::abs(q[s] - predicted[s]) > options_.branch_jump_angle)
      return Step::branch_jump;
  }
  f = factor(q);
  if (det_sign0 != 0 && f.det_sign != 0 && f.det_sign != det_sign0) return Step::branch_jump;
  return Step::ok;
}

void ReferenceSolver::update_poses() {
  for (size_t b = 0; b < model_.bodies.size(); ++b) {
    const Kinematic k = body_state(static_cast<int>(b), q_);
    poses_[b] = Pose{k.r.x(), k.r.y(), k.th};
  }
}

// ---------------------------------------------------------------------------------------------
// Assembly

void ReferenceSolver::report_rank_problem(const VectorXd& q) const {
  MatrixXd jac;
  jacobian(q, jac);
  Eigen::JacobiSVD<MatrixXd> svd(jac, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const VectorXd& sv = svd.singularValues();
  int rank = 0;
  for (int i = 0; i < sv.size(); ++i)
    if (sv[i] > options_.rank_tolerance * sv[0]) ++rank;
  const double involved = 1e-6;
  std::vector<std::string> joints;
  std::set<int> joint_set, driver_set;
  const SourceLoc* loc = nullptr;
  for (int r = 0; r < jac.rows(); ++r) {
    double weight = 0;
    for (int k = rank; k < jac.rows(); ++k)
      weight = std::max(weight, std::abs(svd.matrixU()(r, k)));
    if (weight <= involved) continue;
    const Row& row = rows_[r];
    if (row.kind == Row::driver) {
      if (driver_set.insert(row.index).second) {
        joints.push_back("driver " + model_.drivers[row.index].name);
        if (!loc) loc = &model_.drivers[row.index].loc;
      }
    } else if (joint_set.insert(row.index).second) {
      joints.push_back(model_.joints[row.index].name);
      if (!loc) loc = &model_.joints[row.index].loc;
    }
  }
  std::vector<std::string> bodies;
  for (size_t b = 0; b < bodies_.size(); ++b) {
    const int s = bodies_[b].slot;
    if (s < 0) continue;
    double weight = 0;
    for (int k = rank; k < jac.cols(); ++k)
      for (int c = s; c < s + 3; ++c) weight = std::max(weight, std::abs(svd.matrixV()(c, k)));
    if (weight > involved) {
      bodies.push_back(model_.bodies[b].name);
      if (!loc && model_.bodies[b].loc.line) loc = &model_.bodies[b].loc;
    }
  }
  std::string message = "the constraint Jacobian has rank " + std::to_string(rank) + " for " +
                        std::to_string(jac.rows()) + " equations in " + std::to_string(jac.cols()) +
                        " coordinates at the assembly configuration";
  if (!joints.empty())
    message += "; redundant constraints among joints " + join(joints) +
               " (over-constrained: the Newton-Euler reactions would be statically "
               "indeterminate)";
  if (!bodies.empty())
    message +=
        "; the motion of bodies " + join(bodies) + " is not determined by the joints and drivers";
  const SourceLoc file_loc{model_.file, 0, 0};
  throw ModelError(loc ? *loc : file_loc, message);
}

void ReferenceSolver::assemble(double t) {
  const SourceLoc file_loc{model_.file, 0, 0};
  const int n = 3 * moving_;
  GiNaC::exmap subs_t = subs_;
  subs_t[model_.t] = GiNaC::numeric(t);

  // Initial guess: hinted angles, angles fixed by prismatic joints and angle drivers, positions
  // chained from the ground through the joints.
  VectorXd q = VectorXd::Zero(n);
  std::vector<bool> known(bodies_.size(), false), hinted(bodies_.size(), false);
  std::vector<double> hint(bodies_.size(), 0);
  for (size_t b = 0; b < bodies_.size(); ++b) {
    const Body& body = model_.bodies[b];
    if (bodies_[b].slot < 0) {
      known[b] = true;
      continue;
    }
    if (body.assembly_angle) {
      hint[b] = model_.evaluate(*body.assembly_angle, subs_t);
      hinted[b] = true;
      q[bodies_[b].slot + 2] = hint[b];
    }
  }
  std::vector<int> angle_driver(joints_.size(), -1), length_driver(joints_.size(), -1);
  for (size_t d = 0; d < drivers_.size(); ++d)
    (drivers_[d].kind == DriverKind::angle ? angle_driver : length_driver)[drivers_[d].joint] =
        static_cast<int>(d);
  for (bool progress = true; progress;) {
    progress = false;
    for (size_t ji = 0; ji < joints_.size(); ++ji) {
      const JointData& j = joints_[ji];
      if (known[j.first] == known[j.second]) continue;
      const bool forward = known[j.first];
      const int from = forward ? j.first : j.second, to = forward ? j.second : j.first;
      double relative = 0;  // th_second - th_first when fixed by the joint or a driver
      bool fixed = false;
      if (j.type == JointType::prismatic) {
        relative = j.angle;
        fixed = true;
      } else if (angle_driver[ji] >= 0) {
        relative = drive(drivers_[angle_driver[ji]], 0, t);
        fixed = true;
      }
      const int sf = bodies_[from].slot, st = bodies_[to].slot;
      const double th_from = sf < 0 ? 0 : q[sf + 2];
      if (fixed && !hinted[to]) q[st + 2] = th_from + (forward ? relative : -relative);
      const Kinematic k1 = body_state(j.first, q), k2 = body_state(j.second, q);
      Vector2d on_first = j.p1;  // joint point (revolute) or where the point sits on the line
      if (j.type != JointType::revolute && length_driver[ji] >= 0)
        on_first += drive(drivers_[length_driver[ji]], 0, t) * j.u1;
      if (forward) {
        const Vector2d world = k1.r + k1.R * on_first;
        q.segment<2>(st) = world - k2.R * j.p2;
      } else {
        const Vector2d world = k2.r + k2.R * j.p2;
        q.segment<2>(st) = world - k1.R * on_first;
      }
      known[to] = true;
      progress = true;
    }
  }

  // A hinted angle fixed by an angle driver or a prismatic joint may be given modulo 2 pi (the
  // driver at 5 pi/2, the hint pi/2): it is moved by whole turns next to the value the joint
  // fixes, which changes no position, so Newton-Raphson does not have to turn the body round.
  for (size_t ji = 0; ji < joints_.size(); ++ji) {
    const JointData& j = joints_[ji];
    if (j.type != JointType::prismatic && angle_driver[ji] < 0) continue;
    const double relative =
        j.type == JointType::prismatic ? j.angle : drive(drivers_[angle_driver[ji]], 0, t);
    const int sf = bodies_[j.first].slot, ss = bodies_[j.second].slot;
    const double th_first = sf < 0 ? 0 : q[sf + 2], th_second = ss < 0 ? 0 : q[ss + 2];
    if (ss >= 0 && hinted[j.second]) {
      const double fixed = th_first + relative;
      q[ss + 2] = fixed + std::remainder(th_second - fixed, 2 * std::numbers::pi);
    } else if (sf >= 0 && hinted[j.first]) {
      const double fixed = th_second - relative;
      q[sf + 2] = fixed + std::remainder(th_first - fixed, 2 * std::numbers::pi);
    }
  }

  const Newton result = newton(q, t, 4 * options_.max_iterations, true);
  if (!result.converged) {
    VectorXd phi;
    residual(q, t, phi);
    int worst = 0;
    if (phi.size()) phi.cwiseAbs().maxCoeff(&worst);
    throw ModelError(file_loc,
                     "the mechanism does not assemble at t = " + number(t) +
                         ": Newton-Raphson from the assembly hints did not converge in " +
                         std::to_string(result.iterations) + " iterations (largest residual " +
                         number(phi.size() ? phi[worst] / row_scale_[worst] : 0.0) +
                         " in constraint " + (phi.size() ? row_name(worst) : std::string("-")) +
                         "); check the dimensions and the `assembly:` hints");
  }

  // Hints: the converged angles must lie within the tolerance of every hint (modulo 2 pi).
  int worst = -1;
  double worst_off = 0;
  for (size_t b = 0; b < bodies_.size(); ++b) {
    if (!hinted[b]) continue;
    const double off =
        std::abs(std::remainder(q[bodies_[b].slot + 2] - hint[b], 2 * std::numbers::pi));
    if (off > model_.assembly_tolerance && off > worst_off) {
      worst_off = off;
      worst = static_cast<int>(b);
    }
  }
  if (worst >= 0) {
    const Body& body = model_.bodies[worst];
    throw ModelError(body.assembly_angle->loc,
                     "the assembly hint of body '" + body.name +
                         "' does not assemble: " + "the nearest configuration has its angle at " +
                         number(q[bodies_[worst].slot + 2]) + " rad, " + number(worst_off) +
                         " rad from the hint " + number(hint[worst]) + " (assembly_tolerance " +
                         number(model_.assembly_tolerance) + ")");
  }

  const Factor f = factor(q);
  rank_ = f.rank;
  if (f.rank < n || (f.rank < static_cast<int>(rows_.size()) && !options_.allow_redundant))
    report_rank_problem(q);
  VectorXd qd, qdd;
  if (!rates(f, q, t, qd, qdd)) report_rank_problem(q);

  q_ = q;
  qd_ = qd;
  qdd_ = qdd;
  t_ = t;
  det_sign_ = f.det_sign;
  factor_ = std::move(f);
  update_poses();
  assembled_ = true;
}

// ---------------------------------------------------------------------------------------------
// Dynamics

bool ReferenceSolver::dynamics(double t) {
  const int neq = 3 * moving_, nunk = static_cast<int>(ne_names_.size());
  ne_a_.setZero(neq, nunk);
  ne_b_.setZero(neq);
  std::vector<Kinematic> kin(bodies_.size());
  std::vector<Vector2d> centre(bodies_.size());
  for (size_t b = 0; b < bodies_.size(); ++b) {
    kin[b] = body_state(static_cast<int>(b), q_, &qd_, &qdd_);
    centre[b] = kin[b].r + kin[b].R * bodies_[b].com;
  }
  // An unknown force per unit value `f` at world point `p` on `body`, and a unit moment.
  auto unknown_force = [&](int body, int col, const Vector2d& f, const Vector2d& p) {
    const int s = bodies_[body].slot;
    if (s < 0) return;
    ne_a_(s, col) += f.x();
    ne_a_(s + 1, col) += f.y();
    ne_a_(s + 2, col) += cross(p - centre[body], f);
  };
  auto unknown_moment = [&](int body, int col, double m) {
    const int s = bodies_[body].slot;
    if (s >= 0) ne_a_(s + 2, col) += m;
  };
  auto known_force = [&](int body, const Vector2d& f, const Vector2d& p) {
    const int s = bodies_[body].slot;
    if (s < 0) return;
    ne_b_[s] -= f.x();
    ne_b_[s + 1] -= f.y();
    ne_b_[s + 2] -= cross(p - centre[body], f);
  };
  auto known_moment = [&](int body, double m) {
    const int s = bodies_[body].slot;
    if (s >= 0) ne_b_[s + 2] -= m;
  };

  // Inertia and gravity: m a_G - m g, I alpha.
  for (size_t b = 0; b < bodies_.size(); ++b) {
    const BodyData& body = bodies_[b];
    if (body.slot < 0) continue;
    const Kinematic& k = kin[b];
    const Vector2d rc = k.R * body.com;
    const Vector2d a_g = k.a + k.al * perp(rc) - k.w * k.w * rc;
    ne_b_.segment<2>(body.slot) += body.mass * (a_g - gravity_);
    ne_b_[body.slot + 2] += body.inertia * k.al;
  }
  // Reactions: on the second body at the joint point, the opposite on the first.
  for (const JointData& j : joints_) {
    const Kinematic &k1 = kin[j.first], &k2 = kin[j.second];
    const Vector2d p = k2.r + k2.R * j.p2;
    if (j.type == JointType::revolute) {
      for (int c = 0; c < 2; ++c) {
        const Vector2d unit = c == 0 ? Vector2d(1, 0) : Vector2d(0, 1);
        unknown_force(j.second, j.unknown + c, unit, p);
        unknown_force(j.first, j.unknown + c, -unit, p);
      }
    } else {
      const Vector2d normal = k1.R * j.n1;
      unknown_force(j.second, j.unknown, normal, p);
      unknown_force(j.first, j.unknown, -normal, p);
      if (j.type == JointType::prismatic) {
        unknown_moment(j.second, j.unknown + 1, 1);
        unknown_moment(j.first, j.unknown + 1, -1);
      }
    }
  }
  for (const DriverData& dr : drivers_) {
    const JointData& j = joints_[dr.joint];
    if (dr.kind == DriverKind::angle) {
      unknown_moment(j.second, dr.unknown, 1);
      unknown_moment(j.first, dr.unknown, -1);
    } else {
      const Kinematic &k1 = kin[j.first], &k2 = kin[j.second];
      const Vector2d p = k2.r + k2.R * j.p2, along = k1.R * j.u1;
      unknown_force(j.second, dr.unknown, along, p);
      unknown_force(j.first, dr.unknown, -along, p);
    }
  }
  // Applied loads.
  for (const ForceData& f : forces_) {
    switch (f.type) {
      case ForceType::spring_damper: {
        const Kinematic &ka = kin[f.a], &kb = kin[f.b];
        const Vector2d ra = ka.R * f.pa, rb = kb.R * f.pb;
        const Vector2d pa = ka.r + ra, pb = kb.r + rb;
        const Vector2d va = ka.v + ka.w * perp(ra), vb = kb.v + kb.w * perp(rb);
        const Vector2d d = pb - pa;
        const double length = d.norm();
        const Vector2d u = length > 0 ? Vector2d(d / length) : Vector2d::Zero();
        const double rate = u.dot(vb - va);
        const double tension = f.k(t) * (length - f.free_length(t)) + f.c(t) * rate;
        known_force(f.b, -tension * u, pb);
        known_force(f.a, tension * u, pa);
        break;
      }
      case ForceType::force: {
        const Kinematic& k = kin[f.a];
        known_force(f.a, Vector2d(f.fx(t), f.fy(t)), k.r + k.R * f.pa);
        break;
      }
      case ForceType::torque:
        known_moment(f.a, f.torque(t));
        break;
    }
  }

  ne_x_ = VectorXd::Constant(nunk, nan);
  ne_rank_ = 0;
  if (neq != nunk) return false;
  // Scaled: moment rows / L, moment unknowns * L, so that the rank decision is unit-free.
  VectorXd rs = VectorXd::Ones(neq), cs = VectorXd::Ones(nunk);
  for (int s = 2; s < neq; s += 3) rs[s] = 1 / length_;
  for (const JointData& j : joints_)
    if (j.type == JointType::prismatic) cs[j.unknown + 1] = length_;
  for (const DriverData& dr : drivers_)
    if (dr.kind == DriverKind::angle) cs[dr.unknown] = length_;
  const MatrixXd scaled = rs.asDiagonal() * ne_a_ * cs.asDiagonal();
  // Partial pivoting with a condition estimate; a singular or ill-conditioned system is reported
  // (its numerical rank, from full pivoting, is kept for diagnostics).
  Eigen::PartialPivLU<MatrixXd> lu(scaled);
  if (!(lu.rcond() > options_.rank_tolerance)) {
    Eigen::FullPivLU<MatrixXd> full;
    full.setThreshold(options_.rank_tolerance);
    full.compute(scaled);
    ne_rank_ = std::min(static_cast<int>(full.rank()), nunk - 1);
    return false;
  }
  ne_rank_ = nunk;
  ne_x_ = cs.asDiagonal() * lu.solve(VectorXd(rs.asDiagonal() * ne_b_));
  return ne_x_.allFinite();
}

// ---------------------------------------------------------------------------------------------
// Solve

Status ReferenceSolver::solve(double t, std::vector<double>& row) {
  if (!assembled_) throw std::logic_error("ReferenceSolver::solve called before assemble");
  VectorXd q;
  Factor f;
  Step step = step_to(t_, t, q_, qd_, qdd_, det_sign_, &factor_, q, f);
  // Continuation: retry with 2, 4, ... sub-steps, each predicted from the previous one's rates.
  // A failure is a branch jump when some attempt converged at t itself, but on another branch;
  // else (no configuration found at t) it diverged.
  bool jumped = step == Step::branch_jump;
  for (int pieces = 2; step != Step::ok && pieces <= options_.max_substeps; pieces *= 2) {
    VectorXd qa = q_, qda = qd_, qdda = qdd_;
    int sign = det_sign_;
    double ta = t_;
    Factor previous = factor_;
    for (int k = 1; k <= pieces; ++k) {
      const double tk = k == pieces ? t : t_ + (t - t_) * k / pieces;
      VectorXd qn;
      step = step_to(ta, tk, qa, qda, qdda, sign, &previous, qn, f);
      if (step == Step::ok && k < pieces && !rates(f, qn, tk, qda, qdda)) step = Step::diverged;
      if (step == Step::branch_jump && k == pieces) jumped = true;
      if (step != Step::ok) break;
      qa = qn;
      ta = tk;
      if (f.det_sign != 0) sign = f.det_sign;
      previous = f;
    }
    if (step == Step::ok) q = qa;
  }
  if (step != Step::ok) {
    const Status status = jumped ? Status::branch_jump : Status::diverged;
    fill_row(t, status, row);
    return status;
  }

  q_ = q;
  t_ = t;
  rank_ = f.rank;
  if (f.det_sign != 0) det_sign_ = f.det_sign;
  update_poses();
  VectorXd qd, qdd;
  if (!rates(f, q_, t, qd, qdd)) {
    ne_a_.resize(0, 0);
    ne_b_.resize(0);
    ne_x_.resize(0);
    fill_row(t, Status::singular_kinematics, row);
    return Status::singular_kinematics;
  }
  qd_ = qd;
  qdd_ = qdd;
  factor_ = std::move(f);
  const Status status = dynamics(t) ? Status::ok : Status::singular_dynamics;
  fill_row(t, status, row);
  return status;
}

bool ReferenceSolver::mass_matrix_bias(double t, MatrixXd& M, VectorXd& h, double* asymmetry) {
  if (!assembled_ || !ne_x_.allFinite() || ne_x_.size() == 0) return false;
  const int n = static_cast<int>(drivers_.size());
  const VectorXd qdd_kept = qdd_, b_kept = ne_b_, x_kept = ne_x_;
  const MatrixXd a_kept = ne_a_;
  const int rank_kept = ne_rank_;
  VectorXd g0;
  gamma(q_, qd_, t, g0);
  for (const DriverData& dr : drivers_) g0[dr.row] -= drive(dr, 2, t) * row_scale_[dr.row];
  // Driver efforts for driver accelerations a (gamma's driver rows carry them).
  auto efforts = [&](int unit, VectorXd& e) {
    VectorXd g = g0;
    if (unit >= 0)
      g[drivers_[static_cast<size_t>(unit)].row] +=
          row_scale_[drivers_[static_cast<size_t>(unit)].row];
    qdd_ = solve_kinematic(factor_, g);
    if (!dynamics(t)) return false;
    e.resize(n);
    for (int i = 0; i < n; ++i) e[i] = ne_x_[drivers_[static_cast<size_t>(i)].unknown];
    return true;
  };
  bool ok = efforts(-1, h);
  M.resize(n, n);
  VectorXd e;
  for (int i = 0; ok && i < n; ++i) {
    ok = efforts(i, e);
    if (ok) M.col(i) = e - h;
  }
  qdd_ = qdd_kept;
  ne_a_ = a_kept;
  ne_b_ = b_kept;
  ne_x_ = x_kept;
  ne_rank_ = rank_kept;
  if (!ok) return false;
  if (asymmetry)
    *asymmetry =
        (M - M.transpose()).cwiseAbs().maxCoeff() / std::max(M.cwiseAbs().maxCoeff(), 1e-300);
  M = (0.5 * (M + M.transpose())).eval();
  return true;
}

void ReferenceSolver::set_driver_motion(const VectorXd& q, const VectorXd& qd,
                                        const VectorXd& qdd) {
  const auto n = static_cast<Eigen::Index>(drivers_.size());
  if (q.size() != n || qd.size() != n || qdd.size() != n)
    throw std::logic_error("ReferenceSolver::set_driver_motion: one value per driver expected");
  given_ = {q, qd, qdd};
}

void ReferenceSolver::clear_driver_motion() {
  given_.reset();
}

double ReferenceSolver::drive(const DriverData& dr, int order, double t) const {
  if (given_) return (*given_)[static_cast<size_t>(order)][&dr - drivers_.data()];
  return order == 0 ? dr.f(t) : order == 1 ? dr.fd(t) : dr.fdd(t);
}

double ReferenceSolver::potential_energy() const {
  double v = 0;
  for (size_t b = 0; b < bodies_.size(); ++b) {
    if (bodies_[b].slot < 0) continue;
    const Kinematic k = body_state(static_cast<int>(b), q_);
    v -= bodies_[b].mass * gravity_.dot(k.r + k.R * bodies_[b].com);
  }
  return v;
}

double ReferenceSolver::kinetic_energy() const {
  double e = 0;
  for (size_t b = 0; b < bodies_.size(); ++b) {
    if (bodies_[b].slot < 0) continue;
    const Kinematic k = body_state(static_cast<int>(b), q_, &qd_);
    const Vector2d v = k.v + k.w * perp(k.R * bodies_[b].com);
    e += 0.5 * bodies_[b].mass * v.squaredNorm() + 0.5 * bodies_[b].inertia * k.w * k.w;
  }
  return e;
}

double ReferenceSolver::applied_power(double t) const {
  double p = 0;
  auto velocity = [&](const Kinematic& k, const Vector2d& local) {
    return Vector2d(k.v + k.w * perp(k.R * local));
  };
  for (const ForceData& f : forces_) {
    const Kinematic ka = body_state(f.a, q_, &qd_);
    switch (f.type) {
      case ForceType::spring_damper: {
        const Kinematic kb = body_state(f.b, q_, &qd_);
        const Vector2d d = kb.r + kb.R * f.pb - ka.r - ka.R * f.pa;
        const double length = d.norm();
        const Vector2d u = length > 0 ? Vector2d(d / length) : Vector2d::Zero();
        const double rate = u.dot(velocity(kb, f.pb) - velocity(ka, f.pa));
        p -= (f.k(t) * (length - f.free_length(t)) + f.c(t) * rate) * rate;
        break;
      }
      case ForceType::force:
        p += Vector2d(f.fx(t), f.fy(t)).dot(velocity(ka, f.pa));
        break;
      case ForceType::torque:
        p += f.torque(t) * ka.w;
        break;
    }
  }
  return p;
}

void ReferenceSolver::fill_row(double t, Status status, std::vector<double>& row) const {
  row.assign(static_cast<size_t>(layout_.count), nan);
  row[static_cast<size_t>(layout_.time)] = t;
  if (status == Status::diverged || status == Status::branch_jump) return;
  const bool rates = status != Status::singular_kinematics;
  const bool forces = status == Status::ok;
  auto at = [&](int column) -> double& { return row[static_cast<size_t>(column)]; };

  std::vector<Kinematic> kin(bodies_.size());
  for (size_t b = 0; b < bodies_.size(); ++b)
    kin[b] = rates ? body_state(static_cast<int>(b), q_, &qd_, &qdd_)
                   : body_state(static_cast<int>(b), q_);

  for (size_t d = 0; d < drivers_.size(); ++d) {
    const DriverData& dr = drivers_[d];
    const JointData& j = joints_[dr.joint];
    const Kinematic &k1 = kin[j.first], &k2 = kin[j.second];
    const int c = layout_.driver[d];
    if (dr.kind == DriverKind::angle) {
      at(c) = k2.th - k1.th;
      if (rates) {
        at(c + 1) = k2.w - k1.w;
        at(c + 2) = k2.al - k1.al;
      }
    } else {
      const Vector2d r2p2 = k2.R * j.p2, r1o1 = k1.R * j.p1;
      const Vector2d d_ = k2.r + r2p2 - k1.r - r1o1, u = k1.R * j.u1;
      at(c) = d_.dot(u);
      if (rates) {
        const Vector2d dd = k2.v + k2.w * perp(r2p2) - k1.v - k1.w * perp(r1o1);
        const Vector2d ddd = k2.a + k2.al * perp(r2p2) - k2.w * k2.w * r2p2 - k1.a -
                             k1.al * perp(r1o1) + k1.w * k1.w * r1o1;
        at(c + 1) = dd.dot(u) + k1.w * d_.dot(perp(u));
        at(c + 2) =
            ddd.dot(u) + 2 * k1.w * dd.dot(perp(u)) + d_.dot(k1.al * perp(u) - k1.w * k1.w * u);
      }
    }
    if (forces) at(c + 3) = ne_x_[dr.unknown];
  }
  for (size_t b = 0; b < bodies_.size(); ++b) {
    const int c = layout_.body[b];
    if (c < 0) continue;
    const Kinematic& k = kin[b];
    const Vector2d rc = k.R * bodies_[b].com;
    const Vector2d g = k.r + rc;
    at(c) = g.x();
    at(c + 1) = g.y();
    at(c + 2) = reported_angle(k.th);
    if (!rates) continue;
    const Vector2d v = k.v + k.w * perp(rc);
    const Vector2d a = k.a + k.al * perp(rc) - k.w * k.w * rc;
    at(c + 3) = v.x();
    at(c + 4) = v.y();
    at(c + 5) = k.w;
    at(c + 6) = a.x();
    at(c + 7) = a.y();
    at(c + 8) = k.al;
  }
  for (size_t i = 0; i < points_.size(); ++i) {
    const Kinematic& k = kin[points_[i].second];
    const Vector2d p = k.r + k.R * point_local_[i];
    at(layout_.point[i]) = p.x();
    at(layout_.point[i] + 1) = p.y();
    if (!rates) continue;
    const Vector2d r = k.R * point_local_[i];
    const Vector2d v = k.v + k.w * perp(r);
    const Vector2d a = k.a + k.al * perp(r) - k.w * k.w * r;
    const int c = layout_.point_rates[i];
    at(c) = v.x();
    at(c + 1) = v.y();
    at(c + 2) = a.x();
    at(c + 3) = a.y();
  }
  if (!forces) return;
  for (size_t ji = 0; ji < joints_.size(); ++ji) {
    const JointData& j = joints_[ji];
    const int c = layout_.joint[ji];
    if (j.type == JointType::revolute) {
      at(c) = ne_x_[j.unknown];
      at(c + 1) = ne_x_[j.unknown + 1];
    } else {
      const Vector2d f = ne_x_[j.unknown] * (kin[j.first].R * j.n1);
      at(c) = f.x();
      at(c + 1) = f.y();
      if (j.type == JointType::prismatic) at(c + 2) = ne_x_[j.unknown + 1];
    }
  }
}

}  // namespace mechgen::numeric
