// Spatial Newton-Euler (seed 001's bodies, the planar seed's eqs. 13-14 in 3D): 6 equations per
// moving body, every joint's reaction wrench and every driven coordinate's effort unknown. A
// joint's reaction is a full wrench (force and moment at the joint point) constrained to do no
// work on the joint's own screws: 6 unknowns minus one equation per coordinate (5 for a revolute,
// 3 for a spherical, 6 for a fixed joint). Where circuits carry redundant constraints (a planar
// linkage drawn with spatial revolutes), the reactions are not unique: the solve returns the
// minimum-norm reactions and says which joints' reactions the redundancy leaves undetermined;
// driver efforts stay unique.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <vector>

#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {

struct SpatialLoads {
  Eigen::VectorXd effort;  // per primary column (graph().primary order): torque or force
  // Per joint: the reaction of its first body on its second (driver efforts excluded), force and
  // moment about `point`, ground frame.
  std::vector<Wrench> reaction;
  std::vector<V3> point;  // per joint: the joint point s0 carried by the second body
  int redundancy = 0;     // dimension of the reactions' null space
};

// Which reactions and efforts a redundancy leaves undetermined (at one configuration).
struct Redundancy {
  int degree = 0;
  std::vector<bool> joint_unique;  // per joint
  // Per joint, per component (fx, fy, fz, mx, my, mz at the joint point): unique?
  std::vector<std::array<bool, 6>> component_unique;
  bool efforts_unique = true;
};

// The system A x = b itself at a solved state: rows 6 per moving body (force, moment about the
// ground origin), then one per joint coordinate; unknowns 6 per joint (force, moment at its
// point), then one effort per primary column. The generated kernels' ne_system() returns the same.
struct NewtonEulerSystem {
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
};
NewtonEulerSystem newton_euler_system(const SpatialSolver& solver, const SpatialState& state);

// Inverse dynamics of a solved state (positions, velocities, accelerations). Throws ModelError
// when no wrench set balances the bodies (a motion the joints cannot transmit).
SpatialLoads inverse_dynamics(const SpatialSolver& solver, const SpatialState& state);
Redundancy redundancy(const SpatialSolver& solver, const SpatialState& state);

// Kinetic and potential energy (gravity) of all bodies at a solved state, and their rates.
struct Energy {
  double kinetic = 0, potential = 0, kinetic_rate = 0, potential_rate = 0;
};
Energy energy(const SpatialSolver& solver, const SpatialState& state);

}  // namespace mechgen::spatial
