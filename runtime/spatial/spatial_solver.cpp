// The spatial reference solver: product of exponentials, Newton-Raphson circuit closure, Davies'
// velocities, exact accelerations and screw Jacobians (spatial_solver.hpp).
#include "spatial/spatial_solver.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace mechgen::spatial {

namespace {

using geometry::adjoint;
using geometry::cross;
using geometry::lie_bracket;
using geometry::screw_displacement;

V3 vec(const SpatialModel& m, const Vec3Expr& v, const GiNaC::exmap& subs) {
  return {m.evaluate(v.x, subs), m.evaluate(v.y, subs), m.evaluate(v.z, subs)};
}

Eigen::Matrix<double, 6, 1> to_eigen(const Twist& t) {
  Eigen::Matrix<double, 6, 1> x;
  x << t.w[0], t.w[1], t.w[2], t.v[0], t.v[1], t.v[2];
  return x;
}

// Column-pivoted QR with an absolute rank threshold relative to the largest entry.
Eigen::ColPivHouseholderQR<Eigen::MatrixXd> factor(const Eigen::MatrixXd& A) {
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  qr.setThreshold(1e-10);
  return qr;
}

int rank(const Eigen::MatrixXd& A) {
  if (A.cols() == 0 || A.rows() == 0) return 0;
  return static_cast<int>(factor(A).rank());
}

Eigen::MatrixXd columns(const Eigen::MatrixXd& N, const std::vector<int>& which) {
  Eigen::MatrixXd out(N.rows(), static_cast<Eigen::Index>(which.size()));
  for (size_t k = 0; k < which.size(); ++k) out.col(static_cast<Eigen::Index>(k)) = N.col(which[k]);
  return out;
}

}  // namespace

V3 rotation_log(const M3& R) {
  const double c = std::clamp((R(0, 0) + R(1, 1) + R(2, 2) - 1) / 2, -1.0, 1.0);
  const double angle = std::acos(c);
  const V3 axis2{R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1)};  // 2 sin(a) axis
  if (angle < 1e-6) return {axis2[0] / 2, axis2[1] / 2, axis2[2] / 2};
  if (angle < std::numbers::pi - 1e-6) {
    const double k = angle / (2 * std::sin(angle));
    return {k * axis2[0], k * axis2[1], k * axis2[2]};
  }
  // Near a half turn: the axis from the diagonal of R = 2 a a^T - I.
  V3 a{std::sqrt(std::max(0.0, (R(0, 0) + 1) / 2)), std::sqrt(std::max(0.0, (R(1, 1) + 1) / 2)),
       std::sqrt(std::max(0.0, (R(2, 2) + 1) / 2))};
  if (R(0, 1) + R(1, 0) < 0) a[1] = -a[1];
  if (R(0, 2) + R(2, 0) < 0) a[2] = -a[2];
  return {angle * a[0], angle * a[1], angle * a[2]};
}

std::array<double, 4> quaternion(const M3& R) {
  std::array<double, 4> q;
  const double tr = R(0, 0) + R(1, 1) + R(2, 2);
  if (tr > 0) {
    const double s = 2 * std::sqrt(tr + 1);
    q = {s / 4, (R(2, 1) - R(1, 2)) / s, (R(0, 2) - R(2, 0)) / s, (R(1, 0) - R(0, 1)) / s};
  } else if (R(0, 0) > R(1, 1) && R(0, 0) > R(2, 2)) {
    const double s = 2 * std::sqrt(1 + R(0, 0) - R(1, 1) - R(2, 2));
    q = {(R(2, 1) - R(1, 2)) / s, s / 4, (R(0, 1) + R(1, 0)) / s, (R(0, 2) + R(2, 0)) / s};
  } else if (R(1, 1) > R(2, 2)) {
    const double s = 2 * std::sqrt(1 + R(1, 1) - R(0, 0) - R(2, 2));
    q = {(R(0, 2) - R(2, 0)) / s, (R(0, 1) + R(1, 0)) / s, s / 4, (R(1, 2) + R(2, 1)) / s};
  } else {
    const double s = 2 * std::sqrt(1 + R(2, 2) - R(0, 0) - R(1, 1));
    q = {(R(1, 0) - R(0, 1)) / s, (R(0, 2) + R(2, 0)) / s, (R(1, 2) + R(2, 1)) / s, s / 4};
  }
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  const double sign = q[0] < 0 ? -1 : 1;
  for (double& x : q) x *= sign / n;
  return q;
}

