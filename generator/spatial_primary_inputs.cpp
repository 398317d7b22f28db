// The driven coordinates of a spatial model as kernel inputs (spatial_primary_inputs.hpp).
#include "spatial_primary_inputs.hpp"

namespace mechgen::gen {

std::vector<SpatialPrimaryInput> spatial_primary_inputs(const SpatialModel& model,
                                                        const SpatialGraph& graph) {
  std::vector<SpatialPrimaryInput> out;
  for (const SpatialDriver& d : model.drivers)
    out.push_back({d.name, d.name, graph.joint_column[static_cast<size_t>(d.joint)] + d.column,
                   d.value.ex, d.value_d, d.value_dd, 0});
  for (const PoseDriver& pd : model.pose_drivers)
    for (const PoseCoordinate& c : pd.coordinates)
      if (c.value)
        out.push_back({pd.name + "_" + c.name, pd.name + "." + c.name,
                       graph.joint_column[static_cast<size_t>(c.joint)], c.value->ex, c.value_d,
                       c.value_dd, c.reference});
  return out;
}

}  // namespace mechgen::gen
