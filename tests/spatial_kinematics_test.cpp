// The templated screw layer and the spatial reference solver's kinematics on closed chains:
// N q' = 0, Davies' velocities against finite differences of positions, exact accelerations
// against finite differences of velocities, screw Jacobians against the twists they map to.
#include <ginac/ginac.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>

#include "geometry/screw.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"
#include "spatial_test_models.hpp"

namespace mechgen::spatial {
namespace {

Eigen::Matrix4d homogeneous(const Pose& g) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) T(i, j) = g.R(i, j);
    T(i, 3) = g.p[static_cast<size_t>(i)];
  }
  return T;
}

// exp of the 4 x 4 twist matrix by its power series: independent of Rodrigues' closed form.
Eigen::Matrix4d exp_series(const Twist& x, double q) {
  Eigen::Matrix4d X = Eigen::Matrix4d::Zero();
  X << 0, -x.w[2], x.w[1], x.v[0], x.w[2], 0, -x.w[0], x.v[1], -x.w[1], x.w[0], 0, x.v[2], 0, 0, 0,
      0;
  X *= q;
  Eigen::Matrix4d sum = Eigen::Matrix4d::Identity(), term = Eigen::Matrix4d::Identity();
  for (int k = 1; k < 40; ++k) {
    term = term * X / k;
    sum += term;
  }
  return sum;
}

TEST(ScrewGeometry, ScrewDisplacementIsTheExponentialOfItsTwist) {
  const double n = std::sqrt(1 + 4 + 9.0);
  for (const auto kind : {geometry::ScrewKind::rotation, geometry::ScrewKind::translation,
                          geometry::ScrewKind::helical}) {
    geometry::ScrewAxis<double> a{kind, {1 / n, -2 / n, 3 / n}, {0.3, -0.2, 0.5}, 0.07};
    for (const double q : {-2.5, 0.4, 1.9}) {
      const Eigen::Matrix4d d = homogeneous(geometry::screw_displacement(a, q));
      EXPECT_LT((d - exp_series(geometry::unit_twist(a), q)).norm(), 1e-13);
    }
  }
}

TEST(ScrewGeometry, TheSameCodeRunsOnGinacExpressions) {
  // Rodrigues' rotation and the adjoint of a unit screw, symbolic then evaluated, equal the
  // double instantiation: the generator can reuse this layer.
  const GiNaC::symbol q("q");
  using E = GiNaC::ex;
  const geometry::ScrewAxis<E> a{
      geometry::ScrewKind::helical, {E(0), E(3) / 5, E(4) / 5}, {E(1), E(2), E(-1)}, E(1) / 10};
  const geometry::ScrewAxis<double> b{geometry::ScrewKind::helical, {0, 0.6, 0.8}, {1, 2, -1}, 0.1};
  const geometry::Pose<E> g = geometry::screw_displacement(a, E(q));
  const geometry::Twist<E> t = geometry::adjoint(g, geometry::unit_twist(a));
  const double qv = 0.7;
  const Pose gd = geometry::screw_displacement(b, qv);
  const Twist td = geometry::adjoint(gd, geometry::unit_twist(b));
  auto value = [&](const E& e) {
    return GiNaC::ex_to<GiNaC::numeric>(e.subs(q == qv).evalf()).to_double();
  };
  for (int i = 0; i < 9; ++i)
    EXPECT_NEAR(value(g.R.m[static_cast<size_t>(i)]), gd.R.m[static_cast<size_t>(i)], 1e-15);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(value(g.p[i]), gd.p[i], 1e-15);
    EXPECT_NEAR(value(t.w[i]), td.w[i], 1e-15);
    EXPECT_NEAR(value(t.v[i]), td.v[i], 1e-15);
  }
}

