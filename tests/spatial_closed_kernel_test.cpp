// Generated spatial kernels of closed chains (issue 11): rsur (one circuit with spherical and
// universal joints), chebyshev_spatial (parallel revolute axes: three redundant closure rows)
// and quadruped_leg (four circuits)
// against the numeric reference solver: every kinematic sweep column, the screw Jacobians, the
// closure checks.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <map>

#include "rsur/rsur.hpp"
#include "spatial/spatial_kernel_sweep.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"
#include "spatial_sweep_equivalence.hpp"

namespace mechgen::spatial {
namespace {

namespace k = gen::rsur;

TEST(SpatialClosedKernel, RsurSweepColumnsEqualTheNumericSweep) {
  sweep_equals_numeric("rsur");
}

TEST(SpatialClosedKernel, ChebyshevSpatialSweepColumnsEqualTheNumericSweep) {
  sweep_equals_numeric("chebyshev_spatial");
}

// Seed 002's quadruped leg: four circuits (parallelogram, three cylinders), 24 secondary
// coordinates, three drivers.
TEST(SpatialClosedKernel, QuadrupedLegSweepColumnsEqualTheNumericSweep) {
  sweep_equals_numeric("quadruped_leg");
}

// Samples far apart (two or three over the whole step): the kernel is also called between them,
// at most the model's own step apart, so its warm start follows the motion as the numeric
// solver's halved steps do; quadruped_leg with 2 or 3 samples took the other root at t1 before
// (crank_pivot.q 9.8 rad off, forces 21 N). 1e-6, not 1e-9: the numeric solver's Newton-Raphson
// from a far extrapolation stops at a closure residual that leaves its rates 2.6e-7 off the
// closed forms' (at the model's own step both agree to 1e-9, above); another branch is O(1) off.
TEST(SpatialClosedKernel, CoarseSamplesFollowTheSameBranchAsTheNumericSolver) {
  for (const char* name : {"quadruped_leg", "quadruped_leg_swing", "chebyshev_spatial"}) {
    const SpatialModel model =
        read_spatial_model(std::string(MECHGEN_SOURCE_DIR "/models/") + name + ".yaml");
    const CompiledKernel* kernel = find_compiled_kernel(name);
    ASSERT_NE(kernel, nullptr);
    for (const int samples : {2, 3}) {
      SpatialSweepOptions options = default_spatial_sweep(model, model.common.default_parameters());
      options.samples = samples;
      const SpatialSweepResult numeric = run_spatial_sweep(model, options);
      const SpatialSweepResult generated = run_spatial_kernel_sweep(model, options, *kernel);
      ASSERT_EQ(numeric.rows.size(), generated.rows.size());
      std::string where;
      const double worst =
          test::worst_column_difference(numeric.columns, numeric.rows, generated.rows, where, 1e-6);
      EXPECT_LT(worst, 1e-6) << name << " with " << samples << " samples: " << where;
    }
  }
}

// A driven sample the mechanism cannot reach (a 10 m cylinder) fails, and the samples after it
// are the numeric solver's again: the failed call's State is no assembly to continue from, so
// the next call starts afresh. Continuing from the last accepted call two samples back, the
// closed forms took another root (the foot 0.37 m off, found through the Python module).
TEST(SpatialClosedKernel, AFailedDrivenSampleLeavesTheNextOnTheSameBranch) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/quadruped_leg.yaml");
  const CompiledKernel* kernel = find_compiled_kernel("quadruped_leg");
  ASSERT_NE(kernel, nullptr);
  SpatialSweepOptions options = default_spatial_sweep(model, model.common.default_parameters());
  options.samples = 8;
  const SpatialSweepResult numeric = run_spatial_sweep(model, options);
  const auto n = static_cast<size_t>(kernel->driver_count);
  const size_t failing = 3;
  kernel->seed_start(nullptr);
  std::vector<std::vector<double>> expected, rows;
  for (size_t i = 0; i < numeric.rows.size(); ++i) {
    std::vector<double> row(static_cast<size_t>(kernel->column_count));
    // The first columns: t, then (q, qd, qdd, effort) per driver in model order.
    std::vector<double> drivers;
    for (size_t d = 0; d < n; ++d)
      for (size_t f = 0; f < 3; ++f) drivers.push_back(numeric.rows[i][1 + 4 * d + f]);
    if (i == failing) drivers[0] = 10;
    int group = -1;
    const int status = kernel->evaluate_driven_double(options.parameters.data(), numeric.rows[i][0],
                                                      drivers.data(), row.data(), &group);
    if (i == failing) {
      EXPECT_EQ(status, 1) << "a 10 m cylinder";
      continue;
    }
    ASSERT_EQ(status, 0) << "sample " << i;
    expected.push_back(numeric.rows[i]);
    rows.push_back(row);
  }
  kernel->seed_start(nullptr);
  std::string where;
  EXPECT_LT(test::worst_column_difference(numeric.columns, expected, rows, where), 1e-9) << where;
}

// Property: the closed-form groups (rsur's RSUR link, the quadruped leg's cylinders and coupler)
// equal the numeric solver on perturbed geometry too.
TEST(SpatialClosedKernel, ClosedFormGroupsEqualTheNumericSweepOnPerturbedGeometry) {
  sweep_equals_numeric("rsur", 4);
  sweep_equals_numeric("quadruped_leg", 4);
}

// Every body's balance from the kernel's own outputs: the reactions and driver efforts of the
// joints on it (moved to the ground origin) equal its rate of momentum minus gravity, formed here
// from the kernel's centre of mass, orientation, velocities and accelerations and the model's
// mass and inertia. Joint points and driver axes come from the numeric solver's positions.
void bodies_balance(const std::string& name, const std::vector<double>& parameters) {
  const SpatialModel model =
      read_spatial_model(std::string(MECHGEN_SOURCE_DIR "/models/") + name + ".yaml");
  const CompiledKernel* kernel = find_compiled_kernel(name);
  ASSERT_NE(kernel, nullptr);
  const SpatialSolver solver(model, parameters);
  const SpatialInstance& in = solver.instance();
  const SpatialGraph& g = solver.graph();
  const SpatialSweepOptions options = default_spatial_sweep(model, parameters);
  const SpatialSweepResult out = run_spatial_kernel_sweep(model, options, *kernel);
  std::map<std::string, size_t> col;
  for (size_t c = 0; c < out.columns.size(); ++c) col[out.columns[c]] = c;
  auto v3 = [&](const std::vector<double>& row, const std::string& prefix,
                const std::array<const char*, 3>& f) {
    return V3{row[col.at(prefix + f[0])], row[col.at(prefix + f[1])], row[col.at(prefix + f[2])]};
  };
  SpatialState st;
  double worst = 0;
  for (const std::vector<double>& row : out.rows) {
    solver.solve(row[0], st);
    std::vector<Wrench> sum(model.bodies.size());  // on each body, about the origin
    auto add = [&](int body, double sign, const V3& f, const V3& m_origin) {
      sum[static_cast<size_t>(body)].f = sum[static_cast<size_t>(body)].f + sign * f;
      sum[static_cast<size_t>(body)].m = sum[static_cast<size_t>(body)].m + sign * m_origin;
    };
    for (size_t j = 0; j < model.joints.size(); ++j) {
      const SpatialJoint& joint = model.joints[j];
      const V3 P = geometry::apply(st.D[static_cast<size_t>(joint.second)], in.joint_point[j]);
      const std::string o = joint.name + ".";
      const V3 f = v3(row, o, {"fx", "fy", "fz"});
      const V3 m = v3(row, o, {"mx", "my", "mz"}) + geometry::cross(P, f);
      add(joint.second, 1, f, m);
      add(joint.first, -1, f, m);
    }
    for (const SpatialDriver& d : model.drivers) {
      const int c = g.joint_column[static_cast<size_t>(d.joint)] + d.column;
      const Twist& screw = st.screw[static_cast<size_t>(c)];
      const SpatialJoint& joint = model.joints[static_cast<size_t>(d.joint)];
      const double tau = row[col.at(d.name + ".effort")];
      const V3 P = geometry::apply(st.D[static_cast<size_t>(joint.second)],
                                   in.joint_point[static_cast<size_t>(d.joint)]);
      const bool force = in.axes[static_cast<size_t>(c)].kind == geometry::ScrewKind::translation;
      const V3 f = force ? tau * screw.v : V3{0, 0, 0};
      const V3 m = force ? geometry::cross(P, f) : tau * screw.w;
      add(joint.second, 1, f, m);
      add(joint.first, -1, f, m);
    }
    for (size_t b = 0; b < model.bodies.size(); ++b) {
      const SpatialBody& body = model.bodies[b];
      if (body.ground) continue;
      const std::string o = body.name + ".";
      const double qw = row[col.at(o + "qw")], qx = row[col.at(o + "qx")],
                   qy = row[col.at(o + "qy")], qz = row[col.at(o + "qz")];
      Eigen::Matrix3d R = Eigen::Quaterniond(qw, qx, qy, qz).toRotationMatrix(), I;
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) I(i, k) = in.inertia[b](i, k);
      I = R * I * R.transpose();
      auto e = [](const V3& v) { return Eigen::Vector3d(v[0], v[1], v[2]); };
      const Eigen::Vector3d c = e(v3(row, o, {"x", "y", "z"}));
      const Eigen::Vector3d w = e(v3(row, o, {"wx", "wy", "wz"}));
      const Eigen::Vector3d al = e(v3(row, o, {"alx", "aly", "alz"}));
      const Eigen::Vector3d F = in.mass[b] * (e(v3(row, o, {"ax", "ay", "az"})) - e(in.gravity));
      const Eigen::Vector3d M = I * al + w.cross(I * w) + c.cross(F);
      const double scale = 1e-3 + F.norm() + M.norm();
      worst = std::max(worst, (e(sum[b].f) - F).norm() / scale);
      worst = std::max(worst, (e(sum[b].m) - M).norm() / scale);
    }
  }
  EXPECT_LT(worst, 1e-9);
  std::cout << name << ": every body's balance from the kernel's reactions and efforts, "
            << out.rows.size() << " samples: worst " << worst << "\n";
}

