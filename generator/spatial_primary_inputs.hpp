// The driven (primary) coordinates of a spatial model as kernel inputs: each joint driver, then
// each pose driver's prescribed coordinates, in the order of the sweep's driver columns
// (runtime/spatial/spatial_sweep.cpp). A pose coordinate `x` of pose driver `foot` is the input
// `in.foot_x` (absolute: the position of `at` in first's frame, or the angle), its virtual joint's
// coordinate `in.foot_x - reference`, as the numeric solver's primary motion.
#pragma once

#include <ginac/ginac.h>

#include <string>
#include <vector>

#include "model/spatial_graph.hpp"
#include "model/spatial_model.hpp"

namespace mechgen::gen {

struct SpatialPrimaryInput {
  std::string name;    // C++ identifier: `in.<name>`, `s.drivers.<name>`
  std::string column;  // the sweep's column prefix: "<driver>" or "<pose>.<coordinate>"
  int graph_column = -1;
  GiNaC::ex value, value_d, value_dd;  // in the model's symbols (parameters, t)
  GiNaC::ex reference;                 // subtracted from value to give the coordinate
};

std::vector<SpatialPrimaryInput> spatial_primary_inputs(const SpatialModel& model,
                                                        const SpatialGraph& graph);

}  // namespace mechgen::gen
