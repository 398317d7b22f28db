// The reference solver reports, rather than computes, what has no answer: a hint that does not
// assemble, a mechanism that cannot close, redundant constraints, a statically indeterminate
// system, a driver pushed out of reach.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "numeric/reference_solver.hpp"
#include "numeric_test_support.hpp"

namespace mechgen::numeric {
namespace {

using testing::Columns;

int line_of(const std::string& text, const std::string& needle) {
  const size_t at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
}

std::string four_bar(const std::string& d, const std::string& coupler_hint) {
  return R"(name: fourbar
parameters:
  a: 0.1
  b: 0.35
  c: 0.3
  d: )" + d +
         R"(
bodies:
  - name: ground
    ground: true
    points: {O2: [0, 0], O4: [d, 0]}
  - name: crank
    points: {O2: [0, 0], P: [a, 0]}
    mass: {mass: 0.2, com: [a/2, 0], inertia: 2e-4}
    assembly: 0.4
  - name: coupler
    points: {P: [0, 0], Q: [b, 0]}
    mass: {mass: 0.5, com: [b/2, 0], inertia: 6e-3}
    assembly: )" +
         coupler_hint + R"(
  - name: rocker
    points: {O4: [0, 0], Q: [c, 0]}
    mass: {mass: 0.4, com: [c/2, 0], inertia: 4e-3}
    assembly: 1.8
joints:
  - {name: jO2, type: revolute, first: ground, second: crank, point: O2}
  - {name: jP, type: revolute, first: crank, second: coupler, point: P}
  - {name: jQ, type: revolute, first: coupler, second: rocker, point: Q}
  - {name: jO4, type: revolute, first: ground, second: rocker, point: O4}
drivers:
  - {name: theta, joint: jO2, kind: angle, value: 0.4 + 3*t}
step: {t0: 0, t1: 1, samples: 11}
)";
}

TEST(ReferenceSolverErrors, GoodHintAssembles) {
  const Model model = read_model_text(four_bar("0.4", "0.81"), "fourbar.yaml");
  ReferenceSolver solver(model, model.default_parameters());
  EXPECT_NO_THROW(solver.assemble(0));
  EXPECT_EQ(solver.constraint_rank(), 9);
}

TEST(ReferenceSolverErrors, HintThatDoesNotAssembleIsLocated) {
  const std::string text = four_bar("0.4", "2.5");  // the coupler's real angle is 0.81
  const Model model = read_model_text(text, "fourbar.yaml");
  ReferenceSolver solver(model, model.default_parameters());
  try {
    solver.assemble(0);
    FAIL() << "assembled from a wrong hint";
  } catch (const ModelError& e) {
    EXPECT_EQ(e.where().file, "fourbar.yaml");
    EXPECT_EQ(e.where().line, line_of(text, "assembly: 2.5")) << e.what();
    EXPECT_NE(std::string(e.what()).find("'coupler'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("does not assemble"), std::string::npos) << e.what();
  }
}

TEST(ReferenceSolverErrors, MechanismThatCannotCloseIsReported) {
  // Ground 1.0 but crank + coupler + rocker only 0.75: no configuration exists.
  const Model model = read_model_text(four_bar("1.0", "0"), "open.yaml");
  ReferenceSolver solver(model, model.default_parameters());
  try {
    solver.assemble(0);
    FAIL() << "assembled an impossible four-bar";
  } catch (const ModelError& e) {
    EXPECT_EQ(e.where().file, "open.yaml");
    EXPECT_NE(std::string(e.what()).find("does not assemble"), std::string::npos) << e.what();
  }
  std::vector<double> row;
  EXPECT_THROW(solver.solve(0, row), std::logic_error);
}

TEST(ReferenceSolverErrors, WrongParameterCount) {
  const Model model = read_model_text(four_bar("0.4", "0.81"), "fourbar.yaml");
  EXPECT_THROW(ReferenceSolver(model, {0.1, 0.2}), ModelError);
}

// A parallelogram (crank O1-A, coupler A-B, rocker O2-B, all parallel) with an extra bar O3-C
// parallel to the crank: the classic over-constrained linkage. A free pendulum on Z makes the
// mobility count right (1), so the reader accepts it; the Jacobian has rank 14 of 15.
const char* const parallelogram_yaml = R"(name: parallelogram
bodies:
  - name: ground
    ground: true
    points: {O1: [0, 0], O2: [0.3, 0], O3: [0.15, 0], Z: [-0.2, 0]}
  - name: crank
    points: {O1: [0, 0], A: [0.1, 0]}
    mass: {mass: 0.2, com: [0.05, 0], inertia: 2e-4}
    assembly: 1
  - name: coupler
    points: {A: [0, 0], B: [0.3, 0], C: [0.15, 0]}
    mass: {mass: 0.5, com: [0.15, 0], inertia: 4e-3}
    assembly: 0
  - name: rocker
    points: {O2: [0, 0], B: [0.1, 0]}
    mass: {mass: 0.2, com: [0.05, 0], inertia: 2e-4}
    assembly: 1
  - name: extra
    points: {O3: [0, 0], C: [0.1, 0]}
    mass: {mass: 0.2, com: [0.05, 0], inertia: 2e-4}
    assembly: 1
  - name: pend
    points: {Z: [0, 0], Zt: [0.1, 0]}
    mass: {mass: 0.1, com: [0.1, 0], inertia: 1e-4}
    assembly: -1.5
joints:
  - {name: jO1, type: revolute, first: ground, second: crank, point: O1}
  - {name: jA, type: revolute, first: crank, second: coupler, point: A}
  - {name: jB, type: revolute, first: coupler, second: rocker, point: B}
  - {name: jO2, type: revolute, first: ground, second: rocker, point: O2}
  - {name: jO3, type: revolute, first: ground, second: extra, point: O3}
  - {name: jC, type: revolute, first: coupler, second: extra, point: C}
  - {name: jZ, type: revolute, first: ground, second: pend, point: Z}
drivers:
  - {name: theta, joint: jO1, kind: angle, value: 1 + t}
step: {t0: 0, t1: 1, samples: 11}
)";

TEST(ReferenceSolverErrors, RedundantConstraintsNameTheJoints) {
  const Model model = read_model_text(parallelogram_yaml, "parallelogram.yaml");
  ReferenceSolver solver(model, model.default_parameters());
  try {
    solver.assemble(0);
    FAIL() << "accepted redundant constraints";
  } catch (const ModelError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("rank 14 for 15 equations"), std::string::npos) << what;
    EXPECT_NE(what.find("redundant constraints among joints"), std::string::npos) << what;
    for (const char* joint : {"jA", "jB", "jC", "jO2", "jO3"})
      EXPECT_NE(what.find(joint), std::string::npos) << joint << ": " << what;
    EXPECT_EQ(what.find("jZ"), std::string::npos) << what;  // the pendulum's pin is not redundant
    EXPECT_NE(what.find("motion of bodies pend is not determined"), std::string::npos) << what;
    EXPECT_EQ(e.where().file, "parallelogram.yaml");
    EXPECT_GT(e.where().line, 0);
  }
}

