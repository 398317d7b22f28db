// The reference solver's Newton-Euler solution: static and dynamic cases by hand, the power balance
// on inline models exercising every joint, driver and load type and on every shipped model, and
// PASIBOT's structure and rigid distances.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "model/spatial_model.hpp"
#include "numeric/reference_solver.hpp"
#include "numeric_test_support.hpp"

namespace mechgen::numeric {
namespace {

using Eigen::Vector2d;
using testing::Columns;
using testing::newton_euler_balance;
using testing::power_balance;

constexpr double g0 = 9.81;

// ------------------------------------------------------------------------------------------------
// A crank held still at th0 (driver value constant): the driver torque balances the weight's
// moment about the pivot, m g (cx cos th0 - cy sin th0), and the pivot carries the weight.
TEST(ReferenceSolverDynamics, CrankHeldStill) {
  const char* yaml = R"(
name: held
parameters:
  m: 2.5
  th0: 0.7
bodies:
  - name: ground
    ground: true
    points: {O: [0, 0]}
  - name: crank
    points: {O: [0, 0], P: [0.3, 0]}
    mass: {mass: m, com: [0.12, 0.04], inertia: 0.02}
    assembly: th0
joints:
  - {name: jO, type: revolute, first: ground, second: crank, point: O}
drivers:
  - {name: hold, joint: jO, kind: angle, value: th0}
step: {t0: 0, t1: 1, samples: 11}
)";
  const Model model = read_model_text(yaml, "held.yaml");
  ReferenceSolver solver(model, model.default_parameters());
  solver.assemble(0);
  const Columns col(model);
  std::vector<double> row;
  for (double t : {0.0, 0.5, 1.0}) {
    ASSERT_EQ(solver.solve(t, row), Status::ok);
    const double m = 2.5, th0 = 0.7;
    const double torque = m * g0 * (0.12 * std::cos(th0) - 0.04 * std::sin(th0));
    EXPECT_NEAR(row[col("hold.effort")], torque, 1e-12 * torque);
    EXPECT_NEAR(row[col("jO.fx")], 0, 1e-12);
    EXPECT_NEAR(row[col("jO.fy")], m * g0, 1e-12 * m * g0);
    EXPECT_NEAR(row[col("hold.qd")], 0, 1e-15);
    EXPECT_NEAR(row[col("crank.ax")], 0, 1e-15);
  }
  ASSERT_EQ(solver.ne_unknowns(), (std::vector<std::string>{"jO.fx", "jO.fy", "hold.effort"}));
  EXPECT_EQ(solver.ne_matrix().rows(), 3);
  // The Newton-Euler system as documented: A x = b holds for the reported unknowns.
  EXPECT_LT((solver.ne_matrix() * solver.ne_solution() - solver.ne_rhs()).norm(), 1e-12);
}

// A pendulum driven along th = th0 + w t + e sin(t): torque about the pivot
// (I_G + m lc^2) al + m g lc cos th, reaction of the ground m (a_G - g) with
// a_G = lc (al perp(u) - w^2 u), u = (cos th, sin th).
TEST(ReferenceSolverDynamics, DrivenPendulum) {
  const char* yaml = R"(
name: pendulum
parameters:
  m: 1.7
  lc: 0.25
  IG: 0.03
bodies:
  - name: ground
    ground: true
    points: {O: [0, 0]}
  - name: arm
    points: {O: [0, 0]}
    mass: {mass: m, com: [lc, 0], inertia: IG}
    assembly: 0.3
joints:
  - {name: pivot, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: motor, joint: pivot, kind: angle, value: 0.3 + 4*t + 0.5*sin(t)}
step: {t0: 0, t1: 1, samples: 11}
)";
  const Model model = read_model_text(yaml, "pendulum.yaml");
  ReferenceSolver solver(model, model.default_parameters());
  solver.assemble(0);
  const Columns col(model);
  std::vector<double> row;
  const double m = 1.7, lc = 0.25, IG = 0.03;
  double worst = 0;
  for (int i = 0; i <= 100; ++i) {
    const double t = 0.03 * i;
    ASSERT_EQ(solver.solve(t, row), Status::ok);
    const double th = 0.3 + 4 * t + 0.5 * std::sin(t), w = 4 + 0.5 * std::cos(t),
                 al = -0.5 * std::sin(t);
    const Vector2d u(std::cos(th), std::sin(th)), n(-u.y(), u.x());
    const Vector2d a_g = lc * (al * n - w * w * u);
    const double torque = (IG + m * lc * lc) * al + m * g0 * lc * std::cos(th);
    const Vector2d reaction = m * (a_g - Vector2d(0, -g0));
    worst = std::max({worst, std::abs(row[col("motor.effort")] - torque) / 5,
                      std::abs(row[col("pivot.fx")] - reaction.x()) / 20,
                      std::abs(row[col("pivot.fy")] - reaction.y()) / 20});
  }
  std::printf("driven pendulum: max relative error of torque and reaction %.2e\n", worst);
  EXPECT_LT(worst, 1e-13);
}