TEST(ScrewGeometry, QuaternionAndRotationLog) {
  const V3 s{2 / 3.0, -1 / 3.0, 2 / 3.0};
  for (const double angle : {0.0, 0.3, 2.0, M_PI - 1e-9, -1.2}) {
    const M3 R = geometry::rodrigues(s, angle);
    const std::array<double, 4> q = quaternion(R);
    const double sign = std::cos(angle / 2) < 0 ? -1 : 1;
    EXPECT_NEAR(q[0], sign * std::cos(angle / 2), 1e-12);
    for (size_t i = 0; i < 3; ++i) EXPECT_NEAR(q[i + 1], sign * std::sin(angle / 2) * s[i], 1e-8);
    const V3 w = rotation_log(R);
    const double a = std::remainder(angle, 2 * M_PI);
    for (size_t i = 0; i < 3; ++i) EXPECT_NEAR(w[i], a * s[i], 1e-7);
  }
}

Twist twist_difference(const SpatialState& plus, const SpatialState& minus, int body, double h) {
  // The spatial twist from D(t+h) D(t-h)^-1 ~ exp(2 h V).
  const Pose M =
      plus.D[static_cast<size_t>(body)] * geometry::inverse(minus.D[static_cast<size_t>(body)]);
  const V3 w = rotation_log(M.R);
  // For small motions the translation part of the spatial twist is p - (1/2) w x p.
  const V3 v = M.p - 0.5 * geometry::cross(w, M.p);
  return {(1 / (2 * h)) * w, (1 / (2 * h)) * v};
}

double norm(const Twist& t) {
  return std::sqrt(geometry::dot(t.w, t.w) + geometry::dot(t.v, t.v));
}

TEST(SpatialKinematics, DaviesVelocitiesAndExactAccelerationsOnClosedChains) {
  for (const Case& c : closed_chains()) {
    SCOPED_TRACE(c.name);
    const SpatialModel model = read_spatial_model_text(c.text, c.name + ".yaml");
    const SpatialSolver solver(model, {});
    const double t1 = model.evaluate(model.common.step.t1,
                                     model.common.substitutions(model.common.default_parameters()));
    SpatialState s;
    double worst_nq = 0, worst_v = 0, worst_a = 0, worst_twist = 0, worst_jac = 0;
    const double h = 1e-5;
    for (int i = 0; i <= 12; ++i) {
      const double t = t1 * i / 12;
      solver.solve(t, s);
      const Eigen::MatrixXd N = solver.network(s);
      worst_nq = std::max(worst_nq, (N * s.qd).norm() / std::max(1.0, s.qd.norm()));
      SpatialState plus = s, minus = s;
      solver.solve(t + h, plus);
      solver.solve(t - h, minus);
      worst_v = std::max(worst_v, ((plus.q - minus.q) / (2 * h) - s.qd).norm());
      worst_a = std::max(worst_a, ((plus.qd - minus.qd) / (2 * h) - s.qdd).norm());
      Eigen::VectorXd qp, qpd, qpdd;
      solver.primary_motion(t, qp, qpd, qpdd);
      for (size_t b = 0; b < model.bodies.size(); ++b) {
        const int bi = static_cast<int>(b);
        worst_twist = std::max(worst_twist, norm(twist_difference(plus, minus, bi, h) - s.V[b]));
        const Twist dV{(1 / (2 * h)) * (plus.V[b].w - minus.V[b].w),
                       (1 / (2 * h)) * (plus.V[b].v - minus.V[b].v)};
        worst_a = std::max(worst_a, norm(dV - s.A[b]));
        Eigen::Matrix<double, 6, 1> twist;
        twist << s.V[b].w[0], s.V[b].w[1], s.V[b].w[2], s.V[b].v[0], s.V[b].v[1], s.V[b].v[2];
        worst_jac = std::max(worst_jac, (solver.body_jacobian(s, bi) * qpd - twist).norm());
        for (const V3& local : solver.instance().points[b]) {
          const V3 x = solver.point_position(s, bi, local);
          const V3 v = solver.point_velocity(s, bi, local);
          const V3 fd = (1 / (2 * h)) * (solver.point_position(plus, bi, local) -
                                         solver.point_position(minus, bi, local));
          const V3 fa = (1 / (2 * h)) * (solver.point_velocity(plus, bi, local) -
                                         solver.point_velocity(minus, bi, local));
          const V3 a = solver.point_acceleration(s, bi, local);
          worst_v = std::max(worst_v, std::sqrt(geometry::dot(fd - v, fd - v)));
          worst_a = std::max(worst_a, std::sqrt(geometry::dot(fa - a, fa - a)));
          const Eigen::Vector3d jv = solver.point_jacobian(s, bi, x) * qpd;
          worst_jac = std::max(worst_jac, (jv - Eigen::Vector3d(v[0], v[1], v[2])).norm());
        }
      }
    }
    EXPECT_LT(worst_nq, 1e-12);
    EXPECT_LT(worst_v, 1e-7);
    EXPECT_LT(worst_twist, 1e-7);
    EXPECT_LT(worst_a, 1e-6);
    EXPECT_LT(worst_jac, 1e-12);
    std::cout << c.name << ": |N q'| " << worst_nq << ", velocity vs FD " << worst_v
              << ", twist vs FD " << worst_twist << ", acceleration vs FD " << worst_a
              << ", Jacobian " << worst_jac << "\n";
  }
}

