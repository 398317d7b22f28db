// A pose-driven spatial model (inverse kinematics: e.g. a foot on a trajectory) and its twin with
// joint drivers (the actuators: e.g. the cylinders): the twin follows the pose-driven model's
// motion. At each sample the pose-driven model is solved over time (positions, velocities,
// accelerations, exact), each twin driver's joint (found by name in the pose-driven model) gives
// its coordinate, rate and acceleration, the twin is solved at those and its Newton-Euler gives
// the actuator efforts along the motion (seed 002's swing: cylinder lengths, rates,
// accelerations and forces). Numeric reference solver throughout; generated kernels later.
#pragma once

#include <string>
#include <vector>

#include "model/spatial_model.hpp"

namespace mechgen::analysis {

struct FollowOptions {
  std::vector<double> parameters, twin_parameters;  // empty: the defaults
  int samples = 201;                                // over the pose-driven model's step
};

struct FollowResult {
  std::vector<std::string> columns;  // t, then per twin driver: .q .qd .qdd .effort
  std::vector<std::vector<double>> rows;
};

// Throws ModelError when a twin driver's joint is missing from the pose-driven model or a sample
// does not assemble.
FollowResult follow(const SpatialModel& driven, const SpatialModel& twin,
                    const FollowOptions& options);

}  // namespace mechgen::analysis