SpatialSolver::SpatialSolver(const SpatialModel& model, std::vector<double> parameters)
    : model_(model), graph_(build_spatial_graph(model)), parameters_(std::move(parameters)) {
  if (parameters_.empty()) parameters_ = model.common.default_parameters();
  if (parameters_.size() != model.common.parameters.size())
    throw ModelError({model.common.file, 0, 0}, "wrong number of parameter values");
  const GiNaC::exmap subs = model.common.substitutions(parameters_);
  inst_.gravity = vec(model, model.gravity, subs);
  for (const SpatialBody& b : model.bodies) {
    const V3 axis = vec(model, b.rotation_axis, subs);
    inst_.body_frame.push_back({geometry::rodrigues(axis, model.evaluate(b.rotation_angle, subs)),
                                vec(model, b.origin, subs)});
    inst_.mass.push_back(b.ground ? 0.0 : model.evaluate(b.mass.mass, subs));
    inst_.com.push_back(b.ground ? V3{0, 0, 0} : vec(model, b.mass.com, subs));
    M3 I;
    for (size_t k = 0; k < 9; ++k)
      I.m[k] = b.ground ? 0.0 : model.evaluate({b.mass.inertia[k], "inertia", b.mass.loc}, subs);
    inst_.inertia.push_back(I);
    std::vector<V3> points;
    for (const SpatialPoint& p : b.points) points.push_back(vec(model, p.local, subs));
    inst_.points.push_back(points);
  }
  for (const SpatialJoint& j : model.joints) {
    const V3 s0 = vec(model, j.s0, subs);
    inst_.joint_point.push_back(s0);
    const double pitch = model.evaluate(j.pitch, subs);
    for (size_t k = 0; k < j.columns.size(); ++k) {
      geometry::ScrewAxis<double> a;
      a.kind = j.columns[k].kind == ScrewColumnKind::rotation ? geometry::ScrewKind::rotation
               : j.columns[k].kind == ScrewColumnKind::translation
                   ? geometry::ScrewKind::translation
                   : geometry::ScrewKind::helical;
      a.s = vec(model, j.columns[k].s, subs);
      a.s0 = s0;
      a.pitch = pitch;
      inst_.axes.push_back(a);
      inst_.unit.push_back(geometry::unit_twist(a));
      inst_.hint.push_back(model.evaluate(j.assembly[k], subs));
    }
  }
  for (const SpatialLoad& f : model.loads) {
    Load load;
    load.body = f.body;
    load.torque = f.torque;
    const SpatialBody& b = model.bodies[static_cast<size_t>(f.body)];
    for (size_t k = 0; !f.torque && k < b.points.size(); ++k)
      if (b.points[k].name == f.point) load.local = inst_.points[static_cast<size_t>(f.body)][k];
    const Expr* parts[3] = {&f.value.x, &f.value.y, &f.value.z};
    for (size_t k = 0; k < 3; ++k)
      load.value[k] = numeric::TimeExpression(parts[k]->ex.subs(subs), model.common.t);
    loads_.push_back(load);
  }
  for (const int c : graph_.primary) {
    const SpatialColumn& col = graph_.columns[static_cast<size_t>(c)];
    GiNaC::ex value, value_d, value_dd;
    double reference = 0;
    if (col.driver >= 0) {
      const SpatialDriver& d = model.drivers[static_cast<size_t>(col.driver)];
      if (d.table) {  // a recorded trajectory: the spline's exact value and derivatives
        q_.emplace_back(d.table->spline, 0);
        qd_.emplace_back(d.table->spline, 1);
        qdd_.emplace_back(d.table->spline, 2);
        offset_.push_back(0);
        continue;
      }
      value = d.value.ex, value_d = d.value_d, value_dd = d.value_dd;
    } else {
      const PoseCoordinate& pc = model.pose_drivers[static_cast<size_t>(col.pose_driver)]
                                     .coordinates[static_cast<size_t>(col.pose_coordinate)];
      value = pc.value->ex, value_d = pc.value_d, value_dd = pc.value_dd;
      reference = model.evaluate({pc.reference, "reference", pc.value->loc}, subs);
    }
    q_.emplace_back(value.subs(subs), model.common.t);
    qd_.emplace_back(value_d.subs(subs), model.common.t);
    qdd_.emplace_back(value_dd.subs(subs), model.common.t);
    offset_.push_back(reference);
  }
}

