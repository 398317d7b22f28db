// Planar loops inside spatial models (issue 11 item 1: "a loop whose revolute axes are all
// parallel (a planar linkage inside a spatial model) is solved with the planar dyads of today, in
// that loop's plane"), a circuit solver (spatial_circuit_solvers.hpp). The circuit's joints are
// all revolutes about axes parallel to one direction n or prismatics normal to it (every body of
// the loop then moves in planes normal to n, whatever the pivots' offsets along n), and exactly
// three of its coordinates are unknown, all revolutes: an RRR dyad. The rigid segments between
// them (with the known joints in them) fix a triangle of pivots whose sides are known, the
// planar generator's circle intersection in the loop's plane (generator/derivation.cpp,
// circle_circle) gives the free vertex, and each angle follows from two in-plane vectors.
#pragma once

#include <optional>

#include "spatial_circuit_solvers.hpp"

namespace mechgen::gen {

// The RRR closed form of `circuit`, or nothing when its geometry is not such a loop. Parallelism
// is recognised at the default parameters (as the limb solvers do: a --set that breaks it leaves
// the circuit open, which the closure residual reports). The branch of the circle intersection is
// the numeric assembly's; Status::unreachable in this group where the circles miss (checked
// before the square root); each angle unwound to its warm start (continuous along a sweep).
std::optional<CircuitClosedForm> planar_loop_closed_form(const CircuitSolverContext& context,
                                                         int circuit);

// Planar loops of imported robots (issue 21 item 4), tried after every other solver so that a
// circuit another solver takes keeps its kernel:
//  - out-of-plane joints held: a loop whose revolutes are parallel to n may also hold unknown
//    coordinates that are not (a five-bar's spherical or universal closure, an oblique revolute)
//    when they are 0 at the assembly and their out-of-plane screws are independent there (the
//    out-of-plane rows then fix them at 0 as long as the loop stays planar): they are held at 0
//    and the rest is the planar loop;
//  - shared pivots: two unknown revolutes on one pivot of the plane with nothing moving between
//    them (a Delta's rod ends on the platform) turn as one about it; three such pivots are a
//    triangle as above, which gives every revolute alone on its pivot (a partial closed form when
//    a pivot holds two: their sum only, the circuit is offered again later).
// The branch and unreachable guard as planar_loop_closed_form.
std::optional<CircuitClosedForm> planar_loop_held_closed_form(const CircuitSolverContext& context,
                                                              int circuit);

// A circuit with one unknown coordinate left, a revolute (the others given by closed forms
// before): its angle from the rotation of the rest of the loop, cos q = u.(R u), sin q = s.(u x R
// u) over u.u with u normal to the axis, unwound to its warm start. No root to choose.
std::optional<CircuitClosedForm> one_angle_closed_form(const CircuitSolverContext& context,
                                                       int circuit);

}  // namespace mechgen::gen
