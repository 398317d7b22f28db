// Single support as a model of its own (issue 13): a floating-base robot described with pose
// drivers (models/bioloid.yaml) standing on one foot becomes a tree the spatial kernel generator
// takes as it is:
//  - the real bodies and joints are kept; the virtual chains (pose drivers, their massless bodies
//    and joints) are dropped;
//  - the support body is welded to the ground by a fixed joint `<support>_weld` at its pose
//    driver's `at` point, whose reaction is the floor's wrench on the foot;
//  - every real joint coordinate is driven by a driver `<joint>_drive` (`<joint>_<k>_drive` for
//    the k-th coordinate of a multi-coordinate joint), whose effort is the joint's torque (force),
//    signed as the first body's effort on the second; the drivers' own motion is the reference
//    pose (value 0): the whole-body solve feeds the kernel the real angles, rates and
//    accelerations;
//  - the support foot's placement is four parameters (run-time values of the kernel): support_x,
//    support_y, support_z (where its `at` point is, ground frame) and support_heading (its turn
//    about the ground z axis). The whole reference pose is placed with it: every ground-frame
//    vector v of the description becomes Rz(heading) (v - at) + (x, y, z), every direction
//    Rz(heading) d. Gravity stays the world's as written.
// Assumptions: the support foot is flat (its orientation a turn about z, as for a foot on a level
// floor whose normal is z; the runtime checks it) and the robot touches nothing else. Body frames
// rotated at the reference pose must turn about z (the placement then only adds to the angle).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "model/spatial_model.hpp"

namespace mechgen {

// The placement parameters, in this order, appended to the description's own.
inline constexpr const char* kSupportPlacement[4] = {"support_x", "support_y", "support_z",
                                                     "support_heading"};

// `<model>_support_<body>`: the welded model's name, so its kernel's.
std::string support_model_name(const std::string& model, const std::string& support);
// The inverse: {model, body} for a name of that form (the last "_support_" splits it), else
// nullopt. What a compiled-in kernel's name says about the description it comes from.
std::optional<std::pair<std::string, std::string>> split_support_model_name(
    const std::string& name);
// The driver of coordinate k of a real joint (above).
std::string support_driver_name(const SpatialJoint& joint, size_t k);
// The weld's name, `<support>_weld`.
std::string support_weld_name(const std::string& support);

// The welded model. Its description_hash combines the description's with the support body and
// the transformation's version, so a kernel of it is never run for another description or support.
// Throws ModelError (at the description's file) for an unknown or virtual support body, one no
// pose driver places from the ground, a real joint to the ground, a name taken, or a body frame
// rotated about another axis than z.
SpatialModel weld_support(const SpatialModel& model, const std::string& support);

}  // namespace mechgen