void SpatialSolver::primary_motion(double t, Eigen::VectorXd& q, Eigen::VectorXd& qd,
                                   Eigen::VectorXd& qdd) const {
  const auto n = static_cast<Eigen::Index>(q_.size());
  q.resize(n), qd.resize(n), qdd.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const auto i = static_cast<size_t>(k);
    q[k] = q_[i](t) - offset_[i];
    qd[k] = qd_[i](t);
    qdd[k] = qdd_[i](t);
  }
}

void SpatialSolver::place(SpatialState& s) const {
  const size_t nb = model_.bodies.size();
  s.D.assign(nb, Pose{});
  s.screw.assign(inst_.unit.size(), Twist{});
  auto joint_motion = [&](int j) {
    Pose E;
    const auto c0 = static_cast<size_t>(graph_.joint_column[static_cast<size_t>(j)]);
    for (size_t k = 0; k < model_.joints[static_cast<size_t>(j)].columns.size(); ++k)
      E = E * screw_displacement(inst_.axes[c0 + k], s.q[static_cast<Eigen::Index>(c0 + k)]);
    return E;
  };
  for (const int b : graph_.order) {
    if (b == model_.ground) continue;
    const int p = graph_.parent[static_cast<size_t>(b)];
    const int j = graph_.parent_joint[static_cast<size_t>(b)];
    const Pose E = joint_motion(j);
    s.D[static_cast<size_t>(b)] = model_.joints[static_cast<size_t>(j)].first == p
                                      ? s.D[static_cast<size_t>(p)] * E
                                      : s.D[static_cast<size_t>(p)] * geometry::inverse(E);
  }
  for (size_t j = 0; j < model_.joints.size(); ++j) {
    Pose G = s.D[static_cast<size_t>(model_.joints[j].first)];
    const auto c0 = static_cast<size_t>(graph_.joint_column[j]);
    for (size_t k = 0; k < model_.joints[j].columns.size(); ++k) {
      s.screw[c0 + k] = adjoint(G, inst_.unit[c0 + k]);
      G = G * screw_displacement(inst_.axes[c0 + k], s.q[static_cast<Eigen::Index>(c0 + k)]);
    }
  }
}

Eigen::MatrixXd SpatialSolver::network(const SpatialState& s) const {
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(graph_.rows(), graph_.cols());
  for (int k = 0; k < graph_.circuits(); ++k)
    for (int c = 0; c < graph_.cols(); ++c) {
      const int sign = graph_.circuit_sign[static_cast<size_t>(k)][static_cast<size_t>(c)];
      if (sign != 0) N.block<6, 1>(6 * k, c) = sign * to_eigen(s.screw[static_cast<size_t>(c)]);
    }
  return N;
}

Eigen::VectorXd SpatialSolver::closure_error(const SpatialState& s) const {
  Eigen::VectorXd e(graph_.rows());
  for (int k = 0; k < graph_.circuits(); ++k) {
    const SpatialJoint& j =
        model_.joints[static_cast<size_t>(graph_.chords[static_cast<size_t>(k)])];
    Pose E;
    const auto c0 = static_cast<size_t>(
        graph_.joint_column[static_cast<size_t>(graph_.chords[static_cast<size_t>(k)])]);
    for (size_t i = 0; i < j.columns.size(); ++i)
      E = E * screw_displacement(inst_.axes[c0 + i], s.q[static_cast<Eigen::Index>(c0 + i)]);
    const Pose M = s.D[static_cast<size_t>(j.first)] * E *
                   geometry::inverse(s.D[static_cast<size_t>(j.second)]);
    const V3 w = rotation_log(M.R);
    e.segment<6>(6 * k) << w[0], w[1], w[2], M.p[0], M.p[1], M.p[2];
  }
  return e;
}

