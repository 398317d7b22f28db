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

}  // namespace mechgen::gen
