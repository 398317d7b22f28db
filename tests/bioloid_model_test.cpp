// models/bioloid.yaml (issue 13 item 1): the seed's whole-body mechanism (4 circuits, N 24 x 54,
// 30 primary virtual and 24 secondary real joints), the published totals (mass 1.7 kg, height
// 0.397 m, trunk centre of mass from the waist) and the standing motion's closure.
#include <gtest/gtest.h>

#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {
namespace {

TEST(BioloidModel, SeedsNetworkSizeAndSplit) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/bioloid.yaml");
  const SpatialGraph g = build_spatial_graph(model);
  EXPECT_EQ(g.circuits(), 4);
  EXPECT_EQ(g.rows(), 24);
  EXPECT_EQ(g.cols(), 54);
  ASSERT_EQ(g.primary.size(), 30u);
  ASSERT_EQ(g.secondary.size(), 24u);
  for (const int c : g.primary)
    EXPECT_TRUE(
        model.joints[static_cast<size_t>(g.columns[static_cast<size_t>(c)].joint)].is_virtual);
  for (const int c : g.secondary)
    EXPECT_FALSE(
        model.joints[static_cast<size_t>(g.columns[static_cast<size_t>(c)].joint)].is_virtual);
  // Seed: fifty four joints and fifty one links (the inertial frame counted).
  EXPECT_EQ(model.joints.size(), 54u);
  EXPECT_EQ(model.bodies.size(), 51u);
  EXPECT_EQ(model.pose_drivers.size(), 5u);
}

TEST(BioloidModel, PublishedMassHeightAndTrunkCentreOfMass) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/bioloid.yaml");
  const SpatialSolver solver(model, {});
  const SpatialInstance& in = solver.instance();
  double mass = 0;
  for (const double m : in.mass) mass += m;
  EXPECT_NEAR(mass, 1.7, 1e-12);
  const int waist = model.body_index("waist");
  const auto point = [&](int body, const std::string& name) {
    const SpatialBody& b = model.bodies[static_cast<size_t>(body)];
    for (size_t k = 0; k < b.points.size(); ++k)
      if (b.points[k].name == name) return in.points[static_cast<size_t>(body)][k];
    ADD_FAILURE() << "no point " << name;
    return V3{0, 0, 0};
  };
  // Height: the sole (z = 0 at the reference pose) to the top of the head.
  EXPECT_NEAR(point(waist, "head")[2] - point(model.body_index("r_foot"), "RF")[2], 0.397, 1e-15);
  const V3 c = in.com[static_cast<size_t>(waist)] - point(waist, "W");
  EXPECT_NEAR(c[0], 0.014563, 1e-15);
  EXPECT_NEAR(c[1], 0, 1e-15);
  EXPECT_NEAR(c[2], 0.086397, 1e-15);
}

// The model's own motion (standing weight shift): the circuits close, N q' = 0, and the hands'
// poses put the arms at (arm_pitch, 0, elbow) with the three added wrist joints at zero.
TEST(BioloidModel, StandingMotionClosesWithStraightWrists) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/bioloid.yaml");
  const SpatialSolver solver(model, {});
  auto parameter = [&](const std::string& name) {
    for (size_t k = 0; k < model.common.parameters.size(); ++k)
      if (model.common.parameters[k].name == name) return solver.parameters()[k];
    ADD_FAILURE() << name;
    return 0.0;
  };
  SpatialState s;
  for (int k = 0; k <= 8; ++k) {
    solver.solve(0.25 * k, s);
    EXPECT_LT((solver.network(s) * s.qd).norm(), 1e-12);
    for (const char* arm : {"RA", "LA"}) {
      auto q = [&](int i) {
        return s.q[solver.graph().joint_column[static_cast<size_t>(
            model.joint_index(arm + std::to_string(i)))]];
      };
      EXPECT_NEAR(q(1), parameter("arm_pitch"), 1e-12);
      EXPECT_NEAR(q(3), parameter("elbow"), 1e-12);
      for (int i : {2, 4, 5, 6}) EXPECT_NEAR(q(i), 0, 1e-12);
    }
  }
}

// The solver driven by a primary motion given from outside the description (the gait planner's
// way in): moving all five virtual chains by the same translation moves every body by it and
// leaves every real joint where it was.
TEST(BioloidModel, GivenPrimaryMotionTranslatesTheWholeBody) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/bioloid.yaml");
  const SpatialSolver solver(model, {});
  const SpatialGraph& g = solver.graph();
  const double t = 0.3;
  SpatialState a, b;
  solver.solve(t, a);
  Eigen::VectorXd qp, qpd, qpdd;
  solver.primary_motion(t, qp, qpd, qpdd);
  const V3 shift{0.05, -0.02, 0.01};
  for (size_t k = 0; k < g.primary.size(); ++k) {
    const SpatialColumn& c = g.columns[static_cast<size_t>(g.primary[k])];
    const std::string& name = model.pose_drivers[static_cast<size_t>(c.pose_driver)]
                                  .coordinates[static_cast<size_t>(c.pose_coordinate)]
                                  .name;
    if (name.size() == 1)
      qp[static_cast<Eigen::Index>(k)] += shift[static_cast<size_t>(name[0] - 'x')];
  }
  solver.solve(t, qp, qpd, qpdd, b);
  for (const int c : g.secondary) EXPECT_NEAR(b.q[c], a.q[c], 1e-12);
  EXPECT_LT((b.qd - a.qd).norm(), 1e-12);
  for (size_t body = 0; body < model.bodies.size(); ++body) {
    if (static_cast<int>(body) == model.ground || model.bodies[body].is_virtual) continue;
    const V3 d = solver.body_pose(b, static_cast<int>(body)).p -
                 solver.body_pose(a, static_cast<int>(body)).p;
    for (size_t i = 0; i < 3; ++i) EXPECT_NEAR(d[i], shift[i], 1e-12) << model.bodies[body].name;
  }
  EXPECT_THROW(solver.solve(t, qp.head(3), qpd, qpdd, b), std::invalid_argument);
}

}  // namespace
}  // namespace mechgen::spatial
