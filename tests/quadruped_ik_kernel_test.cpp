// The generated inverse kinematics of seed 002's quadruped leg (models/quadruped_leg_swing.yaml:
// the foot D on a position-only pose driver, closed form by generator/spatial_position_ik.hpp,
// the cylinders from their end centres by generator/spatial_link_loops.hpp): every sweep column
// against the numeric solver; IK(FK(l)) = l over the stroke box through the generated forward
// kernel (quadruped_leg); the swing's cylinder rates and accelerations against the forward
// kernel's foot Jacobian and the seed's law written out; a target out of reach.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <random>
#include <string>

#include "quadruped_leg/quadruped_leg.hpp"
#include "quadruped_leg_swing/quadruped_leg_swing.hpp"
#include "quadruped_seed.hpp"
#include "spatial_sweep_equivalence.hpp"

namespace mechgen::spatial {
namespace {

namespace ik = gen::quadruped_leg_swing;
namespace fk = gen::quadruped_leg;

const std::string kSwingModel =
    std::string(MECHGEN_SOURCE_DIR) + "/models/quadruped_leg_swing.yaml";

// The model's parameters with some set by name, as `--set NAME=VALUE` does.
std::vector<double> with(const SpatialModel& model, std::vector<double> p,
                         const std::map<std::string, double>& set) {
  for (size_t k = 0; k < p.size(); ++k) {
    const auto it = set.find(model.common.parameters[k].name);
    if (it != set.end()) p[k] = it->second;
  }
  return p;
}

// Default (the path stays in the leg's plane: out-of-plane rates are round-off, 1e-14 SI, hence
// the floor of 1e-4 on a column's scale); the stance 60 mm to the side with the feasible lift
// (the side swing turns too); two random geometries (every parameter by up to +-3 %) at that
// stance. (changed_parameters' larger stride takes cylinder 1's rod end
// through its spherical joint's x-y-z singularity, middle angle pi/2, where the kernel's and the
// solver's angles part: docs/spatial.md.)
TEST(QuadrupedIkKernel, SweepColumnsEqualTheNumericSweep) {
  const SpatialModel model = read_spatial_model(kSwingModel);
  const std::map<std::string, double> side{{"Y0", 0.06}, {"H", 0.184}};
  sweep_equals_numeric_at(
      "quadruped_leg_swing",
      {model.common.default_parameters(), with(model, model.common.default_parameters(), side),
       with(model, perturbed_parameters(model, 1), side),
       with(model, perturbed_parameters(model, 2), side)},
      1e-4);
}

// The cylinders' reference lengths, from the seed's formulas on the kernels' own parameters.
Eigen::Vector3d reference_lengths() {
  return Seed(read_spatial_model(kSwingModel)).reference_lengths();
}

// Stroke lengths (350..500 mm for l1, l2, 280..340 mm for l3) -> foot by the generated forward
// kernel -> cylinder lengths by the generated inverse kernel, a fresh State each time (no warm
// start): a 9^3 grid of the box with its corners and 500 random samples.
TEST(QuadrupedIkKernel, InverseOfForwardIsIdentityOverTheStrokeBox) {
  const fk::Params<double> fp;
  const ik::Params<double> p;
  ASSERT_EQ(fp.c, p.c);
  ASSERT_EQ(fp.theta8, p.theta8);
  const Eigen::Vector3d ref = reference_lengths();
  std::vector<Eigen::Vector3d> lengths;
  const int n = 9;
  for (int u = 0; u < n; ++u)
    for (int v = 0; v < n; ++v)
      for (int w = 0; w < n; ++w)
        lengths.push_back(
            {0.35 + 0.15 * u / (n - 1), 0.35 + 0.15 * v / (n - 1), 0.28 + 0.06 * w / (n - 1)});
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u12(0.35, 0.5), u3(0.28, 0.34);
  for (int k = 0; k < 500; ++k) lengths.push_back({u12(random), u12(random), u3(random)});
  double worst = 0, worst_foot = 0;
  for (const Eigen::Vector3d& l : lengths) {
    fk::Inputs<double> f;
    f.l1 = l[0] - ref[0], f.l2 = l[1] - ref[1], f.l3 = l[2] - ref[2];
    fk::State<double> fs;
    ASSERT_EQ(fk::point_positions(fp, f, fs), fk::Status::ok) << l.transpose();
    ik::Inputs<double> in;
    in.foot_x = fs.points.D.x, in.foot_y = fs.points.D.y, in.foot_z = fs.points.D.z;
    ik::State<double> s;
    ASSERT_EQ(ik::evaluate(p, in, s), ik::Status::ok) << l.transpose();
    const Eigen::Vector3d back(s.joints.cyl1.q + ref[0], s.joints.cyl2.q + ref[1],
                               s.joints.cyl3.q + ref[2]);
    worst = std::max(worst, (back - l).cwiseAbs().maxCoeff());
    worst_foot = std::max({worst_foot, std::abs(s.points.D.x - in.foot_x),
                           std::abs(s.points.D.y - in.foot_y), std::abs(s.points.D.z - in.foot_z)});
  }
  EXPECT_EQ(lengths.size(), 1229u);
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(worst_foot, 1e-12);
  std::cout << "quadruped IK(FK(l)) through the generated kernels, " << lengths.size()
            << " stroke samples: worst " << worst << " m (foot " << worst_foot << " m)\n";
}

// Along the seed's swing: l' = J^-1 X' with J the forward kernel's foot Jacobian at the kernel's
// lengths, X' the law's derivative written out (tests/quadruped_seed.hpp); the forward kernel fed
// the inverse kernel's (l, l', l'') moves the foot with the law's X' and X'' (J l'' + J' l' = X'').
TEST(QuadrupedIkKernel, SwingCylinderRatesAndAccelerationsInvertTheForwardKernel) {
  const SpatialModel model = read_spatial_model(kSwingModel);
  const Swing sw{param(model, "S"),  param(model, "H"),  param(model, "T"),
                 param(model, "x0"), param(model, "Y0"), param(model, "z0")};
  const ik::Params<double> p;
  const fk::Params<double> fp;
  ik::State<double> s;
  double worst_rate = 0, worst_acc = 0, scale_rate = 0, scale_acc = 0;
  const int samples = 101;
  for (int k = 0; k < samples; ++k) {
    const double t = sw.T * k / (samples - 1);
    ik::Inputs<double> in;
    ik::driver_inputs(p, t, in);
    const Eigen::Vector3d x = sw.x(t), v = sw.v(t), a = sw.a(t);
    ASSERT_NEAR(in.foot_x, x[0], 1e-15);
    ASSERT_NEAR(in.foot_z_d, v[2], 1e-12);
    ASSERT_EQ(ik::evaluate(p, in, s), ik::Status::ok) << t;
    fk::Inputs<double> f;
    f.l1 = s.joints.cyl1.q, f.l2 = s.joints.cyl2.q, f.l3 = s.joints.cyl3.q;
    f.l1_d = s.joints.cyl1.qd, f.l2_d = s.joints.cyl2.qd, f.l3_d = s.joints.cyl3.qd;
    f.l1_dd = s.joints.cyl1.qdd, f.l2_dd = s.joints.cyl2.qdd, f.l3_dd = s.joints.cyl3.qdd;
    fk::State<double> fs;
    ASSERT_EQ(fk::evaluate(fp, f, fs), fk::Status::ok) << t;
    Eigen::Matrix3d J;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) J(r, c) = fs.point_jacobians.D[r][c];
    const Eigen::Vector3d rate(f.l1_d, f.l2_d, f.l3_d);
    worst_rate = std::max(worst_rate, (rate - J.inverse() * v).cwiseAbs().maxCoeff());
    scale_rate = std::max(scale_rate, rate.cwiseAbs().maxCoeff());
    const Eigen::Vector3d foot(fs.points.D.x, fs.points.D.y, fs.points.D.z);
    const Eigen::Vector3d foot_v(fs.points.D.vx, fs.points.D.vy, fs.points.D.vz);
    const Eigen::Vector3d foot_a(fs.points.D.ax, fs.points.D.ay, fs.points.D.az);
    EXPECT_LT((foot - x).norm(), 1e-12) << t;
    worst_rate = std::max(worst_rate, (foot_v - v).cwiseAbs().maxCoeff());
    worst_acc = std::max(worst_acc, (foot_a - a).cwiseAbs().maxCoeff());
    scale_acc = std::max({scale_acc, a.cwiseAbs().maxCoeff(), std::abs(f.l1_dd)});
  }
  EXPECT_GT(scale_rate, 0.1);
  EXPECT_GT(scale_acc, 0.5);
  EXPECT_LT(worst_rate, 1e-9 * scale_rate);
  EXPECT_LT(worst_acc, 1e-9 * scale_acc);
  std::cout << "quadruped swing through the generated IK, " << samples
            << " samples: rates vs J^-1 X' " << worst_rate << " m/s (largest " << scale_rate
            << "), foot acceleration from the kernel's l'' vs the law's X'' " << worst_acc
            << " m/s^2 (largest " << scale_acc << ")\n";
}

// Foot targets beyond the leg's reach (2 m below the hip; 1 m ahead and to the side): unreachable
// in the limb's group, the State cleared (no NaN); the next target in reach solves.
TEST(QuadrupedIkKernel, TargetOutOfReachIsUnreachableInTheIkGroup) {
  const ik::Params<double> p;
  ik::Inputs<double> in;
  ik::driver_inputs(p, 0.5, in);
  ik::State<double> s;
  ASSERT_EQ(ik::evaluate(p, in, s), ik::Status::ok);
  using Entry =
      ik::Status (*)(const ik::Params<double>&, const ik::Inputs<double>&, ik::State<double>&);
  const Entry entries[] = {&ik::evaluate<double>, &ik::kinematics<double>, &ik::control<double>,
                           &ik::point_positions<double>};
  for (const Eigen::Vector3d& target : {Eigen::Vector3d(0, 0, -2), Eigen::Vector3d(0.9, 0.5, 0)}) {
    ik::Inputs<double> far = in;
    far.foot_x = target[0], far.foot_y = target[1], far.foot_z = target[2];
    for (const Entry entry : entries) {
      ASSERT_EQ(entry(p, far, s), ik::Status::unreachable) << target.transpose();
      ASSERT_GE(s.failed_group, 0);
      EXPECT_EQ(std::string(ik::group_names[s.failed_group]), "ik_foot");
      EXPECT_EQ(s.joints.cyl1.q, 0.0);
      EXPECT_FALSE(std::isnan(s.points.D.x));
      EXPECT_FALSE(std::isnan(s.bodies.shank.x));
    }
  }
  EXPECT_EQ(ik::evaluate(p, in, s), ik::Status::ok);
  EXPECT_NE(s.joints.cyl1.q, 0.0);
}

}  // namespace
}  // namespace mechgen::spatial