// A block on a horizontal prismatic joint held by a length driver, loaded by a horizontal force at
// an offset point: the driver force cancels the load, the normal reaction carries the weight and
// the joint moment closes the moment balance about the centre of mass.
TEST(ReferenceSolverDynamics, PrismaticBlockHeldStill) {
  const char* yaml = R"(
name: block
parameters:
  m: 3
  F: 7
bodies:
  - name: ground
    ground: true
    points: {O: [0, 0]}
  - name: block
    points: {Q: [0, 0], X: [0.1, 0.2]}
    mass: {mass: m, com: [0.05, 0.03], inertia: 0.01}
joints:
  - {name: rail, type: prismatic, first: ground, second: block, point: Q,
     line: {through: [0, -0.5], direction: [2, 0]}, angle: 0}
drivers:
  - {name: push, joint: rail, kind: length, value: 0.4}
forces:
  - {name: load, type: force, body: block, point: X, value: [F, 0]}
step: {t0: 0, t1: 1, samples: 11}
)";
  const Model model = read_model_text(yaml, "block.yaml");
  ReferenceSolver solver(model, model.default_parameters());
  solver.assemble(0);
  const Columns col(model);
  std::vector<double> row;
  ASSERT_EQ(solver.solve(0.0, row), Status::ok);
  const double m = 3, F = 7;
  EXPECT_NEAR(row[col("block.x")], 0.45, 1e-14);
  EXPECT_NEAR(row[col("block.y")], -0.47, 1e-14);
  EXPECT_NEAR(row[col("push.q")], 0.4, 1e-14);
  EXPECT_NEAR(row[col("push.effort")], -F, 1e-12);
  EXPECT_NEAR(row[col("rail.fx")], 0, 1e-12);
  EXPECT_NEAR(row[col("rail.fy")], m * g0, 1e-12);
  // Moments about G = (0.05, 0.03) (body frame = world directions): the normal force N at Q
  // (rho = (-0.05, -0.03)), the driver force -F along x at Q, the load F at X (rho = (0.05, 0.17)),
  // the joint moment M: -0.05 N - (-0.03)(-F) + (-0.17 F) + M = 0.
  const double N = m * g0;
  const double M = 0.05 * N + 0.03 * F + 0.17 * F;
  EXPECT_NEAR(row[col("rail.m")], M, 1e-12);
}

// ------------------------------------------------------------------------------------------------
// Power balance on an inline mechanism with every joint, driver and load type: an arm pinned to
// the ground with a slot along its axis, a block sliding on an inclined prismatic rail (length
// driver) whose pin runs in the arm's slot; a spring-damper from the ground to the arm, a
// time-varying force on the block, a torque on the arm.
const char* const slotted_yaml = R"(
name: slotted
parameters:
  k: 80
  c: 1.5