void SpatialSolver::check_mobility(const Eigen::MatrixXd& N) const {
  const Eigen::MatrixXd Ns = columns(N, graph_.secondary);
  const int rs = rank(Ns);
  const int ns = static_cast<int>(graph_.secondary.size());
  if (rs < ns) {
    // The secondary columns the pivoted QR leaves out are the undetermined coordinates.
    const int c =
        Ns.rows() == 0
            ? graph_.secondary[0]
            : graph_.secondary[static_cast<size_t>(factor(Ns).colsPermutation().indices()[rs])];
    const SpatialColumn& col = graph_.columns[static_cast<size_t>(c)];
    const SpatialJoint& j = model_.joints[static_cast<size_t>(col.joint)];
    std::ostringstream m;
    if (col.pose_driver >= 0) {
      const PoseDriver& pd = model_.pose_drivers[static_cast<size_t>(col.pose_driver)];
      m << "pose driver '" << pd.name << "' under-determines the motion: its free coordinate '"
        << pd.coordinates[static_cast<size_t>(col.pose_coordinate)].name
        << "' is not fixed by the rest of the mechanism (N_s is singular at assembly, rank " << rs
        << " of " << ns << "); prescribe it";
      throw ModelError(pd.loc, m.str());
    }
    m << "the motion is under-determined: joint '" << j.name << "' (coordinate " << col.index + 1
      << ") is not fixed by the drivers (N_s is singular at assembly, rank " << rs << " of " << ns
      << " secondary coordinates); add a driver, prescribe a pose coordinate or lock a joint";
    throw ModelError(j.loc, m.str());
  }
  // Each primary motion must be one the secondary coordinates can follow: range(N_p) inside
  // range(N_s). The first primary column that raises the rank over-determines the motion.
  Eigen::MatrixXd A = Ns;
  for (const int c : graph_.primary) {
    A.conservativeResize(Eigen::NoChange, A.cols() + 1);
    A.col(A.cols() - 1) = N.col(c);
    if (rank(A) == rs) continue;
    const SpatialColumn& col = graph_.columns[static_cast<size_t>(c)];
    if (col.driver >= 0) {
      const SpatialDriver& d = model_.drivers[static_cast<size_t>(col.driver)];
      throw ModelError(d.loc, "driver '" + d.name +
                                  "' over-determines the motion: the mechanism cannot follow it "
                                  "together with the other drivers; remove it or free a joint");
    }
    const PoseDriver& pd = model_.pose_drivers[static_cast<size_t>(col.pose_driver)];
    throw ModelError(pd.loc, "pose driver '" + pd.name +
                                 "' over-determines the motion: its "
                                 "coordinate '" +
                                 pd.coordinates[static_cast<size_t>(col.pose_coordinate)].name +
                                 "' cannot be prescribed together with the others; leave it out");
  }
}

namespace {
// The circuits did not close: a continuation may retry with a shorter step (a singular N_s in
// the rates is not retried: approaching it again would only hide it).
struct ClosureFailure : ModelError {
  using ModelError::ModelError;
};
}  // namespace

void SpatialSolver::close_circuits(SpatialState& s, bool first) const {
  place(s);
  if (graph_.circuits() == 0) return;
  double error = 0;
  for (int iteration = 0; iteration < 60; ++iteration) {
    const Eigen::VectorXd e = closure_error(s);
    error = e.norm();
    if (error < 1e-13) return;
    const Eigen::MatrixXd Ns = columns(network(s), graph_.secondary);
    const Eigen::VectorXd dq = factor(Ns).solve(-e);
    for (size_t k = 0; k < graph_.secondary.size(); ++k)
      s.q[graph_.secondary[k]] += dq[static_cast<Eigen::Index>(k)];
    place(s);
    if (dq.norm() < 1e-15) return;
  }
  if (error < 1e-10) return;
  const SpatialJoint& j = model_.joints[static_cast<size_t>(graph_.chords[0])];
  std::ostringstream m;
  m << "the circuits do not close at t = " << s.t << " (closure error " << error
    << " after 60 Newton-Raphson steps" << (first ? " from the assembly hints" : "")
    << "): the drivers take the mechanism out of reach, or give `assembly:` hints nearer a closed "
       "configuration";
  throw ClosureFailure(j.loc, m.str());
}

