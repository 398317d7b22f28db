// A spatial model solved at given primary coordinates rather than at its drivers' time laws:
// the sampling behind `mechgen workspace` (Monte Carlo over the driver ranges) and the inverse
// kinematics grids of the tests. Same reference solver (positions by product of exponentials,
// circuits closed by Newton-Raphson on the secondary coordinates, Davies' rates); the start is a
// given state (a warm start) moved to the new primary values to first order along the secondary
// map q_s' = -N_s^+ N_p q_p'. Generated kernels (issue 11) can replace this per sample later.
#pragma once

#include <Eigen/Dense>

#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {

// Positions at the primary values qp (solver.graph().primary order) from `state` (placed and
// closed: a solved state or a previous call's result). Returns false, leaving `state` at the last
// iterate, when the circuits do not close to 1e-12 within `iterations` Newton steps.
bool assemble_at(const SpatialSolver& solver, const Eigen::VectorXd& qp, SpatialState& state,
                 int iterations = 40);

// assemble_at, then the rates for primary rates qpd and accelerations qpdd (state.t unchanged).
// Throws ModelError when the circuits do not close.
void solve_at(const SpatialSolver& solver, const Eigen::VectorXd& qp, const Eigen::VectorXd& qpd,
              const Eigen::VectorXd& qpdd, SpatialState& state);

// The primary coordinates of a placed state (graph().primary order).
Eigen::VectorXd primary_of(const SpatialSolver& solver, const SpatialState& state);

}  // namespace mechgen::spatial
