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

std::vector<std::string> mass_bias_columns(const std::vector<std::string>& drivers) {
  std::vector<std::string> out;
  for (size_t a = 0; a < drivers.size(); ++a)
    for (size_t b = a; b < drivers.size(); ++b) out.push_back("M." + drivers[a] + "." + drivers[b]);
  for (const std::string& a : drivers) out.push_back("h." + a);
  return out;
}

void append_mass_bias(const MassBias& mb, std::vector<double>& row) {
  for (Eigen::Index a = 0; a < mb.M.rows(); ++a)
    for (Eigen::Index b = a; b < mb.M.cols(); ++b) row.push_back(mb.M(a, b));
  for (Eigen::Index a = 0; a < mb.h.size(); ++a) row.push_back(mb.h[a]);
}

}  // namespace mechgen::numeric