Eigen::MatrixXd SpatialSolver::secondary_map(const SpatialState& s) const {
  const Eigen::MatrixXd N = network(s);
  return factor(columns(N, graph_.secondary)).solve(-columns(N, graph_.primary));
}

void SpatialSolver::rates(SpatialState& s, const Eigen::VectorXd& qpd,
                          const Eigen::VectorXd& qpdd) const {
  const auto nc = static_cast<Eigen::Index>(graph_.cols());
  s.qd = Eigen::VectorXd::Zero(nc);
  s.qdd = Eigen::VectorXd::Zero(nc);
  for (size_t k = 0; k < graph_.primary.size(); ++k) {
    s.qd[graph_.primary[k]] = qpd[static_cast<Eigen::Index>(k)];
    s.qdd[graph_.primary[k]] = qpdd[static_cast<Eigen::Index>(k)];
  }
  const Eigen::MatrixXd N = network(s);
  const bool closed = graph_.circuits() > 0 && !graph_.secondary.empty();
  const auto Ns = factor(closed ? columns(N, graph_.secondary) : Eigen::MatrixXd::Identity(1, 1));
  // Singular, or so near it (pivot ratio below 1e-7: within about 1e-7 of a singular pose) that
  // the velocities would be meaningless.
  const double conditioning =
      closed ? Ns.matrixR().diagonal().cwiseAbs().minCoeff() /
                   std::max(1e-300, Ns.matrixR().diagonal().cwiseAbs().maxCoeff())
             : 1;
  if (closed &&
      (Ns.rank() < static_cast<Eigen::Index>(graph_.secondary.size()) || conditioning < 1e-7)) {
    std::ostringstream m;
    m << "N_s is singular at t = " << s.t << " (pivot ratio " << conditioning << ", rank "
      << Ns.rank() << " of " << graph_.secondary.size()
      << "): the mechanism passes a singular configuration there; change the drivers' motion "
         "or the geometry";
    throw ModelError(model_.joints[static_cast<size_t>(graph_.chords[0])].loc, m.str());
  }
  const Eigen::VectorXd qsd = closed ? Eigen::VectorXd(Ns.solve(-columns(N, graph_.primary) * qpd))
                                     : Eigen::VectorXd::Zero(0);
  for (size_t k = 0; closed && k < graph_.secondary.size(); ++k)
    s.qd[graph_.secondary[k]] = qsd[static_cast<Eigen::Index>(k)];

  // Twists of every body (sum of signed screws along the tree path) and of every screw's carrier.
  const size_t nb = model_.bodies.size();
  s.V.assign(nb, Twist{});
  for (size_t b = 0; b < nb; ++b)
    for (int c = 0; c < graph_.cols(); ++c)
      if (const int sign = graph_.path_sign[b][static_cast<size_t>(c)])
        s.V[b] = s.V[b] + (sign * s.qd[c]) * s.screw[static_cast<size_t>(c)];
  s.carrier.assign(s.screw.size(), Twist{});
  s.screw_rate.assign(s.screw.size(), Twist{});
  for (size_t j = 0; j < model_.joints.size(); ++j) {
    Twist carrier = s.V[static_cast<size_t>(model_.joints[j].first)];
    const auto c0 = static_cast<size_t>(graph_.joint_column[j]);
    for (size_t k = 0; k < model_.joints[j].columns.size(); ++k) {
      s.carrier[c0 + k] = carrier;
      s.screw_rate[c0 + k] = lie_bracket(carrier, s.screw[c0 + k]);
      carrier = carrier + s.qd[static_cast<Eigen::Index>(c0 + k)] * s.screw[c0 + k];
    }
  }
  // The circulation law differentiated: N q'' + sum_i sign_i [carrier_i, $_i] q_i' = 0.
  Eigen::VectorXd convective = Eigen::VectorXd::Zero(graph_.rows());
  for (int k = 0; k < graph_.circuits(); ++k)
    for (int c = 0; c < graph_.cols(); ++c)
      if (const int sign = graph_.circuit_sign[static_cast<size_t>(k)][static_cast<size_t>(c)])
        convective.segment<6>(6 * k) +=
            (sign * s.qd[c]) * to_eigen(s.screw_rate[static_cast<size_t>(c)]);
  const Eigen::VectorXd qsdd =
      closed ? Eigen::VectorXd(Ns.solve(-columns(N, graph_.primary) * qpdd - convective))
             : Eigen::VectorXd::Zero(0);
  for (size_t k = 0; closed && k < graph_.secondary.size(); ++k)
    s.qdd[graph_.secondary[k]] = qsdd[static_cast<Eigen::Index>(k)];
  s.A.assign(nb, Twist{});
  for (size_t b = 0; b < nb; ++b)
    for (int c = 0; c < graph_.cols(); ++c)
      if (const int sign = graph_.path_sign[b][static_cast<size_t>(c)])
        s.A[b] = s.A[b] + (sign * s.qdd[c]) * s.screw[static_cast<size_t>(c)] +
                 (sign * s.qd[c]) * s.screw_rate[static_cast<size_t>(c)];
}

