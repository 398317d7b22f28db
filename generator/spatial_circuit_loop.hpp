// A circuit of a spatial closed chain as a loop of joints (for the circuit solvers,
// spatial_circuit_solvers.hpp): from the tree's lowest common ancestor of the chord's bodies
// down to the chord's first body, the chord, then up from its second body back to the ancestor.
// The product of the joints' displacements in this order, each inverted where the loop runs
// against the joint (second body to first), is the identity at every closed pose.
#pragma once

#include <vector>

#include "model/spatial_graph.hpp"
#include "model/spatial_model.hpp"

namespace mechgen::gen {

// One joint of a circuit in loop order: moving from one body to the next through `joint`,
// forwards (+1: from its first body to its second) or backwards (-1).
struct CircuitStep {
  int joint = -1;
  int direction = 1;
};

std::vector<CircuitStep> circuit_loop(const SpatialModel& model, const SpatialGraph& graph,
                                      int circuit);

}  // namespace mechgen::gen
