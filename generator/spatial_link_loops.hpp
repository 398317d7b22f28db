// Closed forms of binary links with a universal and a spherical end (issue 11 item 1b), a
// circuit solver (spatial_circuit_solvers.hpp): a link (one body, or a cylinder's barrel and rod
// joined by a known prismatic along the line of its end centres) joins a known body X to a body Y
// turned by one unknown revolute from a known body K, or slid by one unknown prismatic (a spatial
// slider-crank's slider). The distance between the end centres is the link's length (constant, or
// the cylinder's), which gives A cos q + B sin q = C for the revolute, a quadratic in q for the
// prismatic; then the universal end's two angles from the link's direction (two rotations about
// crossed axes) and the spherical end's three from the remaining relative rotation (x-y-z
// angles). rsur's RSUR loop and every circuit of quadruped_leg (cylinders l3, l2, l1 on the
// swing, the crank and the hip, then the coupler on the knee, which needs the crank's: dependency
// order) are such links, and so is a rod between two known bodies (a Delta's, once its platform
// is placed). Branches from the assembly; angles within half a turn of the assembly's.
#pragma once

#include <optional>

#include "spatial_circuit_solvers.hpp"

namespace mechgen::gen {

// The link closing `circuit` (its unknown columns all the circuit's, and with it every secondary
// column of the circuit known), or nothing.
std::optional<CircuitClosedForm> link_loop_closed_form(const CircuitSolverContext& context,
                                                       int circuit);

// A platform held only by parallelogram pairs of rods from three or more known bodies (a Delta
// robot's plate): it keeps its orientation, its position is the intersection of three spheres,
// and the rod on its tree path is placed from it (the circuit closes only if that rod was its
// last unknown: the other rods are then links between known bodies, link_loop_closed_form).
std::optional<CircuitClosedForm> platform_closed_form(const CircuitSolverContext& context,
                                                      int circuit);

}  // namespace mechgen::gen