void SpatialSolver::solve(double t, SpatialState& s) const {
  if (s.assembled && graph_.circuits() > 0) return advance(t, s, 0);
  Eigen::VectorXd qp, qpd, qpdd;
  primary_motion(t, qp, qpd, qpdd);
  solve(t, qp, qpd, qpdd, s);
}

namespace {
// A secondary coordinate closing this far (rad, or m for a slide) from its second-order
// prediction has not followed the motion: samples far apart let Newton-Raphson jump to another
// assembly branch (or to an angle 2 pi k away), silently. Between samples fine enough to plot, the
// prediction error is orders of magnitude below it.
constexpr double kBranchJump = 0.1;
constexpr int kMaxHalvings = 16;
}  // namespace

void SpatialSolver::advance(double t, SpatialState& s, int halvings) const {
  const SpatialState from = s;
  Eigen::VectorXd qp, qpd, qpdd;
  primary_motion(t, qp, qpd, qpdd);
  bool followed = true;
  try {
    solve(t, qp, qpd, qpdd, s);
  } catch (const ClosureFailure&) {
    if (halvings == kMaxHalvings) throw;
    followed = false;
  }
  const double dt = t - from.t;
  for (size_t k = 0; followed && k < graph_.secondary.size(); ++k) {
    const Eigen::Index c = graph_.secondary[k];
    const double predicted = from.q[c] + dt * from.qd[c] + dt * dt / 2 * from.qdd[c];
    followed = std::abs(s.q[c] - predicted) <= kBranchJump;
  }
  if (followed) return;
  if (halvings == kMaxHalvings) {
    std::ostringstream m;
    m << "the mechanism cannot follow its drivers from t = " << from.t << " to t = " << t
      << ": its closure jumps (a branch point or a singular configuration in between)";
    throw ModelError(model_.joints[static_cast<size_t>(graph_.chords[0])].loc, m.str());
  }
  s = from;
  advance(from.t + dt / 2, s, halvings + 1);
  advance(t, s, halvings + 1);
}

