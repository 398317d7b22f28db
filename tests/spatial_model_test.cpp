// The spatial description reader and joint graph: shipped models, Davies' network sizes (down to
// the Bioloid's 24 x 54 with five virtual chains), and located errors for bad input.
#include <gtest/gtest.h>

#include <array>
#include <string>

#include "model/spatial_graph.hpp"
#include "model/spatial_model.hpp"
#include "model/spatial_value_checks.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial_test_models.hpp"

namespace mechgen {
namespace {

std::string error_of(const std::string& text, bool solve = false) {
  try {
    const SpatialModel m = read_spatial_model_text(text, "bad.yaml");
    if (solve) {
      const spatial::SpatialSolver solver(m, {});
      spatial::SpatialState s;
      solver.solve(0, s);
    }
  } catch (const ModelError& e) {
    return e.what();
  }
  return "<accepted>";
}

// A two-link arm on the ground; `extra` is appended to the description.
std::string arm(const std::string& joints, const std::string& drivers) {
  return "name: arm\ndimension: spatial\nparameters: {l: 0.5}\nbodies:\n"
         "  - {name: ground, ground: true, points: {O: [0, 0, 0]}}\n"
         "  - {name: a, points: {P: [l, 0, 0]}, mass: {mass: 1, com: [l/2, 0, 0], inertia: [0.01, "
         "0.02, 0.02]}}\n"
         "  - {name: b, points: {Q: [2*l, 0, 0]}, mass: {mass: 1, com: [1.5*l, 0, 0], inertia: "
         "[0.01, 0.02, 0.02]}}\n"
         "joints:\n" +
         joints + "drivers:\n" + drivers + "step: {t0: 0, t1: 1}\n";
}
const std::string kArmJoints =
    "  - {name: j1, type: revolute, first: ground, second: a, s: [0, 0, 1], s0: O}\n"
    "  - {name: j2, type: revolute, first: a, second: b, s: [0, 1, 0], s0: P}\n";

TEST(SpatialModel, ShippedModelsReadWithTheirNetworkSizes) {
  struct Case {
    const char* model;
    int circuits, cols, primary;
  };
  for (const Case& c :
       {Case{"leg6", 0, 6, 6}, Case{"rsur", 1, 7, 1}, Case{"chebyshev_spatial", 1, 4, 1}}) {
    SCOPED_TRACE(c.model);
    const SpatialModel m =
        read_spatial_model(std::string(MECHGEN_SOURCE_DIR) + "/models/" + c.model + ".yaml");
    EXPECT_TRUE(
        is_spatial_description(std::string(MECHGEN_SOURCE_DIR) + "/models/" + c.model + ".yaml"));
    const SpatialGraph g = build_spatial_graph(m);
    EXPECT_EQ(g.circuits(), c.circuits);
    EXPECT_EQ(g.rows(), 6 * c.circuits);
    EXPECT_EQ(g.cols(), c.cols);
    EXPECT_EQ(static_cast<int>(g.primary.size()), c.primary);
    EXPECT_EQ(static_cast<int>(g.secondary.size()), c.cols - c.primary);
  }
  EXPECT_FALSE(is_spatial_description(MECHGEN_SOURCE_DIR "/models/chebyshev.yaml"));
}

// Issue 27 item 4: the Stewart platform's top is pose-driven; the breadth-first tree would reach it
// through a leg (3 joints) before its virtual chain (6), and the generator would not see it as
// known. The tree goes through the virtual chain: every leg's prismatic closes a circuit and the
// top's tree path holds the six prescribed virtual coordinates only.
TEST(SpatialModel, PrescribedBodiesAreReachedThroughTheirVirtualChains) {
  const SpatialModel m = read_spatial_model(MECHGEN_SOURCE_DIR "/models/stewart.yaml");
  const SpatialGraph g = build_spatial_graph(m);
  const int top = m.body_index("top");
  EXPECT_EQ(m.joints[static_cast<size_t>(g.parent_joint[static_cast<size_t>(top)])].name,
            "pose_rx");
  int on_path = 0;
  for (int c = 0; c < g.cols(); ++c)
    if (g.path_sign[static_cast<size_t>(top)][static_cast<size_t>(c)] != 0) {
      ++on_path;
      EXPECT_TRUE(g.columns[static_cast<size_t>(c)].primary) << column_name(m, g, c);
    }
  EXPECT_EQ(on_path, 6);
  ASSERT_EQ(g.circuits(), 6);
  for (int k = 0; k < 6; ++k)
    EXPECT_EQ(m.joints[static_cast<size_t>(g.chords[static_cast<size_t>(k)])].name,
              "leg" + std::to_string(k + 1));
  // The shipped pose-driven models keep their breadth-first trees (their virtual chains were
  // already on them): the Bioloid's waist, feet and hands hang on their chains.
  const SpatialModel b = read_spatial_model(MECHGEN_SOURCE_DIR "/models/bioloid.yaml");
  const SpatialGraph gb = build_spatial_graph(b);
  for (const char* body : {"waist", "r_foot", "l_foot", "r_hand", "l_hand"})
    EXPECT_TRUE(
        b.joints[static_cast<size_t>(gb.parent_joint[static_cast<size_t>(b.body_index(body))])]
            .is_virtual)
        << body;
}

// Issue 27 item 7: a rod between two spherical joints, written by hand: its spin about the line
// through the centres is idle; the reader makes the second joint universal with both axes normal
// to that line (and to each other) and says so in the model's notes.
TEST(SpatialModel, SphericalSphericalRodsHaveTheirSpinHeld) {
  const SpatialModel m = read_spatial_model(MECHGEN_SOURCE_DIR "/models/delta.yaml");
  ASSERT_EQ(m.notes.size(), 6u);
  EXPECT_NE(m.notes[0].find("link 'rod1a' between spherical joints 'elbow1a' and 'wrist1a': its "
                            "spin about the line through them is idle; fixed"),
            std::string::npos)
      << m.notes[0];
  const GiNaC::exmap subs = m.common.substitutions(m.common.default_parameters());
  auto num = [&](const Vec3Expr& v) {
    return std::array<double, 3>{m.evaluate(v.x, subs), m.evaluate(v.y, subs),
                                 m.evaluate(v.z, subs)};
  };
  auto dot = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  };
  for (const char* rod : {"1a", "1b", "2a", "2b", "3a", "3b"}) {
    SCOPED_TRACE(rod);
    const SpatialJoint& a =
        m.joints[static_cast<size_t>(m.joint_index(std::string("elbow") + rod))];
    const SpatialJoint& b =
        m.joints[static_cast<size_t>(m.joint_index(std::string("wrist") + rod))];
    EXPECT_EQ(a.type, SpatialJointType::spherical);
    ASSERT_EQ(b.type, SpatialJointType::universal);
    ASSERT_EQ(b.columns.size(), 2u);
    const std::array<double, 3> pa = num(a.s0), pb = num(b.s0), s = num(b.s), s2 = num(b.s2);
    const std::array<double, 3> u{pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
    EXPECT_NEAR(dot(s, u), 0, 1e-15);
    EXPECT_NEAR(dot(s2, u), 0, 1e-15);
    EXPECT_NEAR(dot(s, s2), 0, 1e-15);
    EXPECT_NEAR(dot(s, s), 1, 1e-15);
    EXPECT_NEAR(dot(s2, s2), 1, 1e-15);
  }
  // A spherical joint between two rods is not a link of one rod: models without such links keep
  // their spherical joints and have no notes.
  const SpatialModel q = read_spatial_model(MECHGEN_SOURCE_DIR "/models/quadruped_leg.yaml");
  EXPECT_TRUE(q.notes.empty());
  EXPECT_EQ(q.joints[static_cast<size_t>(q.joint_index("coupler_B"))].type,
            SpatialJointType::spherical);
}

TEST(SpatialModel, Leg6FollowsSeedTable1) {
  const SpatialModel m = read_spatial_model(MECHGEN_SOURCE_DIR "/models/leg6.yaml");
  const spatial::SpatialSolver solver(m, {});
  const spatial::SpatialInstance& in = solver.instance();
  // Seed 001 Table 1: yaw z, roll x, pitch y, knee y, ankle pitch y, ankle roll x.
  const spatial::V3 axes[6] = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {1, 0, 0}};
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(in.axes[static_cast<size_t>(k)].s, axes[k]);
    EXPECT_EQ(m.drivers[static_cast<size_t>(k)].name, "q" + std::to_string(k + 1));
    EXPECT_EQ(m.drivers[static_cast<size_t>(k)].joint, k);  // hip to ankle
  }
  // The three hip axes intersect at H; the bar mass is rho pi r^2 l1.
  for (int k = 0; k < 3; ++k) EXPECT_EQ(in.joint_point[static_cast<size_t>(k)], in.joint_point[0]);
  EXPECT_NEAR(in.mass[3], 1200 * M_PI * 0.008 * 0.008 * 0.075, 1e-15);
  // Box foot: Izz = m (a^2 + b^2) / 12.
  const double mf = 400 * 0.1 * 0.06 * 0.01;
  EXPECT_NEAR(in.inertia[6](2, 2), mf * (0.01 + 0.0036) / 12, 1e-15);
  EXPECT_NEAR(in.inertia[1](0, 1), 2e-7, 1e-20);
}

