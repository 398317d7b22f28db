// mechgen import (issue 21): the four Extended URDF robots of ../shared/robots and two MJCF robots
// written for these tests, each imported, read back as a spatial model and moved by its drivers;
// every body placed by the reference solver is checked against an independent placement: the
// source's own tree (URDF joint origins and axes, loops closed by the import's Newton on the
// tree) and, for MJCF, MuJoCo's compiler and kinematics (mj_kinematics, equality residuals). The
// MJCF exports of the shipped spatial models face the same MuJoCo checks (ExportedMjcf).
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <fstream>
#include <memory>
#include <regex>
#include <string>

#include "import/import_tree.hpp"
#include "import/model_export.hpp"
#include "model/spatial_model.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_solver.hpp"

#ifndef MECHGEN_SHARED_ROBOTS
#error "MECHGEN_SHARED_ROBOTS must name ../shared/robots (tests/CMakeLists.txt)"
#endif

namespace {

using namespace mechgen;
using import::Frame;
using import::Mat3;
using import::Vec3;

struct Imported {
  import::Tree tree;
  import::TreePose pose;
  import::AssemblyReport report;
  import::Description description;
  std::unique_ptr<SpatialModel> model;
};

Imported import_file(const std::string& path, const std::string& closures = "",
                     bool floating = false) {
  Imported r;
  r.tree = path.size() > 4 && path.substr(path.size() - 4) == ".xml"
               ? import::read_mjcf(path)
               : import::read_urdf(path, closures);
  if (floating) import::float_base(r.tree);
  r.pose = import::assemble(r.tree, r.report);
  import::hold_free_joints(r.tree, r.pose);
  r.description = import::describe(r.tree, r.pose, floating);
  r.model = std::make_unique<SpatialModel>(
      read_spatial_model_text(import::write_model(r.description), path + ".yaml"));
  return r;
}

// The tree's loops closed again with each actuated joint moved by `delta` from the assembled pose
// (Newton from that pose: the same assembly branch).
auto tree_at(const Imported& r, const std::vector<double>& delta) -> import::TreePose {
  import::Tree moved = r.tree;
  for (size_t i = 0; i < moved.joints.size(); ++i) {
    import::TreeJoint& j = moved.joints[i];
    if (j.dofs() == 1)
      j.value = r.pose.q[i][0];
    else
      j.start.assign(r.pose.q[i].data(), r.pose.q[i].data() + r.pose.q[i].size());
  }
  for (size_t k = 0; k < moved.actuators.size(); ++k)
    moved.joints[static_cast<size_t>(moved.actuators[k].joint)].value += delta[k];
  auto report = import::AssemblyReport();
  return import::assemble(moved, report);
}
auto tree_at(const Imported& r, double delta) -> import::TreePose {
  return tree_at(r, std::vector<double>(r.tree.actuators.size(), delta));
}

Frame to_frame(const spatial::Pose& pose) {
  Frame f = Frame::Identity();
  for (int i = 0; i < 3; ++i) {
    f.translation()[i] = pose.p[static_cast<size_t>(i)];
    for (int k = 0; k < 3; ++k) f.linear()(i, k) = pose.R(i, k);
  }
  return f;
}

Frame pose_of(const mjtNum* pos, const mjtNum* quat) {
  Frame f = Frame::Identity();
  f.linear() = Eigen::Quaterniond(quat[0], quat[1], quat[2], quat[3]).toRotationMatrix();
  f.translation() = Eigen::Vector3d(pos[0], pos[1], pos[2]);
  return f;
}

// Where MuJoCo's kinematics placed body b.
Frame mujoco_frame(const mjData* data, int b) {
  Frame f = Frame::Identity();
  for (int i = 0; i < 3; ++i) {
    f.translation()[i] = data->xpos[3 * b + i];
    for (int k = 0; k < 3; ++k) f.linear()(i, k) = data->xmat[9 * b + 3 * i + k];
  }
  return f;
}

int link_index(const import::Tree& tree, const std::string& name) {
  for (size_t l = 0; l < tree.links.size(); ++l)
    if (tree.links[l].name == name) return static_cast<int>(l);
  return -1;
}

std::string temp_file(const std::string& name, const std::string& text) {
  const std::string path = testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

// `read` throws an error that starts with `prefix` (FILE:LINE: error: ...); its text returned.
template <class Read>
std::string expect_error(Read read, const std::string& prefix) {
  try {
    read();
  } catch (const import::ImportError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(prefix, 0), 0u) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no error, expected " << prefix;
  return "";
}

class SharedRobot : public testing::TestWithParam<const char*> {};

// Import, then the reference solver along the drivers' motion: every body frame equals the
// source tree's link frame with its loops closed at the same motor angles (positions to 1e-12 m,
// rotation matrices to 1e-12; the Delta 3e-11, below; a rod whose idle spin was fixed: its origin
// only).
TEST_P(SharedRobot, ImportsAndMovesAsTheSourceTree) {
  const std::string dir = std::string(MECHGEN_SHARED_ROBOTS) + "/" + GetParam();
  const Imported r = import_file(dir + "/robot.urdf", dir + "/robot.yaml");
  EXPECT_GT(r.report.initial, 1e-4) << "the source's q = 0 is not assembled";
  EXPECT_LT(r.report.final, 1e-14);
  EXPECT_FALSE(r.tree.closures.empty());

  const spatial::SpatialSolver solver(*r.model, {});
  const double amplitude = 0.05, w = 2 * M_PI;
  // The reference solver stops at a closure residual of 1e-13; the Delta's parallelograms are
  // ill-conditioned enough (redundant planar loops) that this leaves 1.2e-11 in the transmission's
  // orientation, which the tree's Newton (to 1e-15) does not have.
  const double tol = std::string(GetParam()) == "robot_delta" ? 3e-11 : 1e-12;
  spatial::SpatialState state;
  for (const double t : {0.0, 0.05, 0.1, 0.15, 0.2}) {
    solver.solve(t, state);
    const import::TreePose tree = tree_at(r, amplitude * std::sin(w * t));
    for (size_t b = 0; b < r.description.bodies.size(); ++b) {
      const import::Body& body = r.description.bodies[b];
      const int l = link_index(r.tree, body.link);
      ASSERT_GE(l, 0) << body.name;
      const spatial::Pose ours = solver.body_pose(state, static_cast<int>(b));
      const Frame& theirs = tree.link[static_cast<size_t>(l)];
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(ours.p[static_cast<size_t>(k)], theirs.translation()[k], tol)
            << GetParam() << " body " << body.name << " at t = " << t;
      if (body.spin_fixed) continue;
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
          EXPECT_NEAR(ours.R(i, k), theirs.linear()(i, k), tol)
              << GetParam() << " body " << body.name << " at t = " << t;
    }
  }
}

// MuJoCo reads the same URDF (meshes left out; its own URDF parser, no fused static bodies):
// with the source tree's joint angles at our motors' positions (the tree's loops closed by the
// import's Newton), MuJoCo's kinematics places every link our model places (1e-12; the Delta
// 3e-11, above) and the closure frames coincide in MuJoCo's frames too (1e-10).
TEST_P(SharedRobot, MuJoCoPlacesTheUrdfTreeAndItsClosuresClose) {
  const std::string dir = std::string(MECHGEN_SHARED_ROBOTS) + "/" + GetParam();
  const Imported r = import_file(dir + "/robot.urdf", dir + "/robot.yaml");
  std::string text = import::read_text(dir + "/robot.urdf");
  text = std::regex_replace(text, std::regex("<(visual|collision)>[\\s\\S]*?</\\1>"), "");
  const size_t robot = text.find('>', text.find("<robot")) + 1;
  text.insert(robot,
              "<mujoco><compiler fusestatic=\"false\" discardvisual=\"true\" boundmass=\"1e-10\" "
              "boundinertia=\"1e-14\"/></mujoco>");
  const std::string path = temp_file(std::string(GetParam()) + ".urdf", text);
  char error[1000] = "";
  const std::unique_ptr<mjModel, void (*)(mjModel*)> m(
      mj_loadXML(path.c_str(), nullptr, error, sizeof error), mj_deleteModel);
  ASSERT_TRUE(m) << error;
  const std::unique_ptr<mjData, void (*)(mjData*)> data(mj_makeData(m.get()), mj_deleteData);
  const spatial::SpatialSolver solver(*r.model, {});
  const double tol = std::string(GetParam()) == "robot_delta" ? 3e-11 : 1e-12;
  spatial::SpatialState state;
  double worst = 0, worst_effort = 0, largest_effort = 0;
  for (const double t : {0.0, 0.1, 0.2}) {
    solver.solve(t, state);
    const import::TreePose tree = tree_at(r, 0.05 * std::sin(2 * M_PI * t));
    for (size_t i = 0; i < r.tree.joints.size(); ++i) {
      if (r.tree.joints[i].dofs() != 1) continue;
      const int j = mj_name2id(m.get(), mjOBJ_JOINT, r.tree.joints[i].name.c_str());
      ASSERT_GE(j, 0) << r.tree.joints[i].name;
      data->qpos[m->jnt_qposadr[j]] = tree.q[i][0];
    }
    mj_kinematics(m.get(), data.get());
    auto mj_frame = [&](const std::string& link) {
      const int b = mj_name2id(m.get(), mjOBJ_BODY, link.c_str());
      EXPECT_GE(b, 0) << link;
      return mujoco_frame(data.get(), b);
    };
    for (size_t b = 0; b < r.description.bodies.size(); ++b) {
      const import::Body& body = r.description.bodies[b];
      const Frame d = to_frame(state.D[b]);
      std::vector<std::string> links = body.merged;
      links.push_back(body.link);
      for (const std::string& link : links) {
        if (std::find(body.idle_links.begin(), body.idle_links.end(), link) !=
            body.idle_links.end())
          continue;  // a Delta's pin: its spin about its axis is the tree's arbitrary choice
        const Frame ours = d * r.pose.link[static_cast<size_t>(link_index(r.tree, link))];
        const Frame theirs = mj_frame(link);
        worst = std::max(worst, (ours.translation() - theirs.translation()).cwiseAbs().maxCoeff());
        if (!body.spin_fixed)
          worst = std::max(worst, (ours.linear() - theirs.linear()).cwiseAbs().maxCoeff());
      }
    }
    for (const import::Closure& c : r.tree.closures) {
      const Frame a = mj_frame(r.tree.links[static_cast<size_t>(c.link_a)].name) * c.in_a;
      const Frame b = mj_frame(r.tree.links[static_cast<size_t>(c.link_b)].name) * c.in_b;
      EXPECT_LT((a.translation() - b.translation()).norm(), 1e-10) << c.name << " t = " << t;
      if (c.weld) {
        EXPECT_LT((a.linear() - b.linear()).norm(), 1e-10) << c.name << " t = " << t;
      }
    }
    // Statics: our driver efforts at rest under gravity against MuJoCo's bias forces projected
    // on the motors, tau = E^T qfrc_bias, E the tree's joint rates per motor rate (central
    // differences of the tree's assembly, h = 1e-6: E to about 1e-9).
    const size_t na = r.tree.actuators.size();
    Eigen::MatrixXd E = Eigen::MatrixXd::Zero(m->nv, static_cast<long>(na));
    const double h = 1e-6;
    for (size_t k = 0; k < na; ++k) {
      std::vector<double> plus(na, 0.05 * std::sin(2 * M_PI * t)), minus = plus;
      plus[k] += h, minus[k] -= h;
      const import::TreePose tp = tree_at(r, plus), tm = tree_at(r, minus);
      for (size_t i = 0; i < r.tree.joints.size(); ++i)
        if (r.tree.joints[i].dofs() == 1)
          E(m->jnt_dofadr[mj_name2id(m.get(), mjOBJ_JOINT, r.tree.joints[i].name.c_str())],
            static_cast<long>(k)) = (tp.q[i][0] - tm.q[i][0]) / (2 * h);
    }
    mju_zero(data->qvel, m->nv);
    mj_forward(m.get(), data.get());
    const Eigen::VectorXd tau = E.transpose() * Eigen::Map<Eigen::VectorXd>(data->qfrc_bias, m->nv);
    spatial::SpatialState rest = state;
    const long np = static_cast<long>(solver.graph().primary.size());
    solver.rates(rest, Eigen::VectorXd::Zero(np), Eigen::VectorXd::Zero(np));
    const Eigen::VectorXd effort = spatial::inverse_dynamics(solver, rest).effort;
    for (long i = 0; i < np; ++i) {
      const int driver =
          solver.graph()
              .columns[static_cast<size_t>(solver.graph().primary[static_cast<size_t>(i)])]
              .driver;
      const double ours = effort[i], theirs = tau[driver];
      EXPECT_NEAR(ours, theirs, 1e-6 * std::max(1.0, std::abs(theirs)))
          << GetParam() << " driver " << driver << " t = " << t;
      worst_effort = std::max(worst_effort, std::abs(ours - theirs));
      largest_effort = std::max(largest_effort, std::abs(theirs));
    }
  }
  EXPECT_LT(worst, tol) << GetParam();
  std::cout << GetParam() << ": MuJoCo's link frames off ours by " << worst
            << "; static efforts up to " << largest_effort << " N m, off E^T qfrc_bias by "
            << worst_effort << "\n";
}

INSTANTIATE_TEST_SUITE_P(Robots, SharedRobot,
                         testing::Values("5bar_linkage_iso3d", "5bar_linkage_iso6d", "cassie_like",
                                         "robot_delta"));

// What the conversions became, robot by robot (the README's table).
TEST(ImportConversions, ClosuresBecomeJointsAndIdleSpinsAreRemoved) {
  const std::string dir = MECHGEN_SHARED_ROBOTS;
  auto count = [](const import::Description& d, import::JointType type) {
    int n = 0;
    for (const import::Joint& j : d.joints) n += j.type == type;
    return n;
  };
  const Imported iso3d =
      import_file(dir + "/5bar_linkage_iso3d/robot.urdf", dir + "/5bar_linkage_iso3d/robot.yaml");
  EXPECT_EQ(count(iso3d.description, import::JointType::spherical), 1);  // the 3d closure
  EXPECT_EQ(iso3d.description.drivers.size(), 2u);
  const Imported iso6d =
      import_file(dir + "/5bar_linkage_iso6d/robot.urdf", dir + "/5bar_linkage_iso6d/robot.yaml");
  EXPECT_EQ(count(iso6d.description, import::JointType::spherical), 1);  // three revolutes
  EXPECT_EQ(iso6d.description.bodies.size(), iso3d.description.bodies.size());
  const Imported cassie =
      import_file(dir + "/cassie_like/robot.urdf", dir + "/cassie_like/robot.yaml");
  EXPECT_EQ(count(cassie.description, import::JointType::spherical), 2);
  EXPECT_EQ(count(cassie.description, import::JointType::universal), 2);  // the rods' spins
  EXPECT_EQ(cassie.description.drivers.size(), 5u);
  const Imported delta =
      import_file(dir + "/robot_delta/robot.urdf", dir + "/robot_delta/robot.yaml");
  EXPECT_EQ(count(delta.description, import::JointType::revolute), 11);  // 3 coaxial pairs: 1 each
  EXPECT_EQ(delta.description.bodies.size(), 9u);
}

// Re-typed joints (`joint_name` / `joint_type`): the five-bar whose ball is written as three
// revolutes, re-typed as one SPHERICAL joint (the other two FIXED), or as a UJOINT_AB (x then y)
// followed by the third revolute, moves as the original: every body in place (1e-12).
TEST(ImportRetyping, SphericalAndUniversalJointsMoveAsTheirRevolutes) {
  const std::string dir = std::string(MECHGEN_SHARED_ROBOTS) + "/5bar_linkage_iso6d";
  const Imported original = import_file(dir + "/robot.urdf", dir + "/robot.yaml");
  const std::string base =
      "closed_loop: [['closedloop6D_1B', 'closedloop6D_1A']]\ntype: ['6d']\n"
      "name_mot: ['mot2', 'mot1']\n";
  const std::string ball = temp_file(
      "ball.yaml", base +
                       "joint_name: ['part_4_part_6_rev0', 'part_4_part_6_rev1', "
                       "'part_4_part_6_rev2']\njoint_type: ['SPHERICAL', 'FIXED', 'FIXED']\n");
  const std::string cross =
      temp_file("cross.yaml", base +
                                  "joint_name: ['part_4_part_6_rev0', 'part_4_part_6_rev1']\n"
                                  "joint_type: ['UJOINT_AB', 'FIXED']\n");
  // The collection's UJOINT_<axes> (battobot's UJOINT_ZY, UJOINT_YZ): the second and third
  // revolutes (y, then z) as one universal joint about those axes.
  const std::string yz =
      temp_file("yz.yaml", base +
                               "joint_name: ['part_4_part_6_rev1', 'part_4_part_6_rev2']\n"
                               "joint_type: ['UJOINT_YZ', 'FIXED']\n");
  for (const std::string& closures : {ball, cross, yz}) {
    const Imported r = import_file(dir + "/robot.urdf", closures);
    const spatial::SpatialSolver s1(*original.model, {}), s2(*r.model, {});
    spatial::SpatialState a, b;
    for (const double t : {0.0, 0.1, 0.2}) {
      s1.solve(t, a);
      s2.solve(t, b);
      for (size_t i = 0; i < original.description.bodies.size(); ++i) {
        const int j = r.model->body_index(original.model->bodies[i].name);
        ASSERT_GE(j, 0) << original.model->bodies[i].name;
        const spatial::Pose p1 = s1.body_pose(a, static_cast<int>(i)), p2 = s2.body_pose(b, j);
        for (int k = 0; k < 3; ++k) {
          EXPECT_NEAR(p1.p[static_cast<size_t>(k)], p2.p[static_cast<size_t>(k)], 1e-12)
              << closures << " " << original.model->bodies[i].name << " t = " << t;
          for (int c = 0; c < 3; ++c) EXPECT_NEAR(p1.R(k, c), p2.R(k, c), 1e-12);
        }
      }
    }
  }
}

// A universal joint names two different axes.
TEST(ImportRetyping, AUniversalJointOfOneAxisTwiceIsLocated) {
  const std::string dir = std::string(MECHGEN_SHARED_ROBOTS) + "/5bar_linkage_iso6d";
  const std::string closures =
      temp_file("xx.yaml",
                "closed_loop: [['closedloop6D_1B', 'closedloop6D_1A']]\ntype: ['6d']\n"
                "name_mot: ['mot2', 'mot1']\njoint_name: ['part_4_part_6_rev0']\n"
                "joint_type: ['UJOINT_XX']\n");
  expect_error([&] { import::read_urdf(dir + "/robot.urdf", closures); },
               closures + ":5: error: joint_type 'UJOINT_XX': ");
}

// Two assemblies at the same motor position (tests/data/urdf_fourbar.urdf, a planar four-bar whose
// source pose leaves the coupler's tip 5 cm from the rocker's end): the import keeps the one
// Newton-Raphson reaches from the source's coordinates, the nearer, and finds the other from its
// deterministic starts. Closed by a ball, or by a weld to a pinned tip (an over-constrained
// planar loop: 6 rows, 3 redundant), it is the same assembly and the same motion.
TEST(ImportAssemblies, TheOneNearestTheSourceIsKeptAndTheOtherIsFound) {
  const std::string data = std::string(MECHGEN_SOURCE_DIR) + "/tests/data/urdf_fourbar";
  const Imported ball = import_file(data + ".urdf", data + "_ball.yaml");
  const Imported weld = import_file(data + ".urdf", data + "_weld.yaml");
  // The coupler's tip by the circles about the crank pin (0.1, 0), radius 0.3, and the rocker
  // pivot (0.35, -0.2), radius |(0.05, 0.25)|: the intersection on the source's side (y > 0).
  const Eigen::Vector2d pin(0.1, 0), pivot(0.35, -0.2);
  const double r1 = 0.3, r2 = std::hypot(0.05, 0.25), d = (pivot - pin).norm();
  const double a = (r1 * r1 - r2 * r2 + d * d) / (2 * d), h = std::sqrt(r1 * r1 - a * a);
  const Eigen::Vector2d u = (pivot - pin) / d, n(-u.y(), u.x());
  const Eigen::Vector2d near = pin + a * u + h * n, far = pin + a * u - h * n;
  ASSERT_GT(near.y(), 0);
  for (const Imported* r : {&ball, &weld}) {
    EXPECT_EQ(r->report.others, 1);
    EXPECT_EQ(r->report.starts, 16);
    EXPECT_LT(r->report.kept_distance, r->report.other_distance);
    const import::Vec3 tip =
        r->pose.link[static_cast<size_t>(link_index(r->tree, "coupler_tip"))].translation();
    EXPECT_NEAR(tip.x(), near.x(), 1e-12);
    EXPECT_NEAR(tip.y(), near.y(), 1e-12);
    EXPECT_NEAR(tip.z(), 0, 1e-12);
    EXPECT_GT((tip.head<2>() - far).norm(), 0.1);
  }
  const spatial::SpatialSolver s1(*ball.model, {}), s2(*weld.model, {});
  spatial::SpatialState x, y;
  for (const double t : {0.0, 0.1, 0.2, 0.3}) {
    s1.solve(t, x);
    s2.solve(t, y);
    for (const char* body : {"crank", "coupler", "rocker"}) {
      const int i = ball.model->body_index(body), j = weld.model->body_index(body);
      ASSERT_GE(i, 0) << body;
      ASSERT_GE(j, 0) << body;
      const spatial::Pose p1 = s1.body_pose(x, i), p2 = s2.body_pose(y, j);
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(p1.p[static_cast<size_t>(k)], p2.p[static_cast<size_t>(k)], 1e-12)
            << body << " t = " << t;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(p1.R(k, c), p2.R(k, c), 1e-12);
      }
    }
  }
}

// --floating: the base floats, held at its source pose by a pose driver from a new ground; the
// robot then moves exactly as with its base as the ground (every body, 1e-12), with 6 more
// coordinates (the pose driver's virtual chain).
TEST(ImportFloating, APoseDriverHoldsTheBaseWhereTheGroundWas) {
  const std::string dir = std::string(MECHGEN_SHARED_ROBOTS) + "/cassie_like";
  const Imported fixed = import_file(dir + "/robot.urdf", dir + "/robot.yaml");
  const Imported floating = import_file(dir + "/robot.urdf", dir + "/robot.yaml", true);
  ASSERT_EQ(floating.description.pose_drivers.size(), 1u);
  EXPECT_EQ(floating.description.pose_drivers[0].name, "pelvis_pose");
  const spatial::SpatialSolver s1(*fixed.model, {}), s2(*floating.model, {});
  EXPECT_EQ(s2.graph().cols(), s1.graph().cols() + 6);
  spatial::SpatialState a, b;
  for (const double t : {0.0, 0.1, 0.2}) {
    s1.solve(t, a);
    s2.solve(t, b);
    for (size_t i = 0; i < fixed.model->bodies.size(); ++i) {
      const int j = floating.model->body_index(fixed.model->bodies[i].name);
      ASSERT_GE(j, 0) << fixed.model->bodies[i].name;
      const spatial::Pose p1 = s1.body_pose(a, static_cast<int>(i)), p2 = s2.body_pose(b, j);
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(p1.p[static_cast<size_t>(k)], p2.p[static_cast<size_t>(k)], 1e-12);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(p1.R(k, c), p2.R(k, c), 1e-12);
      }
    }
  }
}

