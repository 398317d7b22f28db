// A walking gait for a humanoid described as seed 001 does (models/bioloid.yaml): the waist and
// the two feet planned as trajectories in the inertial frame and fed to their 3P3R virtual chains
// (the seed's "five collaborative robots"), the hands carried rigidly with the waist; Davies'
// method then gives every real joint at once. The gait is Kajita's 3D linear inverted pendulum
// (LIP) walk with the pendulum's ZMP on the support foot's centre: per step, the centre of mass
//   c(tau) = p + (c0 - p) cosh(w tau) + (c0'/w) sinh(w tau),   w = sqrt(g / z_c),
// periodic and symmetric about the support foot (forward: from -L/2 to +L/2 behind / ahead of
// it; sideways: from the mid-line towards the foot and back), support switching instantly.
// The waist is placed so that the whole-body centre of mass follows c(t) exactly (Newton on the
// waist's translation with the centre-of-mass Jacobian; its velocity and acceleration from the
// same Jacobian, which maps them linearly), starting from c(t) minus the offset of the standing
// pose; the swing foot moves 2 L forward along a quintic (zero velocity and acceleration at lift
// and touch-down) and rises as h 64 u^3 (1 - u)^3. Steady walking: no start and stop phases.
//
// The numeric reference solver does the kinematics here; the generated spatial kernels (issue 11)
// can replace it behind the same primary motion.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {

struct GaitSettings {
  double step_length = 0;   // L, m
  double step_time = 0;     // T, s (single support; switching is instant)
  double swing_height = 0;  // m
  int steps = 0;
};

// Reads step_length, step_time, swing_height and steps from the solver's parameter values.
// Throws ModelError naming a missing parameter.
GaitSettings gait_settings(const SpatialSolver& solver);

class HumanoidGait {
 public:
  // The pose drivers named `waist`, `right_foot`, `left_foot` (e.g. vFB, vRL, vLL); every other
  // pose driver (the hands) moves rigidly with the waist. The standing pose is the model's own
  // at its t0. Throws ModelError for a missing pose driver or parameter.
  HumanoidGait(const SpatialSolver& solver, const GaitSettings& settings,
               const std::string& waist = "vFB", const std::string& right_foot = "vRL",
               const std::string& left_foot = "vLL");

  double duration() const { return settings_.steps * settings_.step_time; }
  // Which foot supports the robot at t: 0 right (even steps), 1 left.
  int support(double t) const;
  int step_index(double t) const;
  // The primary coordinates (graph().primary order) and their rates at t, the waist at c(t) minus
  // the standing offset (solve() then corrects it). Every rotation keeps its standing value (the
  // waist does not turn, so the hands are carried by translation alone).
  void primary_motion(double t, Eigen::VectorXd& q, Eigen::VectorXd& qd,
                      Eigen::VectorXd& qdd) const;
  // Solves the whole body at t with the waist moved so that the centre of mass follows the
  // pendulum (positions to 1e-14 m, velocities and accelerations exactly). Throws ModelError when
  // it cannot be placed so.
  void solve(double t, SpatialState& state) const;
  // The planned pendulum: centre of mass and ZMP (the support foot's centre) at t.
  V3 planned_com(double t) const;
  V3 planned_zmp(double t) const;
  double com_height() const { return zc_; }
  double omega() const { return omega_; }
  const GaitSettings& settings() const { return settings_; }
  int waist_driver() const { return drivers_[0]; }
  int foot_driver(int side) const { return drivers_[1 + side]; }

 private:
  struct Motion {
    V3 p{0, 0, 0}, v{0, 0, 0}, a{0, 0, 0};
  };
  Motion foot(int side, double t) const;  // its `at` point
  Motion com(double t) const;             // the LIP centre of mass
  V3 footprint(int side, int k) const;    // support position of step k on that side

  const SpatialSolver& solver_;
  GaitSettings settings_;
  std::vector<int> drivers_;  // waist, right foot, left foot
  Eigen::VectorXd q0_;        // primary coordinates of the standing pose
  std::vector<V3> at0_;       // per pose driver: its point at the standing pose
  V3 com_offset_{0, 0, 0};    // centre of mass minus the waist point, standing pose
  double zc_ = 0, omega_ = 0;
};

// The whole-body centre of mass of a solved state (real bodies), its velocity and acceleration.
struct CentreOfMass {
  double mass = 0;
  V3 p{0, 0, 0}, v{0, 0, 0}, a{0, 0, 0};
};
CentreOfMass centre_of_mass(const SpatialSolver& solver, const SpatialState& state);
// Its Jacobian: c' = J q_p' (3 x primaries, screw Jacobians of every body's centre of mass).
Eigen::MatrixXd com_jacobian(const SpatialSolver& solver, const SpatialState& state);

}  // namespace mechgen::spatial