// Without the pendulum (removed after reading: the reader's mobility count would reject the
// over-constrained parallelogram itself), 13 equations bind 12 coordinates. By default that is an
// error; with Options::allow_redundant the kinematics is solved (consistently, by least squares)
// but the dynamics is statically indeterminate (13 reactions and efforts, 12 equations): reported,
// and the effort and force columns are NaN.
TEST(ReferenceSolverErrors, StaticallyIndeterminateIsReportedNotSolved) {
  Model model = read_model_text(parallelogram_yaml, "parallelogram.yaml");
  ASSERT_EQ(model.bodies.back().name, "pend");
  ASSERT_EQ(model.joints.back().name, "jZ");
  model.bodies.pop_back();
  model.joints.pop_back();
  {
    ReferenceSolver solver(model, model.default_parameters());
    EXPECT_THROW(solver.assemble(0), ModelError);
  }
  Options options;
  options.allow_redundant = true;
  ReferenceSolver solver(model, model.default_parameters(), options);
  solver.assemble(0);
  EXPECT_EQ(solver.constraint_rank(), 12);
  EXPECT_EQ(solver.constraint_count(), 13);
  const Columns col(model);
  std::vector<double> row;
  for (double t : {0.0, 0.3, 0.6}) {
    ASSERT_EQ(solver.solve(t, row), Status::singular_dynamics);
    ASSERT_EQ(row.size(), column_names(model).size());
    // Kinematics: the coupler translates, its centre of mass at A + (0.15, 0).
    const double th = 1 + t;
    EXPECT_NEAR(row[col("coupler.th")], 0, 1e-12);
    EXPECT_NEAR(row[col("coupler.x")], 0.1 * std::cos(th) + 0.15, 1e-12);
    EXPECT_NEAR(row[col("coupler.y")], 0.1 * std::sin(th), 1e-12);
    EXPECT_NEAR(row[col("coupler.vx")], -0.1 * std::sin(th), 1e-12);
    EXPECT_NEAR(row[col("coupler.ay")], -0.1 * std::sin(th), 1e-12);
    EXPECT_NEAR(row[col("extra.th")], th, 1e-12);
    // Dynamics: never numbers.
    EXPECT_TRUE(std::isnan(row[col("theta.effort")]));
    for (const Joint& j : model.joints) {
      EXPECT_TRUE(std::isnan(row[col(j.name + ".fx")])) << j.name;
      EXPECT_TRUE(std::isnan(row[col(j.name + ".fy")])) << j.name;
    }
    EXPECT_EQ(solver.ne_unknowns().size(), 13u);
    EXPECT_EQ(solver.ne_matrix().rows(), 12);
  }
}