// The shared reader gives spatial models the planar ones' units and derived parameters.
TEST(SpatialModel, UnitsAndDerivedParametersAsInPlanarModels) {
  std::string text = spatial::text_of(MECHGEN_SOURCE_DIR "/models/leg6.yaml");
  text.replace(text.find("l1: {value: 0.075, unit: m,"), 28, "l1: {value: 75, unit: mm,");
  text.replace(text.find("  r: {value: 0.008"), 0, "  l12: {value: l1 + l2, unit: m}\n");
  text.replace(text.find("s0: A}"), 6, "s0: [0, 0, -l12]}");  // ankle pitch through the ankle
  const SpatialModel m = read_spatial_model_text(text, "leg6_mm.yaml");
  const spatial::SpatialSolver solver(m, {});
  EXPECT_DOUBLE_EQ(solver.instance().joint_point[3][2], -0.075);  // the knee, from 75 mm
  EXPECT_DOUBLE_EQ(solver.instance().joint_point[4][2], -0.15);   // l12 = l1 + l2
}

// The seed's humanoid: a floating waist and four 6-DOF limbs, each end (feet, hands) and the
// waist pose-driven by a 3P3R virtual chain from the ground: 4 circuits, N 24 x 54, 30 primary
// virtual coordinates, 24 secondary real ones.
TEST(SpatialModel, HumanoidWithFiveVirtualChainsHasTheSeedsNetworkSize) {
  const std::string text = spatial::humanoid();
  const SpatialModel m = read_spatial_model_text(text, "humanoid.yaml");
  const SpatialGraph g = build_spatial_graph(m);
  EXPECT_EQ(g.circuits(), 4);
  EXPECT_EQ(g.rows(), 24);
  EXPECT_EQ(g.cols(), 54);
  EXPECT_EQ(g.primary.size(), 30u);
  EXPECT_EQ(g.secondary.size(), 24u);
  for (const int c : g.primary) EXPECT_GE(g.columns[static_cast<size_t>(c)].pose_driver, 0);
  for (const int c : g.secondary) EXPECT_LT(g.columns[static_cast<size_t>(c)].pose_driver, 0);
  EXPECT_EQ(m.bodies.size(), 1u + 1 + 24 + 25);  // ground, waist, limbs, virtual bodies
  // It assembles at the reference pose with N_s square and regular (no exception).
  const spatial::SpatialSolver solver(m, {});
  spatial::SpatialState s;
  solver.solve(0, s);
  EXPECT_LT((solver.network(s) * s.qd).norm(), 1e-12);
}