bodies:
  - name: ground
    ground: true
    points: {O: [0, 0], G: [-0.1, 0.25]}
  - name: arm
    points: {O: [0, 0], T: [0.3, 0.02]}
    mass: {mass: 0.8, com: [0.15, 0.01], inertia: 0.006}
    assembly: 0.2
  - name: block
    points: {N: [0, 0], H: [0.02, -0.03]}
    mass: {mass: 1.2, com: [0.01, 0.02], inertia: 0.002}
    assembly: 0.1
joints:
  - {name: pivot, type: revolute, first: ground, second: arm, point: O}
  - {name: slot, type: pin_in_slot, first: arm, second: block, point: N,
     line: {through: [0.05, 0], direction: [1, 0]}}
  - {name: rail, type: prismatic, first: ground, second: block, point: N,
     line: {through: [0.25, -0.1], direction: [0.3, 1]}, angle: 0.1}
drivers:
  - {name: stroke, joint: rail, kind: length, value: 0.1 + 0.08*sin(2*t)}
forces:
  - {name: spring, type: spring_damper, first: ground, first_point: G, second: arm,
     second_point: T, stiffness: k, damping: c, free_length: 0.2}
  - {name: push, type: force, body: block, point: H, value: [3*cos(t), -2 + sin(3*t)]}
  - {name: drag, type: torque, body: arm, value: -0.4*cos(2*t)}
step: {t0: 0, t1: 3, samples: 151}
)";

struct BalanceResult {
  double worst = 0;     // power balance: max |residual| / scale
  double worst_ne = 0;  // Newton-Euler balance of each body from the row: max relative residual
  int samples = 0;
};

BalanceResult check_power_balance(const Model& model, const std::vector<double>& parameters,
                                  double t0, double t1, int samples, double* seconds = nullptr) {
  ReferenceSolver solver(model, parameters);
  solver.assemble(t0);
  std::vector<double> row;
  BalanceResult out;
  double solving = 0;
  for (int i = 0; i < samples; ++i) {
    const double t = samples > 1 ? t0 + (t1 - t0) * i / (samples - 1) : t0;
    const auto start = std::chrono::steady_clock::now();
    const Status status = solver.solve(t, row);
    solving += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(status, Status::ok) << model.name << " at t = " << t;
    if (status != Status::ok) break;
    const auto balance = power_balance(model, parameters, row);
    out.worst = std::max(out.worst, std::abs(balance.residual) / balance.scale);
    out.worst_ne = std::max(out.worst_ne, newton_euler_balance(model, parameters, row));
    ++out.samples;
  }
  if (seconds) *seconds = solving;
  return out;
}

TEST(ReferenceSolverDynamics, PowerBalanceWithEveryJointDriverAndLoad) {
  const Model model = read_model_text(slotted_yaml, "slotted.yaml");
  const BalanceResult r = check_power_balance(model, model.default_parameters(), 0, 3, 151);
  std::printf(
      "slotted: worst relative residual of the power balance %.2e, of the bodies' "
      "Newton-Euler balance from the row %.2e, over %d samples\n",
      r.worst, r.worst_ne, r.samples);
  EXPECT_EQ(r.samples, 151);
  EXPECT_LT(r.worst, 1e-8);
  EXPECT_LT(r.worst_ne, 1e-12);
}