TEST(ImportErrors, ALoopThatCannotCloseNamesTheClosureAndTheDistanceLeft) {
  const std::string dir = std::string(MECHGEN_SHARED_ROBOTS) + "/5bar_linkage_iso3d";
  // The five-bar with both motors held has no freedom left: the effector cannot reach the base.
  const std::string closures = temp_file(
      "closures.yaml",
      "closed_loop: [['closedloop3D_1B', 'closedloop3D_1A'],\n"
      "              ['part_1', 'effector']]\ntype: ['3d', '3d']\nname_mot: ['mot2', 'mot1']\n");
  try {
    import_file(dir + "/robot.urdf", closures);
    FAIL() << "no error";
  } catch (const import::ImportError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(closures + ":2: error: closure part_1 - effector cannot close"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("distance left 0."), std::string::npos) << what;
  }
}

// The four-bar welded where it has no pin: three revolutes, one driven, cannot close it.
TEST(ImportErrors, AnUnclosableWeldNamesItsClosureAndWhatItLeaves) {
  const std::string data = std::string(MECHGEN_SOURCE_DIR) + "/tests/data/urdf_fourbar";
  const std::string what = expect_error(
      [&] { import_file(data + ".urdf", data + "_unclosable.yaml"); },
      data +
          "_unclosable.yaml:3: error: closure coupler_tip - rocker_end cannot close with the "
          "actuated joints at their source values: distance left 0.0");
  EXPECT_NE(what.find("angle left 0.0"), std::string::npos) << what;
}

