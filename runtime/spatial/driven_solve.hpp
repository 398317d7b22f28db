// A spatial model solved at given primary coordinates rather than at its drivers' time laws:
// the sampling behind `mechgen workspace` (Monte Carlo over the driver ranges) and the inverse
// kinematics grids of the tests. Same reference solver (positions by product of exponentials,
// circuits closed by Newton-Raphson on the secondary coordinates, Davies' rates); the start is a
// given state (a warm start) moved to the new primary values to first order along the secondary
// map q_s' = -N_s^+ N_p q_p'. Generated kernels (issue 11) can replace this per sample later.
#pragma once

#include <Eigen/Dense>
#include <limits>

#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {

// Positions at the primary values qp (solver.graph().primary order) from `state` (placed and
// closed: a solved state or a previous call's result), by continuation: equal steps of at most
// max_step (the largest primary change per step; infinity: one step), each a predicted Newton run
// to 1e-12 within `iterations` iterations; when one does not close, twice as many steps, up to 64
// times. Short steps keep the branch of the start (a cylinder does not flip over its base pin);
// one long step may land on another. Returns false (state at the last iterate) when none closes.
bool assemble_at(const SpatialSolver& solver, const Eigen::VectorXd& qp, SpatialState& state,
                 double max_step = std::numeric_limits<double>::infinity(), int iterations = 40);

// assemble_at, one more Newton correction (the residual to round-off), then the rates for primary
// rates qpd and accelerations qpdd (state.t unchanged). Throws ModelError when the circuits do not
// close.
void solve_at(const SpatialSolver& solver, const Eigen::VectorXd& qp, const Eigen::VectorXd& qpd,
              const Eigen::VectorXd& qpdd, SpatialState& state,
              double max_step = std::numeric_limits<double>::infinity());

// The primary coordinates of a placed state (graph().primary order).
Eigen::VectorXd primary_of(const SpatialSolver& solver, const SpatialState& state);

}  // namespace mechgen::spatial
