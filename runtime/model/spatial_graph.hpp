// The joint graph of a spatial model and Davies' network (seed 001 eqs. 6-9, appendix A): every
// joint coordinate is one column (a revolute 1, a universal 2, a spherical 3, a fixed joint none;
// a pose driver's virtual chain 6), a spanning tree from the ground, one independent circuit per
// chord with 6 rows each, and the split of the columns into primary (driven: joint drivers and
// every prescribed virtual coordinate) and secondary (solved for).
#pragma once

#include <string>
#include <vector>

#include "model/spatial_model.hpp"

namespace mechgen {

struct SpatialColumn {
  int joint = -1;
  int index = 0;             // coordinate within the joint
  int driver = -1;           // a joint driver (SpatialModel::drivers) prescribes it
  int pose_driver = -1;      // a pose driver's virtual coordinate (prescribed or free)
  int pose_coordinate = -1;  // index in PoseDriver::coordinates
  bool primary = false;
};

struct SpatialGraph {
  std::vector<SpatialColumn> columns;  // joints in model order, coordinates in joint order
  std::vector<int> joint_column;       // per joint: its first column
  std::vector<int> parent_joint;       // per body: the tree joint towards the ground (-1: ground)
  std::vector<int> parent;             // per body: the tree parent (-1: ground)
  std::vector<int> order;              // bodies, ground first, each after its parent
  std::vector<int> chords;             // one per independent circuit
  // Per body: the sign (+1, -1 or 0) of each column on the tree path from the ground, so that
  // the body's twist is sum_i sign_i $_i q_i' (seed eq. 4 along the path).
  std::vector<std::vector<int>> path_sign;
  // Per circuit: the sign of each column in the circulation law sum_i sign_i $_i q_i' = 0.
  std::vector<std::vector<int>> circuit_sign;
  std::vector<int> primary, secondary;  // column indices

  int circuits() const { return static_cast<int>(chords.size()); }
  int rows() const { return 6 * circuits(); }
  int cols() const { return static_cast<int>(columns.size()); }
};

// Throws ModelError (at the offending element) for a body not connected to the ground or a
// circuit with no joint coordinate (a loop of fixed joints).
SpatialGraph build_spatial_graph(const SpatialModel& model);

// "hip_yaw", or "hip.q2" for the second coordinate of a multi-coordinate joint.
std::string column_name(const SpatialModel& model, const SpatialGraph& graph, int column);

}  // namespace mechgen