TEST(SpatialClosedKernel, EveryBodyBalancesWithTheKernelsReactions) {
  for (const char* name : {"rsur", "chebyshev_spatial", "quadruped_leg"}) {
    const SpatialModel model =
        read_spatial_model(std::string(MECHGEN_SOURCE_DIR "/models/") + name + ".yaml");
    bodies_balance(name, model.common.default_parameters());
    bodies_balance(name, changed_parameters(model));
  }
}

// rsur's screw Jacobians (through Davies' sensitivity -N_s^-1 N_p) against the numeric
// solver's, along the step with one State (the warm start carried over).
TEST(SpatialClosedKernel, RsurJacobiansEqualTheNumericSolver) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/rsur.yaml");
  const SpatialSolver solver(model, model.common.default_parameters());
  const SpatialSweepOptions options = default_spatial_sweep(model, {});
  const k::Params<double> p;
  k::State<double> s;
  SpatialState st;
  auto body = [&](const std::string& n) {
    for (size_t b = 0; b < model.bodies.size(); ++b)
      if (model.bodies[b].name == n) return static_cast<int>(b);
    return -1;
  };
  double worst = 0;
  for (int i = 0; i < 91; ++i) {
    const double t = options.t0 + (options.t1 - options.t0) * i / 90;
    solver.solve(t, st);
    k::Inputs<double> in;
    k::driver_inputs(p, t, in);
    ASSERT_EQ(k::evaluate(p, in, s), k::Status::ok) << t;
    const std::map<std::string, const double(*)[1]> bodies{{"crank", s.body_jacobians.crank},
                                                           {"coupler", s.body_jacobians.coupler},
                                                           {"rocker", s.body_jacobians.rocker}};
    for (const auto& [n, J] : bodies) {
      const Eigen::MatrixXd expected = solver.body_jacobian(st, body(n));
      for (int r = 0; r < 6; ++r) worst = std::max(worst, std::abs(J[r][0] - expected(r, 0)));
    }
    for (const auto& [point, b] : model.named_points()) {
      if (point != "B" && point != "C") continue;
      const k::PointState<double>& ps = point == "B" ? s.points.B : s.points.C;
      const double(*J)[1] = point == "B" ? s.point_jacobians.B : s.point_jacobians.C;
      const Eigen::MatrixXd expected = solver.point_jacobian(st, b, {ps.x, ps.y, ps.z});
      for (int r = 0; r < 3; ++r) worst = std::max(worst, std::abs(J[r][0] - expected(r, 0)));
    }
  }
  EXPECT_LT(worst, 1e-12);
  std::cout << "rsur Jacobians against the numeric solver, 91 poses: worst " << worst << "\n";
}

