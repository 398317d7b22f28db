// Closed-form inverse kinematics of seed 001's 6-DOF leg (Table 1: hip yaw z, roll x, pitch y
// intersecting at the hip H; knee pitch y at K; ankle pitch y and roll x intersecting at the
// ankle A), from the foot's displacement relative to the waist: the seed solved it numerically.
// The derivation is Kajita's (Introduction to Humanoid Robotics, 2014, sec. 2.5): with r the hip
// seen from the ankle in the foot's frame, the knee from the triangle H K A, the ankle roll and
// pitch from r, and the hip's three angles from the remaining rotation
//   R_hip = R_foot R_x(roll_a)^T R_y(knee + pitch_a)^T = R_z(yaw) R_x(roll) R_y(pitch).
// Knee flexion is taken positive (the branch of the model's knee range [0, 2.5]).
#pragma once

#include <array>
#include <string>

#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {

struct LegGeometry {
  std::array<int, 6> joints{};      // hip yaw, roll, pitch, knee, ankle pitch, ankle roll
  int waist = -1, foot = -1;        // the first joint's first body, the last joint's second body
  V3 hip{0, 0, 0}, ankle{0, 0, 0};  // reference pose, ground frame
  double thigh = 0, calf = 0;
  std::string file;  // the model's, for errors
};

// Checks the Table 1 layout (axes z, x, y, y, y, x at the reference pose; hip axes through one
// point, ankle axes through another, a serial chain). Throws ModelError otherwise.
LegGeometry leg_geometry(const SpatialSolver& solver, const std::array<std::string, 6>& joints);

// The six joint coordinates from the bodies' displacements (state.D of the waist and the foot).
// Throws ModelError when the ankle is out of the leg's reach.
std::array<double, 6> leg_inverse_kinematics(const LegGeometry& leg, const Pose& waist,
                                             const Pose& foot);

}  // namespace mechgen::spatial
