#include "numeric/mass_bias.hpp"

namespace mechgen::numeric {

bool forward_accelerations(const MassBias& mb, const Eigen::VectorXd& effort,
                           Eigen::VectorXd& qdd) {
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(mb.M);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
  // Positive pivots alone do not exclude a numerically singular M.
  const double scale = mb.M.diagonal().cwiseAbs().maxCoeff();
  if (!(ldlt.vectorD().minCoeff() > 1e-12 * scale)) return false;
  const Eigen::VectorXd x = ldlt.solve(effort - mb.h);
  if (!x.allFinite()) return false;
  qdd = x;
  return true;
}

}  // namespace mechgen::numeric