TEST(SpatialModel, ErrorsAreLocatedAndSayWhatToChange) {
  auto is = [](const std::string& error, const std::string& prefix, const std::string& part) {
    return error.rfind(prefix, 0) == 0 && error.find(part) != std::string::npos
               ? testing::AssertionSuccess()
               : testing::AssertionFailure() << error;
  };
  const std::string driven =
      "  - {name: d1, joint: j1, kind: angle, value: t}\n"
      "  - {name: d2, joint: j2, kind: angle, value: t}\n";
  EXPECT_EQ(error_of(arm(kArmJoints, driven), true), "<accepted>");
  // A non-unit and a zero axis, at the axis.
  EXPECT_TRUE(is(error_of(arm("  - {name: j1, type: revolute, first: ground, second: a, s: [0, 0, "
                              "2], s0: O}\n" +
                                  kArmJoints.substr(kArmJoints.find("  - {name: j2")),
                              driven)),
                 "bad.yaml:9:", "has length 2 at the default parameters: give a unit vector"));
  EXPECT_TRUE(is(error_of(arm("  - {name: j1, type: revolute, first: ground, second: a, s: [0, 0, "
                              "0], s0: O}\n" +
                                  kArmJoints.substr(kArmJoints.find("  - {name: j2")),
                              driven)),
                 "bad.yaml:9:", "is zero"));
  // A point named like a body: the CSV would have two `b.x` columns.
  {
    std::string text = arm(kArmJoints, driven);
    text.replace(text.find("{P: [l, 0, 0]}"), 14, "{P: [l, 0, 0], b: [0, 0, 0]}");
    EXPECT_TRUE(is(error_of(text), "bad.yaml:6:", "point 'b' of body 'a' has the name of a body"));
  }
  // A joint of a body to itself: a circuit with no joint.
  EXPECT_TRUE(is(error_of(arm(kArmJoints + "  - {name: j3, type: fixed, first: b, second: b, s0: "
                                           "Q}\n",
                              driven)),
                 "bad.yaml:11:", "to itself"));
  // A rigid circuit through the ground: two fixed joints.
  EXPECT_TRUE(is(error_of("name: m\ndimension: spatial\nbodies:\n  - {name: ground, ground: true}\n"
                          "  - {name: a, mass: {mass: 1, com: [0, 0, 0], inertia: [1, 1, 1]}}\n"
                          "joints:\n  - {name: f1, type: fixed, first: ground, second: a, s0: [0, "
                          "0, 0]}\n  - {name: f2, type: fixed, first: ground, second: a, s0: [1, "
                          "0, 0]}\nstep: {t0: 0, t1: 1}\n"),
                 "bad.yaml:8:", "closes a circuit with no joint coordinate"));
  // Under-determined: j2 not driven (serial chain, no circuit).
  EXPECT_TRUE(
      is(error_of(arm(kArmJoints, "  - {name: d1, joint: j1, kind: angle, value: t}\n"), true),
         "bad.yaml:10:", "under-determined: joint 'j2'"));
  // A pose driver that over-determines: the tip of a 2-DOF arm given x, y and z.
  EXPECT_TRUE(is(error_of(arm(kArmJoints,
                              "  - {name: tip, type: pose, first: ground, second: b, "
                              "at: Q, x: 1, y: 0, z: 0}\n"),
                          true),
                 "bad.yaml:12:", "pose driver 'tip' over-determines the motion"));
  // A pose driver that under-determines: only x of the tip (the other coordinate stays free).
  EXPECT_TRUE(is(error_of(arm(kArmJoints,
                              "  - {name: tip, type: pose, first: ground, second: b, "
                              "at: Q, x: 1}\n"),
                          true),
                 "bad.yaml:", "under-determine"));
  // Two rotations about one axis; a pose driver that prescribes nothing.
  EXPECT_TRUE(is(error_of(arm(kArmJoints,
                              "  - {name: tip, type: pose, first: ground, second: b, "
                              "at: Q, rotations: [{axis: z, value: 0}, {axis: z, "
                              "value: 1}]}\n")),
                 "bad.yaml:12:", "two rotations about z over-determine"));
  EXPECT_TRUE(is(error_of(arm(kArmJoints,
                              "  - {name: tip, type: pose, first: ground, second: b, "
                              "at: Q}\n")),
                 "bad.yaml:12:", "prescribes nothing"));
  // A length driver on a revolute; an unknown joint type.
  EXPECT_TRUE(is(error_of(arm(kArmJoints, "  - {name: d1, joint: j1, kind: length, value: t}\n")),
                 "bad.yaml:12:", "cannot take a length driver"));
  EXPECT_TRUE(
      is(error_of(arm("  - {name: j1, type: ball, first: ground, second: a, s0: O}\n", driven)),
         "bad.yaml:9:", "unknown type 'ball'"));
}

