// Forward dynamics from a mass matrix and bias, whichever solver computed them (issue 22): in the
// drivers' (primary) coordinates effort = M qdd + h. The planar ReferenceSolver::mass_matrix_bias
// and spatial::mass_matrix_bias fill a MassBias; forward_accelerations inverts it.
#pragma once

#include <Eigen/Dense>

namespace mechgen::numeric {

struct MassBias {
  Eigen::MatrixXd M;  // driver x driver (model order), symmetric
  Eigen::VectorXd h;  // per driver: gravity, velocity terms, applied loads, springs, dampers
};

// qdd = M^-1 (effort - h) by LDL^T; false (qdd untouched) when M is not positive definite or its
// smallest pivot is below 1e-12 of its largest diagonal entry (a singular configuration).
bool forward_accelerations(const MassBias& mb, const Eigen::VectorXd& effort, Eigen::VectorXd& qdd);

}  // namespace mechgen::numeric