// On the same mechanism: the pin-in-slot force is normal to the slot (the arm's axis), and the
// reported Newton-Euler solution satisfies A x = b.
TEST(ReferenceSolverDynamics, PinInSlotForceIsNormalToTheSlot) {
  const Model model = read_model_text(slotted_yaml, "slotted.yaml");
  ReferenceSolver solver(model, model.default_parameters());
  solver.assemble(0);
  const Columns col(model);
  std::vector<double> row;
  for (int i = 0; i <= 20; ++i) {
    ASSERT_EQ(solver.solve(0.1 * i, row), Status::ok);
    const double th = row[col("arm.th")];
    const Vector2d f(row[col("slot.fx")], row[col("slot.fy")]);
    EXPECT_NEAR(f.dot(Vector2d(std::cos(th), std::sin(th))), 0, 1e-12 * (1 + f.norm()));
    EXPECT_LT((solver.ne_matrix() * solver.ne_solution() - solver.ne_rhs()).norm(), 1e-10);
    EXPECT_EQ(solver.ne_unknowns().size(), 6u);
  }
}

std::vector<std::filesystem::path> shipped_models() {
  std::vector<std::filesystem::path> paths;
  const std::filesystem::path dir = std::filesystem::path(MECHGEN_SOURCE_DIR) / "models";
  if (std::filesystem::exists(dir))
    for (const auto& entry : std::filesystem::directory_iterator(dir))
      if (entry.path().extension() == ".yaml" && !is_spatial_description(entry.path()))
        paths.push_back(entry.path());  // planar; spatial ones: spatial_dynamics_test.cpp
  std::sort(paths.begin(), paths.end());
  return paths;
}

TEST(ReferenceSolverDynamics, PowerBalanceOnEveryShippedModel) {
  const auto paths = shipped_models();
  if (paths.empty()) GTEST_SKIP() << "no models/*.yaml yet";
  for (const auto& path : paths) {
    SCOPED_TRACE(path.string());
    const Model model = read_model(path.string());
    const std::vector<double> parameters = model.default_parameters();
    const GiNaC::exmap subs = model.substitutions(parameters);
    const double t0 = model.evaluate(model.step.t0, subs), t1 = model.evaluate(model.step.t1, subs);
    double seconds = 0;
    const BalanceResult r =
        check_power_balance(model, parameters, t0, t1, model.step.samples, &seconds);
    std::printf(
        "%s: worst relative residual of the power balance %.2e, of the bodies' "
        "Newton-Euler balance from the row %.2e, over %d samples; solve %.1f us/sample\n",
        model.name.c_str(), r.worst, r.worst_ne, r.samples, 1e6 * seconds / model.step.samples);
    EXPECT_EQ(r.samples, model.step.samples);
    EXPECT_LT(r.worst, 1e-8);
    EXPECT_LT(r.worst_ne, 1e-10);
  }
}

