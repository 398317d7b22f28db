// Forward dynamics from a mass matrix and bias, whichever solver computed them (issue 22): in the
// drivers' (primary) coordinates effort = M qdd + h. The planar ReferenceSolver::mass_matrix_bias
// and spatial::mass_matrix_bias fill a MassBias; forward_accelerations inverts it.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace mechgen::numeric {

struct MassBias {
  Eigen::MatrixXd M;  // driver x driver (model order), symmetric
  Eigen::VectorXd h;  // per driver: gravity, velocity terms, applied loads, springs, dampers
};

// qdd = M^-1 (effort - h) by LDL^T; false (qdd untouched) when M is not positive definite or its
// smallest pivot is below 1e-12 of its largest diagonal entry (a singular configuration).
bool forward_accelerations(const MassBias& mb, const Eigen::VectorXd& effort, Eigen::VectorXd& qdd);

// The CSV columns of `sweep --mass-matrix` (issue 22) for driver coordinates named as in their
// `<a>.q` columns, in model order: `M.<a>.<b>` for a before b (diagonal included), then `h.<a>`.
std::vector<std::string> mass_bias_columns(const std::vector<std::string>& drivers);
// Appends mb's values in mass_bias_columns order.
void append_mass_bias(const MassBias& mb, std::vector<double>& row);

}  // namespace mechgen::numeric