TEST(ImportErrors, BadFilesAreLocated) {
  const std::string dir = std::string(MECHGEN_SHARED_ROBOTS) + "/5bar_linkage_iso3d";
  const std::string closures =
      temp_file("bad.yaml", "closed_loop: [['closedloop3D_1B', 'nowhere']]\ntype: ['3d']\n");
  EXPECT_THROW(
      {
        try {
          import::read_urdf(dir + "/robot.urdf", closures);
        } catch (const import::ImportError& e) {
          EXPECT_EQ(std::string(e.what()),
                    closures +
                        ":1: error: closure frame 'nowhere' is neither a link nor a joint "
                        "of " +
                        dir + "/robot.urdf");
          throw;
        }
      },
      import::ImportError);
  const std::string urdf = temp_file("bad.urdf", "<robot name='r'><link name='a'/>\n<joint");
  EXPECT_THROW(import::read_urdf(urdf, ""), import::ImportError);
  // A link named twice (as one of the collection's robots has it): at the second one.
  const std::string twice =
      temp_file("twice.urdf",
                "<robot name='r'>\n<link name='a'/>\n<link name='foot'/>\n<link name='b'/>\n"
                "<link name='foot'/>\n<joint name='j' type='fixed'><parent link='a'/>"
                "<child link='foot'/></joint>\n</robot>\n");
  expect_error([&] { import::read_urdf(twice, ""); }, twice + ":5: error: not a valid URDF");
  const std::string mjcf = temp_file("bad.xml",
                                     "<mujoco>\n<worldbody>\n<body><joint type='x'/>"
                                     "</body></worldbody></mujoco>");
  try {
    import::read_mjcf(mjcf);
    FAIL() << "no error";
  } catch (const import::ImportError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(mjcf + ":3: error: MuJoCo cannot compile", 0), 0u)
        << e.what();
  }
}

