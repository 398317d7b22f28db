// Generated spatial kernels of pose-driven models (pose drivers' prescribed coordinates as kernel
// inputs; closed-form limb inverse kinematics, generator/spatial_limb_ik.hpp): every sweep column
// against the numeric solver, the lecture's closed forms, FK(IK(x)) = x through the generated
// forward kernel, rates against the forward kernel's, and an unreachable target.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "lecture_leg/lecture_leg.hpp"
#include "lecture_leg_ik/lecture_leg_ik.hpp"
#include "spatial_sweep_equivalence.hpp"

namespace mechgen::spatial {
namespace {

namespace ik = gen::lecture_leg_ik;
namespace fk = gen::lecture_leg;

TEST(SpatialPoseKernel, LectureLegIkSweepColumnsEqualTheNumericSweep) {
  sweep_equals_numeric("lecture_leg_ik");
}

TEST(SpatialPoseKernel, LectureLegAbstractSweepColumnsEqualTheNumericSweep) {
  sweep_equals_numeric("lecture_leg_abstract");
}

// The kernel's closed form is the lecture's: a = toe - f (cos theta, sin theta) relative to the
// hip, q2 = -2 acos(|a| / 2l), q1 = asin(a_x / |a|) - q2 / 2, q3 = theta - q1 - q2 (the foot angle
// is q1 + q2 + q3; the lecture prints q3 = theta - q1 - q2/2, off by q2/2, see docs/spatial.md);
// the generated forward kernel takes the angles back to the target; with the target's rates the
// forward kernel's toe velocity and foot rate are the target's. A fresh State each time: the
// closed form needs no warm start.
TEST(SpatialPoseKernel, LectureLegIkIsTheLecturesClosedFormAndFkOfIkIsTheTarget) {
  const ik::Params<double> p;
  const fk::Params<double> fp;
  ASSERT_EQ(p.l, fp.l);
  ASSERT_EQ(p.f, fp.f);
  double worst = 0;
  int count = 0;
  // Targets from the lecture's own forward kinematics T1 T2 T3 v3 (knee bent backwards).
  for (double a1 : {-0.5, 0.2, 0.8})
    for (double a2 : {-1.6, -0.9, -0.3})
      for (double a3 : {-0.4, 0.3}) {
        const double theta = a1 + a2 + a3;
        const double x = p.l * (std::sin(a1) + std::sin(a1 + a2)) + p.f * std::cos(theta);
        const double y = -p.l * (std::cos(a1) + std::cos(a1 + a2)) + p.f * std::sin(theta);
        ik::Inputs<double> in;
        in.foot_pose_x = x, in.foot_pose_y = y, in.foot_pose_rz = theta;
        in.foot_pose_x_d = 0.3, in.foot_pose_y_d = -0.2, in.foot_pose_rz_d = 0.7;
        ik::State<double> s;
        ASSERT_EQ(ik::evaluate(p, in, s), ik::Status::ok) << x << " " << y << " " << theta;
        const double ax = x - p.f * std::cos(theta), ay = y - p.f * std::sin(theta);
        const double r = std::hypot(ax, ay);
        const double q2 = -2 * std::acos(r / (2 * p.l));
        const double q1 = std::asin(ax / r) - q2 / 2;
        const double q3 = theta - q1 - q2;
        worst = std::max({worst, std::abs(s.joints.j1.q - q1), std::abs(s.joints.j2.q - q2),
                          std::abs(s.joints.j3.q - q3), std::abs(s.joints.j1.q - a1),
                          std::abs(s.joints.j2.q - a2), std::abs(s.joints.j3.q - a3)});
        fk::Inputs<double> f;
        f.q1 = s.joints.j1.q, f.q2 = s.joints.j2.q, f.q3 = s.joints.j3.q;
        f.q1_d = s.joints.j1.qd, f.q2_d = s.joints.j2.qd, f.q3_d = s.joints.j3.qd;
        fk::State<double> fs;
        ASSERT_EQ(fk::evaluate(fp, f, fs), fk::Status::ok);
        const double foot_angle = std::atan2(fs.bodies.foot.R[3], fs.bodies.foot.R[0]);
        worst = std::max({worst, std::abs(fs.points.toe.x - x), std::abs(fs.points.toe.y - y),
                          std::abs(foot_angle - theta), std::abs(fs.points.toe.vx - 0.3),
                          std::abs(fs.points.toe.vy + 0.2), std::abs(fs.bodies.foot.wz - 0.7)});
        ++count;
      }
  EXPECT_EQ(count, 18);
  EXPECT_LT(worst, 1e-12);
  std::cout << "lecture_leg_ik kernel against the lecture's closed forms and the generated FK, "
            << count << " targets: worst " << worst << "\n";
}

// A toe beyond the leg's reach is unreachable in the closed-form group (never NaN); the next
// reachable target is solved again.
TEST(SpatialPoseKernel, LectureLegIkUnreachableTargetNamesTheGroup) {
  const ik::Params<double> p;
  ik::Inputs<double> in;
  in.foot_pose_x = 0.2, in.foot_pose_y = -0.45, in.foot_pose_rz = 0;
  ik::State<double> s;
  ASSERT_EQ(ik::evaluate(p, in, s), ik::Status::unreachable);
  ASSERT_GE(s.failed_group, 0);
  EXPECT_EQ(std::string(ik::group_names[s.failed_group]), "ik_foot_pose");
  EXPECT_EQ(ik::kinematics(p, in, s), ik::Status::unreachable);
  EXPECT_EQ(ik::control(p, in, s), ik::Status::unreachable);
  in.foot_pose_x = 0.05, in.foot_pose_y = -0.3;
  ASSERT_EQ(ik::evaluate(p, in, s), ik::Status::ok);
  EXPECT_TRUE(std::isfinite(s.joints.j2.q));
  EXPECT_LT(s.closure.residual, 1e-28);
}

}  // namespace
}  // namespace mechgen::spatial