TEST(SpatialKinematics, PoseDrivenLegReachesItsTarget) {
  const SpatialModel model = read_spatial_model_text(leg6_inverse_kinematics(), "leg6_ik.yaml");
  const SpatialSolver solver(model, {});
  SpatialState s;
  for (const double t : {0.0, 0.5, 1.3}) {
    solver.solve(t, s);
    const int foot = model.body_index("foot_link");
    const V3 x = solver.point_position(s, foot, solver.instance().points[6][0]);
    EXPECT_NEAR(x[0], 0.02 * std::sin(3 * t), 1e-12);
    EXPECT_NEAR(x[1], 0.01 * std::sin(3 * t), 1e-12);
    EXPECT_NEAR(x[2], -0.16 + 0.01 * std::cos(3 * t), 1e-12);
    // Orientation: Rz(a) Ry(b) Rx(c) relative to the reference (the foot frame is the ground's).
    const M3 R = geometry::rodrigues(V3{0, 0, 1}, 0.1 * std::sin(3 * t)) *
                 geometry::rodrigues(V3{0, 1, 0}, 0.05 * std::sin(6 * t)) *
                 geometry::rodrigues(V3{1, 0, 0}, -0.05 * std::sin(3 * t));
    for (size_t k = 0; k < 9; ++k) EXPECT_NEAR(solver.body_pose(s, foot).R.m[k], R.m[k], 1e-12);
  }
}