// MuJoCo against us, per MuJoCo body: the body of ours that carries it and its frame at our
// reference pose (ground frame). The world (MuJoCo body 0) is our ground.
struct MuJoCoBodies {
  std::vector<int> ours;
  std::vector<Frame> reference;
};

// The worst differences met over the samples (a body's position, m, or rotation matrix entry).
struct MuJoCoAgreement {
  double pose = 0, efc_pos = 0, rate = 0, effort = 0, largest_effort = 0;
};

using MuJoCoModel = std::unique_ptr<mjModel, void (*)(mjModel*)>;
using MuJoCoData = std::unique_ptr<mjData, void (*)(mjData*)>;

MuJoCoModel load_mujoco(const std::string& path) {
  char error[1000] = "";
  MuJoCoModel m(mj_loadXML(path.c_str(), nullptr, error, sizeof error), mj_deleteModel);
  EXPECT_TRUE(m) << error;
  return m;
}

Vec3 column(const mjtNum* v) {
  return Vec3(v[0], v[1], v[2]);
}

// The coordinates of body b's joints carrying it from `from` (its parent's frame times its rest
// pose) to `to`, as mj_kinematics runs them: each joint in the frame the earlier ones leave, a
// hinge about its anchor. The hinges split the relative rotation (one: its angle about its axis;
// two, a universal: the first turns the second's axis to where the rotation takes it, the second
// turns the rest), a ball takes it whole; then the slides take the translation left, linear in
// them once the rotations are set.
void set_joints(const mjModel* m, int b, const Frame& from, const Frame& to, mjtNum* qpos) {
  const Frame target = from.inverse() * to;
  const int j0 = m->body_jntadr[b], nj = m->body_jntnum[b];
  std::vector<int> hinges, slides;
  for (int j = j0; j < j0 + nj; ++j) {
    const int qa = m->jnt_qposadr[j];
    if (m->jnt_type[j] == mjJNT_HINGE) {
      hinges.push_back(j);
    } else if (m->jnt_type[j] == mjJNT_SLIDE) {
      slides.push_back(j);
    } else if (m->jnt_type[j] == mjJNT_BALL) {
      ASSERT_EQ(nj, 1) << "a ball and other joints in body " << m->names + m->name_bodyadr[b];
      const Eigen::Quaterniond q(target.linear());
      qpos[qa] = q.w(), qpos[qa + 1] = q.x(), qpos[qa + 2] = q.y(), qpos[qa + 3] = q.z();
      return;
    } else {
      FAIL() << "joint type " << m->jnt_type[j] << " in body " << m->names + m->name_bodyadr[b];
    }
  }
  ASSERT_LE(hinges.size(), 2u) << m->names + m->name_bodyadr[b];
  auto axis = [&](int j) { return column(m->jnt_axis + 3 * j); };  // body frame, unit
  const Mat3& rotation = target.linear();
  std::vector<double> angle;
  if (hinges.size() == 1) {
    const Eigen::AngleAxisd turn(rotation);
    angle = {turn.angle() * turn.axis().dot(axis(hinges[0]))};
  } else if (hinges.size() == 2) {
    const Vec3 a1 = axis(hinges[0]), a2 = axis(hinges[1]), moved = rotation * a2;
    const Vec3 before = a2 - a1.dot(a2) * a1, after = moved - a1.dot(moved) * a1;
    const double first = std::atan2(a1.dot(before.cross(after)), before.dot(after));
    const Eigen::AngleAxisd rest(Eigen::AngleAxisd(first, a1).toRotationMatrix().transpose() *
                                 rotation);
    angle = {first, rest.angle() * rest.axis().dot(a2)};
  }
  // The origin with the slides at qpos0, and each slide's direction (fixed by the hinges before).
  Mat3 R = Mat3::Identity();
  Vec3 origin = Vec3::Zero();
  Eigen::MatrixXd direction(3, static_cast<long>(slides.size()));
  size_t hinge = 0, slide = 0;
  for (int j = j0; j < j0 + nj; ++j) {
    const Vec3 at = column(m->jnt_pos + 3 * j);
    if (m->jnt_type[j] == mjJNT_SLIDE) {
      direction.col(static_cast<long>(slide++)) = R * axis(j);
      continue;
    }
    const Vec3 anchor = R * at + origin;
    R = R * Eigen::AngleAxisd(angle[hinge++], axis(j)).toRotationMatrix();
    origin = anchor - R * at;
  }
  for (size_t k = 0; k < hinges.size(); ++k) {
    const int qa = m->jnt_qposadr[hinges[k]];
    qpos[qa] = m->qpos0[qa] + angle[k];
  }
  if (slides.empty()) return;
  const Eigen::VectorXd travel =
      direction.colPivHouseholderQr().solve(target.translation() - origin);
  for (size_t k = 0; k < slides.size(); ++k) {
    const int qa = m->jnt_qposadr[slides[k]];
    qpos[qa] = m->qpos0[qa] + travel[static_cast<long>(k)];
  }
}

