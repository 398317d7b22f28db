// Closed-form inverse kinematics of pose-driven limbs (issue 11: "a pose-driven limb: the joint
// angles in closed form where the chain allows it"), recognised from the geometry of a circuit:
// a serial limb of real revolute joints (the circuit's only real secondary coordinates) closed by
// a rest of known motion (primary coordinates, such as a pose driver's prescribed ones, and that
// pose driver's free virtual coordinates).
#pragma once

#include <optional>

#include "spatial_circuit_solvers.hpp"

namespace mechgen::gen {

// Three revolutes with parallel axes n; the rest moves in the limb's plane (rotations about n,
// translations normal to n) and its free virtual coordinates are the translation along n and
// the rotations about two axes normal to n, all zero at the solution (seed 003's leg with its
// foot pose-driven: x, y and the foot angle). The middle angle by the law of cosines (branch
// from the assembly), the first from the hip-to-ankle direction, the last from the prescribed
// rotation. Unreachable (|cos| > 1) is reported through the group's reach value.
std::optional<CircuitClosedForm> planar_limb_ik(const CircuitSolverContext& context, int circuit);

// Six revolutes in Pieper's layout, from either end: the last three axes meet at a point W (a
// spherical wrist, or a humanoid's hip seen from the foot), the first two meet at a point O (a
// shoulder, or an ankle's pitch and roll) and the third misses O (an elbow or a knee); the rest
// fully prescribed (a pose driver giving position and orientation). The third angle from |W - O|
// (Paden-Kahan subproblem 3), the first two from W's direction (subproblem 2), the last three
// from the remaining rotation (subproblems 2 and 1); each branch from the assembly. Bioloid's
// legs (hip yaw, roll, pitch meeting; knee; ankle pitch and roll meeting) and its arms (shoulder
// pitch and roll meeting; elbow; the seed's three added wrist joints meeting).
std::optional<CircuitClosedForm> six_revolute_limb_ik(const CircuitSolverContext& context,
                                                      int circuit);

}  // namespace mechgen::gen
