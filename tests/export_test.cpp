// mechgen export (issue 21): every shipped spatial model with joint drivers, exported as URDF +
// Extended URDF closures and as MJCF, imported back; driven by the original's motion, the round
// trip places and moves every body as the original does (orientation, centre of mass, twist and
// its rate) and needs the same driver efforts. Models with pose drivers (bioloid, quadruped_leg_
// swing, lecture_leg_ik, lecture_leg_abstract) have no URDF or MJCF form: a located error.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <ostream>
#include <set>
#include <string>

#include "import/import_tree.hpp"
#include "import/model_export.hpp"
#include "model/spatial_model.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"

namespace {

using namespace mechgen;

std::string write(const std::string& name, const std::string& text) {
  const std::string path = testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

SpatialModel round_trip(const SpatialModel& m, bool mjcf) {
  import::Tree tree;
  if (mjcf) {
    tree = import::read_mjcf(write(m.common.name + ".xml", import::export_mjcf(m, "test")));
  } else {
    const import::UrdfExport e = import::export_urdf(m, "test");
    tree = import::read_urdf(write(m.common.name + ".urdf", e.urdf),
                             write(m.common.name + "_closures.yaml", e.closures));
  }
  import::AssemblyReport report;
  import::TreePose pose = import::assemble(tree, report);
  import::hold_free_joints(tree, pose);
  EXPECT_LT(report.initial, 1e-14) << "an exported model is assembled as written";
  return read_spatial_model_text(import::write_model(import::describe(tree, pose)),
                                 m.common.name + ".round_trip.yaml");
}

struct Case {
  const char* model;
  bool mjcf;
};
// Test names and ctest's display of the parameter: the model and the format, not the struct's
// bytes.
void PrintTo(const Case& c, std::ostream* os) {
  *os << c.model << (c.mjcf ? "_mjcf" : "_urdf");
}

class RoundTrip : public testing::TestWithParam<Case> {};

TEST_P(RoundTrip, MovesEveryBodyAsTheOriginal) {
  const SpatialModel m =
      read_spatial_model(std::string(MECHGEN_SOURCE_DIR) + "/models/" + GetParam().model + ".yaml");
  const SpatialModel m2 = round_trip(m, GetParam().mjcf);
  const spatial::SpatialSolver s1(m, {}), s2(m2, {});
  // m2's primary columns from m's: the same driven joints, by name.
  std::vector<int> from;
  for (const int c2 : s2.graph().primary) {
    const std::string& joint =
        m2.joints[static_cast<size_t>(s2.graph().columns[static_cast<size_t>(c2)].joint)].name;
    const int c1 = s1.graph().joint_column[static_cast<size_t>(m.joint_index(joint))];
    const auto at = std::find(s1.graph().primary.begin(), s1.graph().primary.end(), c1);
    ASSERT_NE(at, s1.graph().primary.end()) << joint;
    from.push_back(static_cast<int>(at - s1.graph().primary.begin()));
  }
  const spatial::SpatialSweepOptions step = spatial::default_spatial_sweep(m);
  spatial::SpatialState a, b;
  double worst_pose = 0, worst_rate = 0, worst_effort = 0;
  for (int k = 0; k <= 8; ++k) {
    const double t = step.t0 + (step.t1 - step.t0) * k / 8;
    s1.solve(t, a);
    Eigen::VectorXd q, qd, qdd;
    s1.primary_motion(t, q, qd, qdd);
    Eigen::VectorXd q2(static_cast<long>(from.size())), qd2 = q2, qdd2 = q2;
    for (size_t i = 0; i < from.size(); ++i)
      q2[static_cast<long>(i)] = q[from[i]], qd2[static_cast<long>(i)] = qd[from[i]],
      qdd2[static_cast<long>(i)] = qdd[from[i]];
    s2.solve(t, q2, qd2, qdd2, b);
    for (size_t i = 0; i < m.bodies.size(); ++i) {
      if (m.bodies[i].ground) continue;
      const int j = m2.body_index(m.bodies[i].name);
      ASSERT_GE(j, 0) << m.bodies[i].name;
      const spatial::Pose p1 = s1.body_pose(a, static_cast<int>(i)), p2 = s2.body_pose(b, j);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          worst_pose = std::max(worst_pose, std::abs(p1.R(r, c) - p2.R(r, c)));
      const spatial::V3 c1 = s1.point_position(a, static_cast<int>(i), s1.instance().com[i]);
      const spatial::V3 c2 = s2.point_position(b, j, s2.instance().com[static_cast<size_t>(j)]);
      for (int r = 0; r < 3; ++r)
        worst_pose =
            std::max(worst_pose, std::abs(c1[static_cast<size_t>(r)] - c2[static_cast<size_t>(r)]));
      auto differ = [](const spatial::V3& x, const spatial::V3& y) {
        return std::max({std::abs(x[0] - y[0]), std::abs(x[1] - y[1]), std::abs(x[2] - y[2])});
      };
      const size_t k = static_cast<size_t>(j);
      worst_rate = std::max({worst_rate, differ(a.V[i].w, b.V[k].w), differ(a.V[i].v, b.V[k].v),
                             differ(a.A[i].w, b.A[k].w), differ(a.A[i].v, b.A[k].v)});
    }
    const Eigen::VectorXd e1 = spatial::inverse_dynamics(s1, a).effort;
    const Eigen::VectorXd e2 = spatial::inverse_dynamics(s2, b).effort;
    for (size_t i = 0; i < from.size(); ++i)
      worst_effort = std::max(worst_effort, std::abs(e1[from[i]] - e2[static_cast<long>(i)]) /
                                                std::max(1.0, std::abs(e1[from[i]])));
  }
  EXPECT_LT(worst_pose, 1e-12) << GetParam().model;
  EXPECT_LT(worst_rate, 1e-12) << GetParam().model;
  EXPECT_LT(worst_effort, 1e-12) << GetParam().model;
  std::cout << GetParam().model << (GetParam().mjcf ? " MJCF" : " URDF") << ": pose " << worst_pose
            << ", rates " << worst_rate << ", efforts " << worst_effort << "\n";
}

INSTANTIATE_TEST_SUITE_P(Shipped, RoundTrip,
                         testing::Values(Case{"rsur", false}, Case{"rsur", true},
                                         Case{"chebyshev_spatial", false},
                                         Case{"chebyshev_spatial", true}, Case{"leg6", false},
                                         Case{"leg6", true}, Case{"lecture_leg", false},
                                         Case{"lecture_leg", true}, Case{"quadruped_leg", false},
                                         Case{"quadruped_leg", true}, Case{"bennett", false},
                                         Case{"bennett", true}, Case{"delta", false},
                                         Case{"delta", true}));

// The files carry the drivers' laws and the step (mechgen's additions): `sweep` of the round trip
// writes the original's columns for every body, point and driver (joints: the tree may run a
// joint the other way, which flips its reaction) to 1e-12 of max(1, |value|).
TEST_P(RoundTrip, SweepsAsTheOriginal) {
  const SpatialModel m =
      read_spatial_model(std::string(MECHGEN_SOURCE_DIR) + "/models/" + GetParam().model + ".yaml");
  const SpatialModel m2 = round_trip(m, GetParam().mjcf);
  const spatial::SpatialSweepResult a =
      spatial::run_spatial_sweep(m, spatial::default_spatial_sweep(m));
  const spatial::SpatialSweepResult b =
      spatial::run_spatial_sweep(m2, spatial::default_spatial_sweep(m2));
  ASSERT_EQ(a.rows.size(), b.rows.size());
  std::set<std::string> owners;
  for (const SpatialBody& body : m.bodies) owners.insert(body.name);
  for (const auto& [point, body] : m.named_points()) owners.insert(point);
  for (const SpatialDriver& d : m.drivers) owners.insert(d.name);
  int compared = 0;
  double worst = 0;
  for (size_t c = 0; c < a.columns.size(); ++c) {
    const std::string& name = a.columns[c];
    if (name != "t" && !owners.count(name.substr(0, name.find('.')))) continue;
    const auto at = std::find(b.columns.begin(), b.columns.end(), name);
    ASSERT_NE(at, b.columns.end()) << name;
    const size_t k = static_cast<size_t>(at - b.columns.begin());
    ++compared;
    for (size_t r = 0; r < a.rows.size(); ++r)
      worst = std::max(
          worst, std::abs(a.rows[r][c] - b.rows[r][k]) / std::max(1.0, std::abs(a.rows[r][c])));
  }
  EXPECT_LT(worst, 1e-12) << GetParam().model;
  std::cout << GetParam().model << (GetParam().mjcf ? " MJCF" : " URDF") << ": " << compared
            << " columns x " << a.rows.size() << " samples, worst " << worst << "\n";
}

TEST(Export, PoseDriversHaveNoUrdfForm) {
  const SpatialModel m =
      read_spatial_model(std::string(MECHGEN_SOURCE_DIR) + "/models/bioloid.yaml");
  try {
    import::export_urdf(m, "bioloid.yaml");
    FAIL() << "no error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("pose drivers (virtual chains) have no URDF or MJCF form"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
