// mechgen export (issue 21): a spatial model for ROS and MuJoCo users. The joint graph's spanning
// tree (SpatialGraph) becomes the URDF or MJCF tree; each chord closes a loop as the field writes
// it: a spherical chord is a ball closure (Extended URDF `3d`, MJCF `connect`) at its point, any
// other chord is kept as a joint to a massless cut link welded to its second body (`6d`,
// MJCF `weld`). Numbers at the default parameters, in the reference pose.
#pragma once

#include <string>

#include "model/spatial_model.hpp"

namespace mechgen::import {

struct UrdfExport {
  std::string urdf;      // the tree
  std::string closures;  // Extended URDF YAML: closed_loop, type, name_mot
};

// Throws ModelError (at the element) for what the formats cannot hold: pose drivers, helical
// joints, a driver on one coordinate of a multi-coordinate joint.
UrdfExport export_urdf(const SpatialModel& model, const std::string& source);
std::string export_mjcf(const SpatialModel& model, const std::string& source);

}  // namespace mechgen::import
