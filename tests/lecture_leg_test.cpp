// Seed 003 (the walking lecture): its leg's forward kinematics (T1 T2 T3 v3), inverse kinematics
// (foot point and foot angle by a pose driver) and abstract kinematics (leg extension, leg angle,
// foot angle by a pose driver on the ankle), solved by the numeric spatial solver, against the
// lecture's closed forms written out here.
#include <gtest/gtest.h>

#include <cmath>

#include "spatial/driven_solve.hpp"
#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {
namespace {

std::string model_path(const std::string& name) {
  return std::string(MECHGEN_SOURCE_DIR) + "/models/" + name + ".yaml";
}

double param(const SpatialModel& m, const std::string& name) {
  for (const Parameter& p : m.common.parameters)
    if (p.name == name) return p.value;
  ADD_FAILURE() << "no parameter " << name;
  return 0;
}

// The lecture's homogeneous transforms: T(q) = [cos q, -sin q, l sin q; sin q, cos q, -l cos q]
// for hip and knee (each followed by its link of length l); the ankle turns the foot vector only.
Eigen::Matrix3d T(double q, double l) {
  Eigen::Matrix3d m;
  m << std::cos(q), -std::sin(q), l * std::sin(q), std::sin(q), std::cos(q), -l * std::cos(q), 0, 0,
      1;
  return m;
}

Eigen::Vector2d lecture_fk(const Eigen::Vector3d& q, double l, double f) {
  const Eigen::Vector3d v = T(q[0], l) * T(q[1], l) * T(q[2], 0) * Eigen::Vector3d(f, 0, 1);
  return {v[0], v[1]};
}

// Joint angles (j1, j2, j3) of a solved state.
Eigen::Vector3d angles(const SpatialSolver& s, const SpatialState& st) {
  Eigen::Vector3d q;
  for (int k = 0; k < 3; ++k)
    q[k] = st.q[s.graph().joint_column[static_cast<size_t>(
        s.model().joint_index("j" + std::to_string(k + 1)))]];
  return q;
}

V3 toe(const SpatialSolver& s, const SpatialState& st) {
  const int foot = s.model().body_index("foot");
  return s.point_position(st, foot, s.instance().points[static_cast<size_t>(foot)][1]);
}

// Solves a pose-driven model at the given prescribed values (x, y, rz), from its t0 state.
SpatialState pose_solve(const SpatialSolver& s, const SpatialState& start, double x, double y,
                        double rz) {
  const PoseDriver& pd = s.model().pose_drivers.front();
  const GiNaC::exmap subs = s.model().common.substitutions(s.parameters());
  Eigen::VectorXd qp(3);
  const SpatialGraph& g = s.graph();
  for (size_t k = 0; k < g.primary.size(); ++k) {
    const SpatialColumn& col = g.columns[static_cast<size_t>(g.primary[k])];
    const PoseCoordinate& c = pd.coordinates[static_cast<size_t>(col.pose_coordinate)];
    const double value = c.name == "x" ? x : c.name == "y" ? y : rz;
    qp[static_cast<Eigen::Index>(k)] =
        value - s.model().evaluate({c.reference, "reference", pd.loc}, subs);
  }
  SpatialState st = start;
  solve_at(s, qp, Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(3), st, 0.02);
  return st;
}

TEST(LectureLeg, ForwardKinematicsIsTheLecturesProductOfTransforms) {
  const SpatialModel m = read_spatial_model(model_path("lecture_leg"));
  const SpatialSolver s(m, {});
  const double l = param(m, "l"), f = param(m, "f");
  SpatialState st;
  s.solve(0, st);
  for (double q1 : {-0.6, 0.1, 0.9})
    for (double q2 : {-1.8, -0.7, -0.1})
      for (double q3 : {-0.5, 0.4}) {
        const Eigen::Vector3d q(q1, q2, q3);
        solve_at(s, q, Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(3), st);
        const V3 x = toe(s, st);
        const Eigen::Vector2d expected = lecture_fk(q, l, f);
        EXPECT_NEAR(x[0], expected[0], 1e-15);
        EXPECT_NEAR(x[1], expected[1], 1e-15);
        EXPECT_NEAR(x[2], 0, 1e-15);
      }
}

TEST(LectureLeg, InverseKinematicsMatchesTheLecturesClosedForms) {
  const SpatialModel m = read_spatial_model(model_path("lecture_leg_ik"));
  const SpatialSolver s(m, {});
  const double l = param(m, "l"), f = param(m, "f");
  SpatialState start;
  s.solve(0, start);
  int count = 0;
  for (double q1 : {-0.5, 0.2, 0.8})
    for (double q2 : {-1.6, -0.9, -0.3})
      for (double q3 : {-0.4, 0.3}) {
        const Eigen::Vector3d q(q1, q2, q3);
        const Eigen::Vector2d v1 = lecture_fk(q, l, f);
        const double theta = q1 + q2 + q3;
        const SpatialState st = pose_solve(s, start, v1[0], v1[1], theta);
        const Eigen::Vector3d got = angles(s, st);
        EXPECT_LT((got - q).cwiseAbs().maxCoeff(), 1e-12);  // IK(FK(q)) = q
        // The lecture: a = v1 - |v3| (cos theta, sin theta), q2 = -2 acos(|a| / 2l),
        // q1 = asin(a_x / |a|) - q2 / 2.
        const Eigen::Vector2d a(v1[0] - f * std::cos(theta), v1[1] - f * std::sin(theta));
        const double lq2 = -2 * std::acos(a.norm() / (2 * l));
        const double lq1 = std::asin(a[0] / a.norm()) - lq2 / 2;
        EXPECT_NEAR(got[1], lq2, 1e-12);
        EXPECT_NEAR(got[0], lq1, 1e-12);
        // The ankle: q3 = theta - q1 - q2 (the foot angle is q1 + q2 + q3); the lecture's
        // printed q3 = theta - q1 - q2/2 is off by q2/2.
        EXPECT_NEAR(got[2], theta - lq1 - lq2, 1e-12);
        EXPECT_NEAR(got[2] - (theta - lq1 - lq2 / 2), -lq2 / 2, 1e-12);
        // FK(IK(x)) = x.
        const V3 x = toe(s, st);
        EXPECT_NEAR(x[0], v1[0], 1e-12);
        EXPECT_NEAR(x[1], v1[1], 1e-12);
        ++count;
      }
  EXPECT_EQ(count, 18);
}

TEST(LectureLeg, AbstractKinematicsMatchesTheLecturesClosedForms) {
  const SpatialModel m = read_spatial_model(model_path("lecture_leg_abstract"));
  const SpatialSolver s(m, {});
  const double l = param(m, "l");
  SpatialState start;
  s.solve(0, start);
  for (double eta : {0.55, 0.75, 0.95})
    for (double leg : {-0.4, 0.0, 0.5})
      for (double foot : {-0.2, 0.3}) {
        const SpatialState st =
            pose_solve(s, start, 2 * l * eta * std::sin(leg), -2 * l * eta * std::cos(leg), foot);
        const Eigen::Vector3d got = angles(s, st);
        // q2 = 2 acos(eta), q1 = theta_leg - q2/2, q3 = theta_foot - theta_leg - q2/2.
        const double q2 = 2 * std::acos(eta);
        EXPECT_NEAR(got[1], q2, 1e-12);
        EXPECT_NEAR(got[0], leg - q2 / 2, 1e-12);
        EXPECT_NEAR(got[2], foot - leg - q2 / 2, 1e-12);
      }
}

}  // namespace
}  // namespace mechgen::spatial