// Seed 003's leg (hip, knee, ankle, links of length l, foot vector v3 = (f, 0) at the zero pose)
// in the x-z plane, its inverse kinematics written as a pose driver on the foot (x, z and the foot
// angle), against the lecture's closed forms: a = v1 - |v3| (cos th, sin th),
// q2 = -2 acos(|a| / 2l), q1 = asin(a_x / |a|) - q2 / 2, and q3 = th - q1 - q2 (the foot angle is
// q1 + q2 + q3; the lecture prints q3 = th - q1 - q2/2, which does not return th through its own
// forward kinematics T1 T2 T3 v3 unless q2 = 0).
TEST(SpatialKinematics, TheLecturesLegInverseKinematicsIsAPoseDrivenModel) {
  const char* const text = R"(name: lecture_leg
dimension: spatial
parameters: {l: 0.2, f: 0.08}
bodies:
  - {name: hip, ground: true, points: {H: [0, 0, 0]}}
  - {name: thigh, points: {K: [0, 0, -l]}, mass: {mass: 1, com: [0, 0, -l/2], inertia: [0.01, 0.01, 0.001]}}
  - {name: shank, points: {A: [0, 0, -2*l]}, mass: {mass: 1, com: [0, 0, -1.5*l], inertia: [0.01, 0.01, 0.001]}}
  - {name: foot, points: {F: [f, 0, -2*l]}, mass: {mass: 0.5, com: [f/2, 0, -2*l], inertia: [0.001, 0.001, 0.001]}}
joints:   # s = -y: a positive angle turns x towards z (counter-clockwise, x right, z up)
  - {name: q1, type: revolute, first: hip, second: thigh, s: [0, -1, 0], s0: H, assembly: 0.3}
  - {name: q2, type: revolute, first: thigh, second: shank, s: [0, -1, 0], s0: K, assembly: -0.6}
  - {name: q3, type: revolute, first: shank, second: foot, s: [0, -1, 0], s0: A, assembly: 0.3}
drivers:  # the foot point v1 and the foot angle th (a rotation about -y is -ry)
  - {name: v1, type: pose, first: hip, second: foot, at: F, x: 0.1 + 0.05*sin(t), z: -0.33 + 0.03*cos(t),
     rotations: [{axis: y, value: -0.2*sin(t)}]}
step: {t0: 0, t1: 6, samples: 61}
)";
  const SpatialModel model = read_spatial_model_text(text, "lecture_leg.yaml");
  const SpatialSolver solver(model, {});
  const SpatialGraph& g = solver.graph();
  EXPECT_EQ(g.rows(), 6);
  EXPECT_EQ(g.primary.size(), 3u);  // x, z, ry; y, rx, rz free virtual joints
  SpatialState s;
  const double l = 0.2, f = 0.08;
  double worst = 0;
  for (int i = 0; i <= 60; ++i) {
    const double t = 0.1 * i;
    solver.solve(t, s);
    const double th = 0.2 * std::sin(t), vx = 0.1 + 0.05 * std::sin(t),
                 vz = -0.33 + 0.03 * std::cos(t);
    const double ax = vx - f * std::cos(th), az = vz - f * std::sin(th);
    const double norm = std::hypot(ax, az);
    const double q2 = -2 * std::acos(norm / (2 * l));
    const double q1 = std::asin(ax / norm) - q2 / 2;
    const double q3 = th - q1 - q2;
    worst = std::max({worst, std::abs(s.q[0] - q1), std::abs(s.q[1] - q2), std::abs(s.q[2] - q3)});
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(SpatialKinematics, ReachingASingularPoseIsALocatedError) {
  // A two-link planar arm whose tip is pulled out to full stretch at t = 1.
  const char* const text = R"(name: straight
dimension: spatial
bodies:
  - {name: g, ground: true, points: {O: [0, 0, 0]}}
  - {name: a, points: {P: [1, 0, 0]}, mass: {mass: 1, com: [0.5, 0, 0], inertia: [0.01, 0.1, 0.1]}}
  - {name: b, points: {Q: [2, 0, 0]}, mass: {mass: 1, com: [1.5, 0, 0], inertia: [0.01, 0.1, 0.1]}}
joints:
  - {name: j1, type: revolute, first: g, second: a, s: [0, 0, 1], s0: O, assembly: 0.5}
  - {name: j2, type: revolute, first: a, second: b, s: [0, 0, 1], s0: P, assembly: -1}
drivers:
  - {name: tip, type: pose, first: g, second: b, at: Q, x: 1.5 + 0.5*t, y: 0}
step: {t0: 0, t1: 1, samples: 11}
)";
  const SpatialModel model = read_spatial_model_text(text, "straight.yaml");
  const SpatialSolver solver(model, {});
  SpatialState s;
  for (int i = 0; i < 10; ++i) solver.solve(0.1 * i, s);  // bent: fine
  try {
    solver.solve(1.0, s);
    FAIL() << "no error at full stretch";
  } catch (const ModelError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("straight.yaml:", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("N_s is singular at t = 1"), std::string::npos)
        << e.what();
  }
}