// Issue 28 item 4: a spatial model's masses and inertias are checked as planar ones are, in the
// file and through --set (located at the body's mass, naming the values set).
TEST(SpatialModel, MassesAndInertiasAreCheckedInTheFileAndThroughSet) {
  auto body = [](const std::string& mass) {
    return "name: link\ndimension: spatial\nparameters: {m: 1, Izz: 0.015}\nbodies:\n"
           "  - {name: ground, ground: true, points: {O: [0, 0, 0]}}\n"
           "  - name: a\n    points: {P: [0.5, 0, 0]}\n    mass: " +
           mass +
           "\njoints:\n"
           "  - {name: j1, type: revolute, first: ground, second: a, s: [0, 0, 1], s0: O}\n"
           "drivers:\n  - {name: d1, joint: j1, kind: angle, value: t}\nstep: {t0: 0, t1: 1}\n";
  };
  const std::string good = "{mass: m, com: [0.25, 0, 0], inertia: [0.01, 0.01, Izz]}";
  EXPECT_EQ(error_of(body(good), true), "<accepted>");
  // Principal moments 0.01, 0.01, 0.03: no rigid body has them.
  EXPECT_EQ(error_of(body("{mass: m, com: [0.25, 0, 0], inertia: [0.01, 0.01, 0.03]}")),
            "bad.yaml:8:11: error: body 'a': principal moments 0.01, 0.01, 0.03 kg m^2 violate "
            "the triangle inequality (I1 + I2 >= I3)");
  EXPECT_EQ(error_of(body("{mass: m, com: [0.25, 0, 0], inertia: [[0.01, 0.02, 0], [0.02, 0.01, "
                          "0], [0, 0, 0.015]]}")),
            "bad.yaml:8:11: error: body 'a': the inertia tensor has a negative principal "
            "moment (-0.01 kg m^2)");
  EXPECT_EQ(error_of(body("{mass: 0, com: [0.25, 0, 0], inertia: [0.01, 0.01, 0.01]}")),
            "bad.yaml:8:11: error: body 'a' has no mass but an inertia tensor");
  EXPECT_EQ(error_of(body("{mass: 0, com: [0.25, 0, 0], inertia: [0, 0, 0]}"), true),
            "<accepted>");  // a massless link

  const SpatialModel model = read_spatial_model_text(body(good), "link.yaml");
  auto set_error = [&](const std::vector<std::string>& overrides) -> std::string {
    std::vector<double> values = model.common.default_parameters();
    try {
      apply_overrides(model, overrides, values);
    } catch (const ModelError& e) {
      return e.what();
    }
    return "<accepted>";
  };
  EXPECT_EQ(set_error({"m=2", "Izz=0.019"}), "<accepted>");
  EXPECT_EQ(set_error({"m=-1"}),
            "link.yaml:8:11: error: body 'a' has a negative mass (-1 kg) (with m = -1)");
  EXPECT_EQ(set_error({"Izz=0.5"}),
            "link.yaml:8:11: error: body 'a': principal moments 0.01, 0.01, 0.5 kg m^2 violate "
            "the triangle inequality (I1 + I2 >= I3) (with Izz = 0.5)");
  // A thin rod along z (Izz = 0) and a point mass are rigid bodies; a negative moment is not.
  EXPECT_EQ(set_error({"Izz=0"}), "<accepted>");
  EXPECT_EQ(error_of(body("{mass: m, com: [0.25, 0, 0], inertia: [0, 0, 0]}"), true), "<accepted>");
  EXPECT_EQ(set_error({"Izz=-0.001"}),
            "link.yaml:8:11: error: body 'a': the inertia tensor has a negative principal moment "
            "(-0.001 kg m^2) (with Izz = -0.001)");

  // The cases: a negative mass and a negative density in shipped models.
  const SpatialModel bioloid =
      read_spatial_model(std::string(MECHGEN_SOURCE_DIR) + "/models/bioloid.yaml");
  std::vector<double> values = bioloid.common.default_parameters();
  EXPECT_THROW(apply_overrides(bioloid, {"m_hip2=-1"}, values), ModelError);
  const SpatialModel rsur =
      read_spatial_model(std::string(MECHGEN_SOURCE_DIR) + "/models/rsur.yaml");
  values = rsur.common.default_parameters();
  EXPECT_THROW(apply_overrides(rsur, {"rho=-2700"}, values), ModelError);
  values = rsur.common.default_parameters();
  EXPECT_NO_THROW(apply_overrides(rsur, {"rho=2000"}, values));
}

}  // namespace
}  // namespace mechgen
