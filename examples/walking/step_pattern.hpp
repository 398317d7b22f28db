// The walking lecture's step motion pattern generator and abstract kinematics (seed 003,
// ../shared/seeds/003_*.txt), plain C++17 with <cmath> only, the scalar type a template parameter.
//
// Reading of the lecture's formulas. The phase mu runs over [-pi, pi) once per gait cycle.
//   Leg lifting  eta(mu)            = C1 sin mu (mu < 0),  C2 sin mu (mu >= 0)
//   Leg swing    theta_leg(mu, S)   = S (2 mu + pi) / pi (mu < 0),  S cos mu (mu >= 0)
// eta(mu) vanishes at mu = 0 and mu = -pi, so it cannot be the leg extension of the abstract
// kinematics itself (eta in [0, 1], 1 = stretched): we read it as the change of a nominal
// extension eta0, i.e. extension(mu) = eta0 + eta(mu). With C1 > 0 the leg shortens (the foot
// lifts) for mu < 0, and theta_leg rises linearly from -S to S there: mu < 0 is the swing phase,
// the foot carried forward. For mu >= 0 theta_leg = S cos mu returns from S to -S while the
// extension is eta0 + C2 sin mu: the stance phase, the hip passing over the foot. Touch-down is at
// mu = 0 (leg angle S, in front), lift-off at mu = -pi (leg angle -S, behind); both functions are
// continuous there. The lecture leaves C2 open: C2 = eta0 (cos S - 1) < 0 keeps the hip at the same
// height at touch-down, mid-stance and lift-off (level_stance_c2 below).
// The minimal walking function calls abstractKinematics(eta(mu), theta_leg(mu, S)) without a foot
// angle: theta_foot = 0, the sole stays parallel to the trunk's horizontal.
#pragma once

#include <cmath>

namespace walking {

template <class T>
struct StepPattern {
  T S;     // rad: leg swing amplitude
  T C1;    // leg lifting in the swing phase (shortening of the extension at mid-swing)
  T C2;    // extension change in the stance phase
  T eta0;  // nominal leg extension (hip-ankle distance / 2 l)
};

template <class T>
T level_stance_c2(T S, T eta0) {
  return eta0 * (std::cos(S) - T(1));
}

template <class T>
T pi_value() {
  return T(3.14159265358979323846);
}

// Leg extension eta0 + eta(mu).
template <class T>
T leg_extension(const StepPattern<T>& p, T mu) {
  return p.eta0 + (mu < T(0) ? p.C1 : p.C2) * std::sin(mu);
}

// Leg angle theta_leg(mu, S) (from -y, positive forward).
template <class T>
T leg_angle(const StepPattern<T>& p, T mu) {
  return mu < T(0) ? p.S * (T(2) * mu + pi_value<T>()) / pi_value<T>() : p.S * std::cos(mu);
}

template <class T>
struct Joints {
  T q1, q2, q3;
};

// The lecture's abstract kinematics: q2 = 2 acos(eta), q1 = theta_leg - q2 / 2,
// q3 = theta_foot - theta_leg - q2 / 2.
template <class T>
Joints<T> abstract_kinematics(T eta, T theta_leg, T theta_foot) {
  const T q2 = T(2) * std::acos(eta);
  return {theta_leg - q2 / T(2), q2, theta_foot - theta_leg - q2 / T(2)};
}

}  // namespace walking
