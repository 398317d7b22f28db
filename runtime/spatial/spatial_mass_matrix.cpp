#include "spatial/spatial_mass_matrix.hpp"

#include "spatial/spatial_dynamics.hpp"

namespace mechgen::spatial {

MassBias mass_matrix_bias(const SpatialSolver& solver, const SpatialState& state,
                          const Eigen::VectorXd& qpd) {
  const Eigen::Index n = qpd.size();
  SpatialState s = state;
  Eigen::VectorXd qpdd = Eigen::VectorXd::Zero(n);
  solver.rates(s, qpd, qpdd);
  MassBias mb;
  mb.h = inverse_dynamics(solver, s).effort;
  mb.M.resize(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    qpdd.setZero();
    qpdd(i) = 1;
    solver.rates(s, qpd, qpdd);
    mb.M.col(i) = inverse_dynamics(solver, s).effort - mb.h;
  }
  // The unit-acceleration columns agree with their transposes to round-off; average them so the
  // result is symmetric exactly, as M is.
  mb.M = (0.5 * (mb.M + mb.M.transpose())).eval();
  return mb;
}

}  // namespace mechgen::spatial