// The first assembly: Newton-Raphson from the assembly hints with the drivers at their values at
// t0. Where that does not close (drivers far from the hints' values: cranks started out of phase),
// the drivers move from the hints' values to theirs in steps, each closed from the last (halved on
// failure), when the hints themselves close: the assembly is then the one the hints' branch
// reaches continuously, not whichever one Newton-Raphson falls into.
void SpatialSolver::assemble(const Eigen::VectorXd& qp, SpatialState& s) const {
  const Eigen::VectorXd hint = Eigen::Map<const Eigen::VectorXd>(
      inst_.hint.data(), static_cast<Eigen::Index>(inst_.hint.size()));
  const auto drive = [&](double fraction) {
    for (size_t k = 0; k < graph_.primary.size(); ++k) {
      const Eigen::Index c = graph_.primary[k];
      s.q[c] = hint[c] + fraction * (qp[static_cast<Eigen::Index>(k)] - hint[c]);
    }
  };
  s.q = hint;
  drive(1);
  try {
    close_circuits(s, true);
    return;
  } catch (const ClosureFailure& direct) {
    s.q = hint;
    try {
      close_circuits(s, true);
    } catch (const ClosureFailure&) {
      throw direct;  // the hints themselves do not close: nothing to continue from
    }
    double done = 0, step = 0.125;
    Eigen::VectorXd travel(static_cast<Eigen::Index>(graph_.primary.size()));
    for (size_t k = 0; k < graph_.primary.size(); ++k)
      travel[static_cast<Eigen::Index>(k)] =
          qp[static_cast<Eigen::Index>(k)] - hint[graph_.primary[k]];
    while (done < 1) {
      const Eigen::VectorXd from = s.q;
      const double next = std::min(1.0, done + step);
      // Start each step from the first-order prediction, and refuse a step that lands farther
      // from it than a branch jump (Newton-Raphson wandering to another assembly or winding an
      // angle by turns), as advance() does along time.
      const Eigen::VectorXd predicted = secondary_map(s) * ((next - done) * travel);
      for (size_t k = 0; k < graph_.secondary.size(); ++k)
        s.q[graph_.secondary[k]] += predicted[static_cast<Eigen::Index>(k)];
      const Eigen::VectorXd start = s.q;
      drive(next);
      bool closed = true;
      try {
        close_circuits(s, true);
      } catch (const ClosureFailure&) {
        closed = false;
      }
      for (size_t k = 0; closed && k < graph_.secondary.size(); ++k)
        closed = std::abs(s.q[graph_.secondary[k]] - start[graph_.secondary[k]]) <= kBranchJump;
      if (closed) {
        done = next;
        step = std::min(2 * step, 0.125);
      } else {
        s.q = from;
        place(s);
        step /= 2;
        if (step < 1.0 / 4096) throw direct;
      }
    }
  }
}

// Joint coordinates defined once (issue 28): the first assembly's free angles of real joints in
// (-pi, pi], a spherical joint's three in the set whose middle angle lies in [-pi/2, pi/2]
// (rotations about x, y, z: (a, b, c) and (a + pi, pi - b, c + pi) are one orientation). From
// there every coordinate follows the motion continuously, never wrapped (a column jumping by
// 2 pi within a sweep would break its plots and its rates), and a generated kernel, seeded with
// this assembly, follows it the same way: equal configurations, equal columns.
void SpatialSolver::canonical_angles(SpatialState& s) const {
  const auto wrapped = [](double a) {
    const double w = std::remainder(a, 2 * M_PI);
    return w == -M_PI ? M_PI : w;
  };
  bool changed = false;
  for (size_t j = 0; j < model_.joints.size(); ++j) {
    const SpatialJoint& joint = model_.joints[j];
    if (joint.is_virtual) continue;
    const auto c0 = static_cast<size_t>(graph_.joint_column[j]);
    const auto free = [&](size_t k) { return !graph_.columns[c0 + k].primary; };
    const auto q = [&](size_t k) -> double& { return s.q[static_cast<Eigen::Index>(c0 + k)]; };
    if (joint.type == SpatialJointType::spherical && free(0) && free(1) && free(2) &&
        std::abs(wrapped(q(1))) > M_PI / 2) {
      const double b = wrapped(q(1));
      q(0) += M_PI;
      q(1) = (b > 0 ? M_PI : -M_PI) - b;
      q(2) += M_PI;
      changed = true;
    }
    for (size_t k = 0; k < joint.columns.size(); ++k)
      if (free(k) && joint.columns[k].kind == ScrewColumnKind::rotation && wrapped(q(k)) != q(k)) {
        q(k) = wrapped(q(k));
        changed = true;
      }
  }
  if (changed) place(s);
}

void SpatialSolver::solve(double t, const Eigen::VectorXd& qp, const Eigen::VectorXd& qpd,
                          const Eigen::VectorXd& qpdd, SpatialState& s) const {
  const auto np = static_cast<Eigen::Index>(graph_.primary.size());
  if (qp.size() != np || qpd.size() != np || qpdd.size() != np)
    throw std::invalid_argument("SpatialSolver::solve: " + std::to_string(np) +
                                " primary coordinates expected");
  const bool first = !s.assembled;
  if (first) {
    s.t = t;
    assemble(qp, s);
    canonical_angles(s);
  } else {
    // Continue from the previous sample, extrapolated along its rates.
    const double dt = t - s.t;
    s.t = t;
    s.q += dt * s.qd + (dt * dt / 2) * s.qdd;
    for (size_t k = 0; k < graph_.primary.size(); ++k)
      s.q[graph_.primary[k]] = qp[static_cast<Eigen::Index>(k)];
    close_circuits(s, first);
  }
  if (first) check_mobility(network(s));
  rates(s, qpd, qpdd);
  s.assembled = true;
}

