// Solving a spatial model at given primary coordinates (driven_solve.hpp).
#include "spatial/driven_solve.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mechgen::spatial {

namespace {

// The closing joints' mismatch, 6 rows per circuit: the chord's relative displacement from its
// first body to its second as a rotation vector and a translation (zero when closed).
Eigen::VectorXd mismatch(const SpatialSolver& solver, const SpatialState& s) {
  const SpatialGraph& g = solver.graph();
  const SpatialModel& m = solver.model();
  Eigen::VectorXd out(g.rows());
  for (int k = 0; k < g.circuits(); ++k) {
    const int chord = g.chords[static_cast<size_t>(k)];
    const SpatialJoint& joint = m.joints[static_cast<size_t>(chord)];
    const auto c0 = static_cast<size_t>(g.joint_column[static_cast<size_t>(chord)]);
    Pose motion;
    for (size_t i = 0; i < joint.columns.size(); ++i)
      motion = motion * geometry::screw_displacement(solver.instance().axes[c0 + i],
                                                     s.q[static_cast<Eigen::Index>(c0 + i)]);
    const Pose gap = s.D[static_cast<size_t>(joint.first)] * motion *
                     geometry::inverse(s.D[static_cast<size_t>(joint.second)]);
    const V3 w = rotation_log(gap.R);
    out.segment<6>(6 * k) << w[0], w[1], w[2], gap.p[0], gap.p[1], gap.p[2];
  }
  return out;
}

Eigen::MatrixXd pick(const Eigen::MatrixXd& N, const std::vector<int>& which) {
  Eigen::MatrixXd out(N.rows(), static_cast<Eigen::Index>(which.size()));
  for (size_t k = 0; k < which.size(); ++k) out.col(static_cast<Eigen::Index>(k)) = N.col(which[k]);
  return out;
}

}  // namespace

Eigen::VectorXd primary_of(const SpatialSolver& solver, const SpatialState& state) {
  const std::vector<int>& primary = solver.graph().primary;
  Eigen::VectorXd qp(static_cast<Eigen::Index>(primary.size()));
  for (size_t k = 0; k < primary.size(); ++k)
    qp[static_cast<Eigen::Index>(k)] = state.q[primary[k]];
  return qp;
}

namespace {

bool newton_step(const SpatialSolver& solver, const Eigen::VectorXd& qp, SpatialState& state,
                 int iterations) {
  const SpatialGraph& g = solver.graph();
  const Eigen::VectorXd step = qp - primary_of(solver, state);
  if (g.circuits() > 0 && !g.secondary.empty() && step.norm() > 0) {
    // First-order prediction along the secondary map at the start.
    const Eigen::MatrixXd N = solver.network(state);
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(pick(N, g.secondary));
    qr.setThreshold(1e-10);
    const Eigen::VectorXd ds = qr.solve(-pick(N, g.primary) * step);
    for (size_t k = 0; k < g.secondary.size(); ++k)
      state.q[g.secondary[k]] += ds[static_cast<Eigen::Index>(k)];
  }
  for (size_t k = 0; k < g.primary.size(); ++k)
    state.q[g.primary[k]] = qp[static_cast<Eigen::Index>(k)];
  solver.place(state);
  if (g.circuits() == 0 || g.secondary.empty()) return true;
  for (int it = 0; it < iterations; ++it) {
    const Eigen::VectorXd e = mismatch(solver, state);
    if (!e.allFinite()) return false;
    if (e.norm() < 1e-13) return true;
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(pick(solver.network(state), g.secondary));
    qr.setThreshold(1e-10);
    const Eigen::VectorXd dq = qr.solve(-e);
    for (size_t k = 0; k < g.secondary.size(); ++k)
      state.q[g.secondary[k]] += dq[static_cast<Eigen::Index>(k)];
    solver.place(state);
    if (dq.norm() < 1e-15) break;
  }
  // Closed when the residual is well below any length of interest (1e-10 m); polish() then takes
  // it to round-off, so the accepted configuration is as accurate as with a tighter test.
  return mismatch(solver, state).norm() < 1e-10;
}

// One more Newton correction from a closed state: the residual goes from the closing tolerance
// (1e-13) to round-off, which matters for the coordinates near a singular pose (a knee almost
// straight), where that residual is amplified.
void polish(const SpatialSolver& solver, SpatialState& state) {
  const SpatialGraph& g = solver.graph();
  if (g.circuits() == 0 || g.secondary.empty()) return;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(pick(solver.network(state), g.secondary));
  qr.setThreshold(1e-10);
  const Eigen::VectorXd dq = qr.solve(-mismatch(solver, state));
  for (size_t k = 0; k < g.secondary.size(); ++k)
    state.q[g.secondary[k]] += dq[static_cast<Eigen::Index>(k)];
  solver.place(state);
}

}  // namespace

bool assemble_at(const SpatialSolver& solver, const Eigen::VectorXd& qp, SpatialState& state,
                 double max_step, int iterations) {
  // Equal steps of at most max_step (largest primary change); when they do not close, twice,
  // four times ... as many, up to 64 times.
  const SpatialState start = state;
  const Eigen::VectorXd q0 = primary_of(solver, start);
  const double span = (qp - q0).cwiseAbs().maxCoeff();
  const int least = std::isfinite(max_step) && max_step > 0
                        ? std::max(1, static_cast<int>(std::ceil(span / max_step)))
                        : 1;
  for (int steps = least; steps <= 64 * least; steps *= 2) {
    state = start;
    bool closed = true;
    for (int k = 1; k <= steps && closed; ++k)
      closed =
          newton_step(solver, q0 + (qp - q0) * (static_cast<double>(k) / steps), state, iterations);
    if (closed) return true;
  }
  return false;
}

void solve_at(const SpatialSolver& solver, const Eigen::VectorXd& qp, const Eigen::VectorXd& qpd,
              const Eigen::VectorXd& qpdd, SpatialState& state, double max_step) {
  if (!assemble_at(solver, qp, state, max_step)) {
    const SpatialModel& m = solver.model();
    const SpatialJoint& j = m.joints[static_cast<size_t>(solver.graph().chords.at(0))];
    throw ModelError(j.loc,
                     "the circuits do not close at the requested primary coordinates "
                     "(Newton-Raphson from the warm start): out of reach, or too far "
                     "from the start for one step");
  }
  polish(solver, state);
  solver.rates(state, qpd, qpdd);
  state.assembled = true;
}

}  // namespace mechgen::spatial
