// Structure of a mechanism as a graph of bodies (vertices) and joints (edges): counts that need no
// numbers, checked for every model as it is read.
#pragma once

#include <string>
#include <vector>

#include "model/model.hpp"

namespace mechgen {

struct StructureReport {
  int moving_bodies = 0;
  int constraints = 0;  // scalar joint constraints
  int mobility = 0;     // Gruebler: 3 (bodies - 1) - constraints
  int drivers = 0;
  int loops = 0;         // independent loops: joints - bodies + 1 (connected graph)
  int ne_unknowns = 0;   // joint reactions + driver efforts
  int ne_equations = 0;  // 3 per moving body
};

StructureReport analyze_structure(const Model& model);

// Throws ModelError when the graph is disconnected, a shared point is not a joint, or the driver
// count differs from the mobility.
void check_structure(const Model& model);

}  // namespace mechgen