// A non-finite input is unreachable; the kernel (rsur's loop in closed form, its angles unwound
// to their warm start) closes from a fresh State; control() checks the closure too and equals
// evaluate() on what it writes.
TEST(SpatialClosedKernel, RsurClosureChecks) {
  const k::Params<double> p;
  k::State<double> s;
  k::Inputs<double> in;
  k::driver_inputs(p, 0.3, in);
  ASSERT_EQ(k::evaluate(p, in, s), k::Status::ok);
  EXPECT_LT(s.closure.residual, 1e-28);
  k::Inputs<double> bad = in;
  bad.theta = std::nan("");
  EXPECT_EQ(k::evaluate(p, bad, s), k::Status::unreachable);
  bad = in;
  bad.theta = std::numeric_limits<double>::infinity();
  bad.t = 0;
  EXPECT_EQ(k::kinematics(p, bad, s), k::Status::unreachable);
  k::State<double> c = s;
  ASSERT_EQ(k::evaluate(p, in, s), k::Status::ok);
  ASSERT_EQ(k::control(p, in, c), k::Status::ok);
  EXPECT_EQ(c.points.C.x, s.points.C.x);
  EXPECT_EQ(c.point_jacobians.C[1][0], s.point_jacobians.C[1][0]);
}

}  // namespace
}  // namespace mechgen::spatial
