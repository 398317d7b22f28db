// Walking, not one step: a model that describes one support phase (its ground body is the support
// foot) is chained over several steps in the world frame, the support foot alternating every step,
// optionally from rest with a motor-speed ramp. Evaluated with the generated kernel, the driver's
// (q, qd, qdd) fed directly.
//
// Assumptions (checked where they can be, else named here):
//  - One driver, running at constant speed in the model's own motion (qdd = 0, qd > 0); the
//    model's step [t0, t1] is one support phase and advances the driver by dq = qd (t1 - t0).
//  - After dq the mechanism repeats with its legs swapped: every body and point X of the flying
//    leg is named X + mirror_suffix (PASIBOT: l1p, Ep, ...), and at driver q + dq it stands where X
//    stands at q (tests/kernel_test.cpp checks PASIBOT's flying leg against its support leg phased
//    by pi). A body without a mirror keeps its own columns; the driver's second body (the crank),
//    whose pins swap, is turned by the driver's advance. A joint's mirror joins the mirrors of its
//    bodies (a body without one stands for itself) at the mirror of its point (or its own point).
//  - The support foot lies flat where it stands: the world frame is the ground body's frame of
//    the first step, and each later support foot's frame is that frame moved along the floor to
//    where the foot landed (translation only: the landing foot is level at the double support).
//  - Applied loads do not depend on the step (the kernel sees the walk's own time t).
#pragma once

#include <string>
#include <vector>

#include "model/model.hpp"

namespace mechgen::analysis {

// The motor-speed ramp from rest: qd = W s(t / T) with the quintic s(u) = 10u^3 - 15u^4 + 6u^5,
// whose first and second derivatives vanish at both ends (the acceleration starts and ends at 0
// without a jump), q = q0 + W T S(u), S(u) = 2.5u^4 - 3u^5 + u^6 (S(1) = 1/2), and
// qdd = (W / T) 30 u^2 (1 - u)^2; constant speed W after the ramp, q = q0 + W (t - T / 2).
// T = 0: constant speed from t = 0.
struct DriverMotion {
  double q, qd, qdd;
};
DriverMotion ramped_motion(double q0, double speed, double ramp_time, double t);

struct WalkOptions {
  std::vector<double> parameters;  // Model::parameters order; empty: the defaults
  int steps = 4;                   // support phases
  double ramp = 0;                 // s: speed ramp from rest; 0 starts at speed
  int samples_per_step = 0;        // time resolution: dt = step time / (this - 1); 0: the model's
  std::string mirror_suffix = "p";
};

struct WalkResult {
  // t, step (0-based), support (0: the model's ground body, 1: its mirror), support.x (world x
  // of the support foot's frame origin); per driver q, qd, qdd, effort; per body of the model,
  // the ground body and its mirror included, x, y, th, vx, vy, w, ax, ay, al (world frame, centre
  // of mass); per named point x, y (world); per joint fx, fy (and m for a prismatic joint), the
  // force of its first body on its second (world axes: the support frames are only translated). At
  // each support change two rows share t: the last of the old support, the first of the new.
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::string support_body, swing_body;  // the model's ground body and its mirror
  std::string hip_body;                  // the driver's first body: the frame carrying the motor
  double step_angle = 0;                 // dq of one step (rad or m)
  double speed = 0;                      // steady driver speed W
  double step_time = 0;                  // steady duration of one step
  std::vector<double> support_x;         // per step: world x of the support foot's frame origin

  int column(const std::string& name) const;  // -1 when absent
};

// Throws ModelError when the model does not fit the assumptions above (several drivers, a
// driver that is not at constant speed, a missing mirror of the ground body or of its points),
// for bad options, when the kernel is not compiled in, and for a sample the kernel cannot
// evaluate.
WalkResult walk(const Model& model, const WalkOptions& options);

}  // namespace mechgen::analysis