// Samples far apart (three over a whole cycle) must land on the branch that fine samples follow:
// before continuation, Newton-Raphson from the previous coarse sample jumped to another assembly
// (chebyshev_spatial's rocker 4.43 rad off) or wound angles by 2 pi k (quadruped_leg 91 rad).
TEST(SpatialKinematics, CoarseSamplesFollowTheBranchOfFineOnes) {
  for (const char* name : {"chebyshev_spatial", "quadruped_leg", "quadruped_leg_swing"}) {
    const SpatialModel model =
        read_spatial_model(std::string(MECHGEN_SOURCE_DIR "/models/") + name + ".yaml");
    const std::vector<double> defaults = model.common.default_parameters();
    const SpatialSolver solver(model, defaults);
    const SpatialSweepOptions step = default_spatial_sweep(model, defaults);
    constexpr int kFine = 64;
    SpatialState coarse, fine;
    double worst = 0;
    for (int k = 0; k <= 2; ++k) {
      const double t = step.t0 + (step.t1 - step.t0) * k / 2;
      solver.solve(t, coarse);
      for (int f = (k == 0 ? 0 : (k - 1) * kFine + 1); f <= k * kFine; ++f)
        solver.solve(step.t0 + (step.t1 - step.t0) * f / (2 * kFine), fine);
      worst = std::max(worst, (coarse.q - fine.q).cwiseAbs().maxCoeff());
      worst = std::max(worst, (coarse.qd - fine.qd).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(worst, 1e-9) << name;
  }
}

// Cranks started out of phase (issue 28): Newton-Raphson from the assembly hints (every joint at
// zero) does not close four RSUR copies whose cranks start a quarter turn apart; the first
// assembly moves the drivers there from the hints' values in steps. Each copy must then sit where
// the single loop, followed continuously from its hints, is when its crank has turned as far.
TEST(SpatialKinematics, OutOfPhaseCranksAssembleByContinuationFromTheHints) {
  constexpr int kCopies = 4;
  const SpatialModel model = read_spatial_model_text(rsur_copies(kCopies, true), "copies.yaml");
  const SpatialSolver solver(model, model.common.default_parameters());
  SpatialState s;
  solver.solve(0, s);
  const SpatialModel one = read_spatial_model(MECHGEN_SOURCE_DIR "/models/rsur.yaml");
  const std::vector<double> defaults = one.common.default_parameters();
  const SpatialSolver single(one, defaults);
  const double w = 2;  // models/rsur.yaml's crank speed
  for (int i = 0; i < kCopies; ++i) {
    SpatialState loop;
    for (int f = 0; f <= 32 * i; ++f) single.solve(2 * M_PI / kCopies / w * f / 32, loop);
    // Seven coordinates a copy, in model order, all angles: the assembly puts its free angles
    // in (-pi, pi] (EquivalentAssemblyHintsGiveTheSameCoordinates), the single loop followed
    // there is unwound: equal modulo 2 pi.
    const Eigen::Index offset = 7 * i;
    for (Eigen::Index k = 0; k < 7; ++k)
      EXPECT_LT(std::abs(std::remainder(s.q[offset + k] - loop.q[k], 2 * M_PI)), 1e-9)
          << "copy " << i << ", coordinate " << k;
  }
}

// Joint coordinates defined once (issue 28 item 3): rsur hinted at the other angle set of its
// spherical joint ((a + pi, pi - b, c + pi): the same orientation) and at its universal and
// rocker angles plus 2 pi assembles on the same configuration, and reports the same columns as
// the unhinted model: free angles in (-pi, pi] at the assembly, a spherical middle angle in
// [-pi/2, pi/2], continuous after.
TEST(SpatialKinematics, EquivalentAssemblyHintsGiveTheSameCoordinates) {
  const std::string path = MECHGEN_SOURCE_DIR "/models/rsur.yaml";
  std::ifstream file(path);
  std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const auto hint = [&](const std::string& joint, const std::string& values) {
    const std::string key = "{name: " + joint + ",";
    const size_t at = text.find(key);
    ASSERT_NE(at, std::string::npos) << joint;
    text.insert(at + key.size(), " assembly: " + values + ",");
  };
  hint("jB", "[pi, pi, pi]");
  hint("jC", "[2*pi, -2*pi]");
  hint("jD", "[2*pi]");
  const SpatialModel hinted = read_spatial_model_text(text, "rsur_hinted.yaml");
  const SpatialModel plain = read_spatial_model(path);
  SpatialSweepOptions options = default_spatial_sweep(plain, plain.common.default_parameters());
  options.samples = 19;
  const SpatialSweepResult expected = run_spatial_sweep(plain, options);
  const SpatialSweepResult got = run_spatial_sweep(hinted, options);
  ASSERT_EQ(expected.columns, got.columns);
  ASSERT_EQ(expected.rows.size(), got.rows.size());
  for (size_t r = 0; r < got.rows.size(); ++r)
    for (size_t c = 0; c < got.columns.size(); ++c)
      EXPECT_NEAR(got.rows[r][c], expected.rows[r][c], 1e-9 * (1 + std::abs(expected.rows[r][c])))
          << got.columns[c] << " at sample " << r;
}

}  // namespace
}  // namespace mechgen::spatial