// MuJoCo's qpos from our body frames, then MuJoCo's own kinematics places every body as ours
// (1e-12) and its equality constraints hold (efc_pos, 1e-10); its constraint Jacobian annihilates
// our velocity map on the loop rows (efc_J E = 0, 1e-10); our static driver efforts under gravity
// are E^T qfrc_bias (1e-9 of max(1, |effort|)).
void expect_mujoco_agrees(const std::string& label, mjModel* m,
                          const spatial::SpatialSolver& solver, const MuJoCoBodies& bodies,
                          MuJoCoAgreement& worst) {
  m->opt.jacobian = mjJAC_DENSE;  // efc_J as a dense nefc x nv matrix
  const MuJoCoData data(mj_makeData(m), mj_deleteData);
  spatial::SpatialState state;
  for (const double t : {0.0, 0.07, 0.19}) {
    solver.solve(t, state);
    std::vector<Frame> frame(static_cast<size_t>(m->nbody), Frame::Identity());
    for (int b = 1; b < m->nbody; ++b)
      frame[static_cast<size_t>(b)] =
          to_frame(state.D[static_cast<size_t>(bodies.ours[static_cast<size_t>(b)])]) *
          bodies.reference[static_cast<size_t>(b)];
    // qpos: each body's joints from its parent frame (MuJoCo: body_pos, body_quat, then the
    // joints).
    for (int b = 1; b < m->nbody; ++b) {
      const Frame rest = pose_of(m->body_pos + 3 * b, m->body_quat + 4 * b);
      set_joints(m, b, frame[static_cast<size_t>(m->body_parentid[b])] * rest,
                 frame[static_cast<size_t>(b)], data->qpos);
      if (testing::Test::HasFatalFailure()) return;
    }
    mj_forward(m, data.get());
    for (int b = 1; b < m->nbody; ++b)
      for (int i = 0; i < 3; ++i) {
        const double off =
            std::abs(data->xpos[3 * b + i] - frame[static_cast<size_t>(b)].translation()[i]);
        EXPECT_LT(off, 1e-12) << label << " body " << m->names + m->name_bodyadr[b] << " t = " << t;
        worst.pose = std::max(worst.pose, off);
        for (int k = 0; k < 3; ++k) {
          const double turned = std::abs(data->xmat[9 * b + 3 * i + k] -
                                         frame[static_cast<size_t>(b)].linear()(i, k));
          EXPECT_LT(turned, 1e-12)
              << label << " body " << m->names + m->name_bodyadr[b] << " t = " << t;
          worst.pose = std::max(worst.pose, turned);
        }
      }
    int rows = 0, expected_rows = 0;
    for (int e = 0; e < m->neq; ++e) expected_rows += m->eq_type[e] == mjEQ_WELD ? 6 : 3;
    for (int i = 0; i < data->nefc; ++i)
      if (data->efc_type[i] == mjCNSTR_EQUALITY) {
        ++rows;
        EXPECT_LT(std::abs(data->efc_pos[i]), 1e-10) << label << " t = " << t;
        worst.efc_pos = std::max(worst.efc_pos, std::abs(data->efc_pos[i]));
      }
    EXPECT_EQ(rows, expected_rows) << label;

    // Rates: E, MuJoCo's qvel per unit rate of each driver, from our body twists: each body's
    // twist on its parent's (about its origin) in the span of its joints' motions (a hinge: about
    // its axis through its anchor; a slide: along it; a ball: about the body's axes, MuJoCo's
    // ball rates being in the body's frame). MuJoCo's constraint Jacobian annihilates every column
    // on the loop rows: efc_J E = 0.
    const long np = static_cast<long>(solver.graph().primary.size());
    Eigen::MatrixXd E = Eigen::MatrixXd::Zero(m->nv, np);
    for (long i = 0; i < np; ++i) {
      spatial::SpatialState s = state;
      solver.rates(s, Eigen::VectorXd::Unit(np, i), Eigen::VectorXd::Zero(np));
      for (int b = 1; b < m->nbody; ++b) {
        if (m->body_dofnum[b] == 0) continue;
        const Vec3 x = frame[static_cast<size_t>(b)].translation();
        auto twist = [&](int body) -> Eigen::Matrix<double, 6, 1> {
          Eigen::Matrix<double, 6, 1> V = Eigen::Matrix<double, 6, 1>::Zero();
          if (body == 0) return V;
          const spatial::Twist& T =
              s.V[static_cast<size_t>(bodies.ours[static_cast<size_t>(body)])];
          const Vec3 w(T.w.data());
          V << w, Vec3(T.v.data()) + w.cross(x);
          return V;
        };
        const Eigen::Matrix<double, 6, 1> relative = twist(b) - twist(m->body_parentid[b]);
        Eigen::MatrixXd motion(6, m->body_dofnum[b]);
        for (int j = m->body_jntadr[b]; j < m->body_jntadr[b] + m->body_jntnum[b]; ++j) {
          const long d = m->jnt_dofadr[j] - m->body_dofadr[b];
          const Vec3 anchor = column(data->xanchor + 3 * j), axis = column(data->xaxis + 3 * j);
          if (m->jnt_type[j] == mjJNT_SLIDE)
            motion.col(d) << Vec3::Zero(), axis;
          else if (m->jnt_type[j] == mjJNT_HINGE)
            motion.col(d) << axis, axis.cross(x - anchor);
          else
            for (long c = 0; c < 3; ++c) {
              const Vec3 body_axis = frame[static_cast<size_t>(b)].linear().col(c);
              motion.col(d + c) << body_axis, body_axis.cross(x - anchor);
            }
        }
        const Eigen::VectorXd rates = motion.colPivHouseholderQr().solve(relative);
        EXPECT_LT((motion * rates - relative).cwiseAbs().maxCoeff(), 1e-10)
            << label << " body " << m->names + m->name_bodyadr[b]
            << ": our twist is not a motion of its MuJoCo joints, t = " << t;
        E.block(m->body_dofadr[b], i, m->body_dofnum[b], 1) = rates;
      }
    }
    for (int r = 0; r < data->nefc; ++r)
      if (data->efc_type[r] == mjCNSTR_EQUALITY)
        for (long i = 0; i < np; ++i) {
          double v = 0;
          for (int k = 0; k < m->nv; ++k) v += data->efc_J[r * m->nv + k] * E(k, i);
          EXPECT_LT(std::abs(v), 1e-10) << label << " efc_J E, row " << r << ", t = " << t;
          worst.rate = std::max(worst.rate, std::abs(v));
        }
    // Statics: our driver efforts at rest under gravity equal MuJoCo's bias forces projected on
    // the drivers (tau = E^T qfrc_bias: the constraint forces do no work along E).
    spatial::SpatialState rest = state;
    solver.rates(rest, Eigen::VectorXd::Zero(np), Eigen::VectorXd::Zero(np));
    const Eigen::VectorXd effort = spatial::inverse_dynamics(solver, rest).effort;
    mju_zero(data->qvel, m->nv);
    mj_forward(m, data.get());
    const Eigen::VectorXd tau = E.transpose() * Eigen::Map<Eigen::VectorXd>(data->qfrc_bias, m->nv);
    for (long i = 0; i < np; ++i) {
      EXPECT_NEAR(effort[i], tau[i], 1e-9 * std::max(1.0, std::abs(tau[i])))
          << label << " driver " << i << ", t = " << t;
      worst.effort = std::max(worst.effort, std::abs(effort[i] - tau[i]));
      worst.largest_effort = std::max(worst.largest_effort, std::abs(tau[i]));
    }
  }
  std::cout << label << ": MuJoCo's bodies off ours by " << worst.pose << ", efc_pos up to "
            << worst.efc_pos << ", efc_J E up to " << worst.rate << "; static efforts up to "
            << worst.largest_effort << " N m, off MuJoCo's E^T qfrc_bias by " << worst.effort
            << "\n";
}