// A slider-crank driven by its slider, pushed beyond the reach L + r: no configuration exists. The
// sample is reported diverged (NaN but t) and the solver stays on its last configuration.
TEST(ReferenceSolverErrors, DriverOutOfReachDiverges) {
  const char* yaml = R"(name: pushed
bodies:
  - name: ground
    ground: true
    points: {O: [0, 0]}
  - name: crank
    points: {O: [0, 0], P: [0.05, 0]}
    mass: {mass: 0.3, com: [0.025, 0], inertia: 1e-4}
    assembly: 2.03
  - name: rod
    points: {P: [0, 0], Q: [0.18, 0]}
    mass: {mass: 0.5, com: [0.09, 0], inertia: 2e-3}
    assembly: -0.25
  - name: slider
    points: {Q: [0, 0]}
    mass: {mass: 1, com: [0, 0], inertia: 1e-3}
joints:
  - {name: jO, type: revolute, first: ground, second: crank, point: O}
  - {name: jP, type: revolute, first: crank, second: rod, point: P}
  - {name: jQ, type: revolute, first: rod, second: slider, point: Q}
  - {name: slide, type: prismatic, first: ground, second: slider, point: Q,
     line: {through: [0, 0], direction: [1, 0]}, angle: 0}
drivers:
  - {name: stroke, joint: slide, kind: length, value: 0.15 + 0.1*t}
step: {t0: 0, t1: 1, samples: 11}
)";
  const Model model = read_model_text(yaml, "pushed.yaml");
  ReferenceSolver solver(model, model.default_parameters());
  solver.assemble(0);
  const Columns col(model);
  std::vector<double> row;
  ASSERT_EQ(solver.solve(0.2, row), Status::ok);
  EXPECT_NEAR(row[col("slider.x")], 0.17, 1e-13);
  EXPECT_EQ(solver.solve(1.0, row), Status::diverged);  // 0.25 > 0.23
  EXPECT_EQ(row[0], 1.0);
  for (size_t i = 1; i < row.size(); ++i) EXPECT_TRUE(std::isnan(row[i])) << i;
  ASSERT_EQ(solver.solve(0.4, row), Status::ok);
  EXPECT_NEAR(row[col("slider.x")], 0.19, 1e-13);
}

}  // namespace
}  // namespace mechgen::numeric

namespace mechgen::numeric {
namespace {

// A parallelogram four-bar (crank = rocker, coupler = ground) is a change-point mechanism: at crank
// angle 0 all links are collinear, the Jacobian is singular and the parallelogram and
// anti-parallelogram branches cross. A step across it flips the sign of det(Phi_q): reported as a
// branch jump (the previous configuration is kept), never silently continued.
TEST(ReferenceSolverErrors, CrossingAChangePointIsABranchJump) {
  const char* yaml = R"(name: change_point
bodies:
  - name: ground
    ground: true
    points: {O1: [0, 0], O2: [0.3, 0]}
  - name: crank
    points: {O1: [0, 0], A: [0.1, 0]}
    mass: {mass: 0.2, com: [0.05, 0], inertia: 2e-4}
    assembly: -0.3
  - name: coupler
    points: {A: [0, 0], B: [0.3, 0]}
    mass: {mass: 0.5, com: [0.15, 0], inertia: 4e-3}
    assembly: 0
  - name: rocker
    points: {O2: [0, 0], B: [0.1, 0]}
    mass: {mass: 0.2, com: [0.05, 0], inertia: 2e-4}
    assembly: -0.3
joints:
  - {name: jO1, type: revolute, first: ground, second: crank, point: O1}
  - {name: jA, type: revolute, first: crank, second: coupler, point: A}
  - {name: jB, type: revolute, first: coupler, second: rocker, point: B}
  - {name: jO2, type: revolute, first: ground, second: rocker, point: O2}
drivers:
  - {name: theta, joint: jO1, kind: angle, value: -0.3 + t}
step: {t0: 0, t1: 0.6, samples: 13}
)";
  const Model model = read_model_text(yaml, "change_point.yaml");
  ReferenceSolver solver(model, model.default_parameters());
  solver.assemble(0);
  const Columns col(model);
  std::vector<double> row;
  for (double t : {0.1, 0.2, 0.25}) {
    ASSERT_EQ(solver.solve(t, row), Status::ok) << t;
    EXPECT_NEAR(row[col("coupler.th")], 0, 1e-12);  // parallelogram: the coupler translates
    EXPECT_NEAR(row[col("rocker.th")], -0.3 + t, 1e-12);
  }
  EXPECT_EQ(solver.solve(0.35, row), Status::branch_jump);
  EXPECT_EQ(row[0], 0.35);
  EXPECT_TRUE(std::isnan(row[col("rocker.th")]));
  EXPECT_NEAR(solver.poses()[model.body_index("crank")].th, -0.05, 1e-12);  // kept
}

}  // namespace
}  // namespace mechgen::numeric
