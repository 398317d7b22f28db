// Forward-dynamics quantities of the spatial reference solver, computed its own way (issue 22):
// by unit accelerations through its Newton-Euler solve. In the primary coordinates,
// effort = M(q) qdd + h(q, qd, t), so h is the effort at qdd = 0 and column i of M is the effort
// at qdd = e_i minus h. Generated kernels' mass_matrix / bias / forward_dynamics are checked
// against these.
#pragma once

#include <Eigen/Dense>

#include "numeric/mass_bias.hpp"
#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {

// M is primary x primary (graph().primary order).
using numeric::forward_accelerations;
using numeric::MassBias;

// M and h at a placed state (positions closed, e.g. by solve or solve_at) with primary rates
// qpd at time state.t; state's accelerations are not used. Throws ModelError as
// inverse_dynamics does.
MassBias mass_matrix_bias(const SpatialSolver& solver, const SpatialState& state,
                          const Eigen::VectorXd& qpd);

}  // namespace mechgen::spatial