// MJCF robots (tests/data: a four-bar cut by a connect; a Cassie-style leg; a rocker pushed by an
// S-P-S linear actuator, whose idle spin the import removes) imported, against MuJoCo on the same
// file (expect_mujoco_agrees). Their keyframes leave the loops open: the import closes them.
class MjcfRobot : public testing::TestWithParam<const char*> {};

TEST_P(MjcfRobot, MuJoCoPlacesEveryBodyAsWeDoAndItsConstraintsHold) {
  const std::string path = std::string(MECHGEN_SOURCE_DIR) + "/tests/data/" + GetParam();
  const Imported r = import_file(path);
  EXPECT_LT(r.report.final, 1e-14);
  EXPECT_GT(r.report.initial, 1e-3) << "the keyframe leaves the loops open";
  if (std::string(GetParam()) == "mjcf_cassie_leg.xml") {  // the knee spring, the toe flap
    const std::string notes = [&] {
      std::string all;
      for (const std::string& n : r.description.notes) all += n + "\n";
      return all;
    }();
    EXPECT_NE(notes.find("joint knee_spring (stiffness 1500.000000) kept rigid"), std::string::npos)
        << notes;
    EXPECT_NE(notes.find("joint flap is neither actuated nor in a loop: held"), std::string::npos)
        << notes;
  }
  const MuJoCoModel m = load_mujoco(path);
  ASSERT_TRUE(m);
  // Every MuJoCo body is the link of its name, carried by the body of ours it became.
  MuJoCoBodies bodies{std::vector<int>(static_cast<size_t>(m->nbody), -1),
                      std::vector<Frame>(static_cast<size_t>(m->nbody), Frame::Identity())};
  for (int b = 1; b < m->nbody; ++b) {
    const std::string name = m->names + m->name_bodyadr[b];
    const int l = link_index(r.tree, name);
    ASSERT_GE(l, 0) << name;
    int& ours = bodies.ours[static_cast<size_t>(b)];
    for (size_t k = 0; k < r.description.bodies.size(); ++k) {
      const import::Body& body = r.description.bodies[k];
      if (body.link == name ||
          std::find(body.merged.begin(), body.merged.end(), name) != body.merged.end())
        ours = static_cast<int>(k);
    }
    ASSERT_GE(ours, 0) << name;
    bodies.reference[static_cast<size_t>(b)] = r.pose.link[static_cast<size_t>(l)];
  }
  MuJoCoAgreement worst;
  expect_mujoco_agrees(GetParam(), m.get(), spatial::SpatialSolver(*r.model, {}), bodies, worst);
}

