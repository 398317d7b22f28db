// Generated spatial kernels of pose-driven models (pose drivers' prescribed coordinates as kernel
// inputs; closed-form limb inverse kinematics, generator/spatial_limb_ik.hpp): every sweep column
// against the numeric solver, the lecture's closed forms, FK(IK(x)) = x through the generated
// forward kernel, rates against the forward kernel's, and an unreachable target.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "lecture_leg/lecture_leg.hpp"
#include "lecture_leg_ik/lecture_leg_ik.hpp"
#include "model/spatial_graph.hpp"
#include "spatial/spatial_solver.hpp"
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

// Seed 001's humanoid: four 6R limbs in closed form (no Newton), every sweep column against the
// numeric solver.
TEST(SpatialPoseKernel, BioloidSweepColumnsEqualTheNumericSweep) {
  sweep_equals_numeric("bioloid");
}

// Along a walking-like motion (every one of the 30 virtual coordinates swinging about the
// model's standing pose, with rates), the kernel's joint angles and Davies velocities equal the
// numeric solver's given the same primary motion, and N q' = 0 with the kernel's velocities.
TEST(SpatialPoseKernel, BioloidDaviesVelocitiesCloseTheCircuitsAlongAMotion) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/bioloid.yaml");
  const SpatialSolver solver(model, model.common.default_parameters());
  const SpatialGraph& g = solver.graph();
  const CompiledKernel* kernel = find_compiled_kernel("bioloid");
  ASSERT_NE(kernel, nullptr);
  ASSERT_EQ(kernel->driver_count, 30);
  const GiNaC::exmap subs = model.common.substitutions(solver.parameters());
  // The kernel's inputs are the pose coordinates in pose-driver order, absolute values.
  std::vector<int> input_column;
  std::vector<double> reference;
  for (const PoseDriver& pd : model.pose_drivers)
    for (const PoseCoordinate& c : pd.coordinates) {
      input_column.push_back(g.joint_column[static_cast<size_t>(c.joint)]);
      reference.push_back(model.evaluate({c.reference, "reference", pd.loc}, subs));
    }
  std::vector<size_t> primary_index(static_cast<size_t>(g.cols()));
  for (size_t k = 0; k < g.primary.size(); ++k)
    primary_index[static_cast<size_t>(g.primary[k])] = k;
  const std::vector<std::string> names(kernel->column_names,
                                       kernel->column_names + kernel->column_count);
  const auto column_of = [&names](const std::string& n) {
    return static_cast<size_t>(std::find(names.begin(), names.end(), n) - names.begin());
  };
  SpatialState st;
  double worst_q = 0, worst_qd = 0, worst_nq = 0;
  for (int i = 0; i <= 40; ++i) {
    const double t = 0.05 * i;
    Eigen::VectorXd qp, qpd, qpdd;
    solver.primary_motion(t, qp, qpd, qpdd);
    for (Eigen::Index k = 0; k < qp.size(); ++k) {
      // Zero at t = 0 (the numeric solver starts from the assembly), then each coordinate
      // swings with its own weight.
      const double weight = std::cos(0.7 * static_cast<double>(k));
      const SpatialColumn& col = g.columns[static_cast<size_t>(g.primary[static_cast<size_t>(k)])];
      const bool translation =
          model.joints[static_cast<size_t>(col.joint)].type == SpatialJointType::prismatic;
      const double amplitude = translation ? 0.0015 : 0.015;  // the hands have 5 mm of reach left
      qp[k] += weight * amplitude * std::sin(3.0 * t);
      qpd[k] += weight * 3.0 * amplitude * std::cos(3.0 * t);
      qpdd[k] += -weight * 9.0 * amplitude * std::sin(3.0 * t);
    }
    solver.solve(t, qp, qpd, qpdd, st);
    std::vector<double> drivers;
    for (size_t k = 0; k < input_column.size(); ++k) {
      const auto j = static_cast<Eigen::Index>(primary_index[static_cast<size_t>(input_column[k])]);
      drivers.insert(drivers.end(), {qp[j] + reference[k], qpd[j], qpdd[j]});
    }
    std::vector<double> row(names.size());
    int group = -1;
    ASSERT_EQ(kernel->evaluate_driven_double(solver.parameters().data(), t, drivers.data(),
                                             row.data(), &group),
              0)
        << t;
    Eigen::VectorXd qd = st.qd;
    for (const int c : g.secondary) {
      const std::string joint =
          model.joints[static_cast<size_t>(g.columns[static_cast<size_t>(c)].joint)].name;
      const auto e = static_cast<Eigen::Index>(c);
      worst_q = std::max(worst_q, std::abs(row[column_of(joint + ".q")] - st.q[e]));
      worst_qd = std::max(worst_qd, std::abs(row[column_of(joint + ".qd")] - st.qd[e]));
      qd[e] = row[column_of(joint + ".qd")];
    }
    worst_nq = std::max(worst_nq, (solver.network(st) * qd).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst_q, 1e-10);
  EXPECT_LT(worst_qd, 1e-9);
  EXPECT_LT(worst_nq, 1e-12);
  std::cout << "bioloid kernel along 41 poses: joint angles " << worst_q << " rad, Davies "
            << "velocities " << worst_qd << " rad/s from the numeric solver's; |N q'| " << worst_nq
            << "\n";
}

}  // namespace
}  // namespace mechgen::spatial