Eigen::MatrixXd SpatialSolver::body_jacobian(const SpatialState& s, int body) const {
  const bool closed = graph_.circuits() > 0 && !graph_.secondary.empty();
  const Eigen::MatrixXd S = closed ? secondary_map(s) : Eigen::MatrixXd();
  const auto np = static_cast<Eigen::Index>(graph_.primary.size());
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(graph_.cols(), np);  // q' = G q_p'
  for (size_t k = 0; k < graph_.primary.size(); ++k)
    G(graph_.primary[k], static_cast<Eigen::Index>(k)) = 1;
  for (size_t k = 0; k < graph_.secondary.size(); ++k)
    if (closed) G.row(graph_.secondary[k]) = S.row(static_cast<Eigen::Index>(k));
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(6, np);
  for (int c = 0; c < graph_.cols(); ++c)
    if (const int sign = graph_.path_sign[static_cast<size_t>(body)][static_cast<size_t>(c)])
      J += sign * to_eigen(s.screw[static_cast<size_t>(c)]) * G.row(c);
  return J;
}

Eigen::MatrixXd SpatialSolver::point_jacobian(const SpatialState& s, int body, const V3& x) const {
  const Eigen::MatrixXd J = body_jacobian(s, body);
  Eigen::Matrix3d skew;
  skew << 0, -x[2], x[1], x[2], 0, -x[0], -x[1], x[0], 0;
  return J.bottomRows(3) - skew * J.topRows(3);  // v + w x x = v - [x] w
}

Pose SpatialSolver::body_pose(const SpatialState& s, int body) const {
  return s.D[static_cast<size_t>(body)] * inst_.body_frame[static_cast<size_t>(body)];
}

V3 SpatialSolver::point_position(const SpatialState& s, int body, const V3& local) const {
  return geometry::apply(body_pose(s, body), local);
}

V3 SpatialSolver::point_velocity(const SpatialState& s, int body, const V3& local) const {
  return geometry::point_velocity(s.V[static_cast<size_t>(body)], point_position(s, body, local));
}

V3 SpatialSolver::point_acceleration(const SpatialState& s, int body, const V3& local) const {
  return geometry::point_acceleration(s.V[static_cast<size_t>(body)],
                                      s.A[static_cast<size_t>(body)],
                                      point_position(s, body, local));
}

std::vector<std::pair<V3, V3>> SpatialSolver::load_values(const SpatialState& s) const {
  std::vector<std::pair<V3, V3>> out;
  for (const Load& load : loads_)
    out.push_back({{load.value[0](s.t), load.value[1](s.t), load.value[2](s.t)},
                   point_position(s, load.body, load.local)});
  return out;
}

std::vector<Wrench> SpatialSolver::applied_wrenches(const SpatialState& s) const {
  std::vector<Wrench> out(model_.bodies.size());
  const auto values = load_values(s);
  for (size_t k = 0; k < loads_.size(); ++k) {
    const auto& [value, x] = values[k];
    Wrench& w = out[static_cast<size_t>(loads_[k].body)];
    w = w +
        (loads_[k].torque ? Wrench{{0, 0, 0}, value} : Wrench{value, geometry::cross(x, value)});
  }
  return out;
}

double SpatialSolver::applied_power(const SpatialState& s) const {
  double power = 0;
  const auto values = load_values(s);
  for (size_t k = 0; k < loads_.size(); ++k) {
    const Twist& V = s.V[static_cast<size_t>(loads_[k].body)];
    const auto& [value, x] = values[k];
    power += loads_[k].torque ? geometry::dot(value, V.w)
                              : geometry::dot(value, geometry::point_velocity(V, x));
  }
  return power;
}

}  // namespace mechgen::spatial