INSTANTIATE_TEST_SUITE_P(Robots, MjcfRobot,
                         testing::Values("mjcf_fourbar.xml", "mjcf_cassie_leg.xml",
                                         "mjcf_sps_rocker.xml"));

// `mechgen export --mjcf` of every shipped spatial model with joint drivers (pose drivers have no
// MJCF form) against MuJoCo (expect_mujoco_agrees), compared with the ORIGINAL model, not its
// re-import (the round trip, export_test.cpp, compares those). An export is assembled as written.
// Every MuJoCo body is the model's body of its name, or a chord's cut link welded to one: carried
// by that body, from where MuJoCo places it at qpos0 (where the weld takes its relative pose).
class ExportedMjcf : public testing::TestWithParam<const char*> {};

// The checks on a model's MJCF export (`label` names it in messages).
void expect_export_agrees(const std::string& label, const SpatialModel& model,
                          const std::string& source) {
  const std::string path = temp_file(label + "_export.xml", import::export_mjcf(model, source));
  const MuJoCoModel m = load_mujoco(path);
  ASSERT_TRUE(m);
  const spatial::SpatialSolver solver(model, {});
  const MuJoCoData at_qpos0(mj_makeData(m.get()), mj_deleteData);
  mj_kinematics(m.get(), at_qpos0.get());
  MuJoCoBodies bodies{std::vector<int>(static_cast<size_t>(m->nbody), -1),
                      std::vector<Frame>(static_cast<size_t>(m->nbody), Frame::Identity())};
  int cut_links = 0;
  for (int b = 1; b < m->nbody; ++b) {
    const std::string name = m->names + m->name_bodyadr[b];
    int& ours = bodies.ours[static_cast<size_t>(b)];
    ours = model.body_index(name);
    if (ours >= 0) {
      bodies.reference[static_cast<size_t>(b)] =
          to_frame(solver.instance().body_frame[static_cast<size_t>(ours)]);
      continue;
    }
    for (int e = 0; e < m->neq; ++e)
      if (m->eq_type[e] == mjEQ_WELD && m->eq_obj1id[e] == b)
        ours = model.body_index(m->names + m->name_bodyadr[m->eq_obj2id[e]]);
    ASSERT_GE(ours, 0) << name << " is neither a body of " << label << " nor welded to one";
    ++cut_links;
    bodies.reference[static_cast<size_t>(b)] = mujoco_frame(at_qpos0.get(), b);
  }
  EXPECT_EQ(m->nbody - 1 - cut_links, static_cast<int>(model.bodies.size()) - 1)
      << "every moving body of " << label << " in MuJoCo";
  MuJoCoAgreement worst;
  expect_mujoco_agrees(label, m.get(), solver, bodies, worst);
}