// ------------------------------------------------------------------------------------------------
// PASIBOT (../shared/pasibot.md from the repository root): 69 Newton-Euler unknowns, the support
// foot fixed, the rigid distances and affine relations of the geometry at every sample of the step.
TEST(ReferenceSolverDynamics, Pasibot) {
  const std::string path = MECHGEN_SOURCE_DIR "/models/pasibot.yaml";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "models/pasibot.yaml not written yet";
  const Model model = read_model(path);
  const std::vector<double> parameters = model.default_parameters();
  const GiNaC::exmap subs = model.substitutions(parameters);
  const double l8 = parameters[static_cast<size_t>(model.parameter_index("l8"))];
  const double t0 = model.evaluate(model.step.t0, subs), t1 = model.evaluate(model.step.t1, subs);
  ReferenceSolver solver(model, parameters);
  solver.assemble(t0);
  EXPECT_EQ(solver.constraint_rank(), 69);
  const Columns col(model);
  std::vector<double> row;
  auto P = [&](const std::string& name) {
    return Vector2d(row[col(name + ".x")], row[col(name + ".y")]);
  };
  const int hip = model.body_index("l13");
  const int samples = model.step.samples;
  double worst = 0;  // units of l8
  std::string worst_what;
  auto check = [&](double got, double want, const std::string& what) {
    const double err = std::abs(got - want) / l8;
    if (!(err <= worst)) {
      worst = err;
      worst_what = what;
    }
  };
  double c_dev = 0, tilt = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < samples; ++i) {
    const double t = t0 + (t1 - t0) * i / (samples - 1);
    ASSERT_EQ(solver.solve(t, row), Status::ok) << "t = " << t;
    ASSERT_EQ(solver.ne_unknowns().size(), 69u);
    ASSERT_EQ(solver.ne_matrix().rows(), 69);
    ASSERT_EQ(solver.ne_matrix().cols(), 69);
    // Support foot: E and F fixed, also as seen from the tibia l2 and the rear bar l11 (whose
    // frames have their origins at E and F).
    const auto& l2 = solver.poses()[model.body_index("l2")];
    const auto& l11 = solver.poses()[model.body_index("l11")];
    check(l2.x, 0, "l2 origin x");
    check(l2.y, 0, "l2 origin y");
    check(l11.x, 4.2 * l8, "l11 origin x");
    check(l11.y, 0, "l11 origin y");
    check(P("E").x(), 0, "E.x");
    check(P("F").x(), 4.2 * l8, "F.x");
    for (const std::string s : {"", "p"}) {  // support and flying leg
      const Vector2d Pp = s.empty() ? P("P") : P("Pp");
      const Vector2d M = P("M" + s), C = P("C" + s), K = P("K" + s), J = P("J" + s);
      const Vector2d L = P("L" + s), E = P("E" + s), S = P("S" + s), R = P("R" + s), F = P("F" + s);
      const Vector2d D = P("D"), B = P("B");
      check((Pp - M).norm(), 2.5 * l8, "|PM|" + s);
      check((B - M).norm(), 2.5 * l8, "|BM|" + s);
      check((D - K).norm(), 6 * l8, "|DK|" + s);
      check((C - K).norm(), 3 * l8, "|CK|" + s);
      check((C - S).norm(), 4.2 * l8, "|CS|" + s);
      check((D - L).norm(), 6 * l8, "|DL|" + s);
      check((E - F).norm(), 4.2 * l8, "|EF|" + s);
      check((R - F).norm(), 18 * l8, "|RF|" + s);
      check((C - (Pp + 2 * (M - Pp))).norm(), 0, "C = P + 2(M - P)" + s);
      check((E - (3 * D - 2 * C)).norm(), 0, "E = 3D - 2C" + s);
      check((J - (C + 3 * (K - C))).norm(), 0, "J = C + 3(K - C)" + s);
      check((L - (J + (E - J) / 3)).norm(), 0, "L = J + (E - J)/3" + s);
      check((R - (S + (J - C))).norm(), 0, "R = S + (J - C)" + s);
      check((F - (R + (E - J))).norm(), 0, "F = R + (E - J)" + s);
    }
    // Hip frame: S and Sp on the slot y = -4 l8; C (support leg) on it within 0.0098 l8.
    const auto& h = solver.poses()[hip];
    const Eigen::Rotation2Dd to_hip(-h.th);
    auto in_hip = [&](const Vector2d& w) { return Vector2d(to_hip * (w - Vector2d(h.x, h.y))); };
    check(in_hip(P("S")).y(), -4 * l8, "S on the slot");
    check(in_hip(P("Sp")).y(), -4 * l8, "Sp on the slot");
    check(in_hip(P("A")).norm(), 0, "A at the hip origin");
    c_dev = std::max(c_dev, std::abs(in_hip(P("C")).y() + 4 * l8) / l8);
    tilt = std::max(tilt, std::abs(h.th));
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "pasibot: worst rigid-distance error %.2e l8 (%s); C off the slot line by at most "
      "%.4f l8; hip tilt at most %.4f rad; %.1f us per sample\n",
      worst, worst_what.c_str(), c_dev, tilt, 1e6 * seconds / samples);
  EXPECT_LT(worst, 1e-12) << worst_what;
  EXPECT_LT(c_dev, 0.0099);
  EXPECT_LT(tilt, 0.003);
}

}  // namespace
}  // namespace mechgen::numeric
