// Closed-form inverse kinematics of a 3R limb driven by a position-only target (a pose driver
// giving a point, its three rotations free), a circuit solver (spatial_circuit_solvers.hpp):
// seed 002's quadruped leg with its foot on a pose driver (side swing about X, hip and knee about
// Y). Recognised from the geometry of the circuit, never the names.
#pragma once

#include <optional>

#include "spatial_circuit_solvers.hpp"

namespace mechgen::gen {

// Three real revolutes: the last two parallel (a planar 2R moving the target point in a plane
// normal to them), the first not parallel to them (a side swing); the rest of the circuit a pose
// driver whose prescribed coordinates place the target point and whose three free rotations
// turn about axes through it. Under the swing the target's component along the first axis and
// its distance from it are invariant, which with the 2R's plane fixes the point before the swing
// (two branches); the swing angle is the rotation taking it to the target (Paden-Kahan 1), the
// 2R's second angle by the law of cosines (two branches), its first by subproblem 1; the pose's
// free rotations from the rest of the orientation (subproblems 2 and 1). Branches from the
// assembly; a target out of reach (a negative discriminant) is reported through the group's
// reach values (`ik_<pose driver>`).
std::optional<CircuitClosedForm> position_limb_ik(const CircuitSolverContext& context, int circuit);

}  // namespace mechgen::gen