TEST_P(ExportedMjcf, MuJoCoPlacesEveryBodyAsTheModelDoesAndItsConstraintsHold) {
  const std::string source = std::string(MECHGEN_SOURCE_DIR) + "/models/" + GetParam() + ".yaml";
  expect_export_agrees(GetParam(), read_spatial_model(source), source);
}

// The shared URDF robots: MuJoCo cannot hold an Extended URDF closure, so their imports go to
// MuJoCo through the MJCF export (connect and weld for the cut loops), where the loop rows'
// Jacobian (efc_J E = 0) and the static efforts (E^T qfrc_bias) are checked as above.
TEST_P(SharedRobot, ItsImportExportedToMjcfAgreesWithMuJoCo) {
  const std::string dir = std::string(MECHGEN_SHARED_ROBOTS) + "/" + GetParam();
  const Imported r = import_file(dir + "/robot.urdf", dir + "/robot.yaml");
  expect_export_agrees(std::string(GetParam()) + "_import", *r.model, dir + "/robot.urdf");
}

INSTANTIATE_TEST_SUITE_P(Shipped, ExportedMjcf,
                         testing::Values("bennett", "chebyshev_spatial", "delta", "lecture_leg",
                                         "leg6", "quadruped_leg", "rsur"));

}  // namespace
