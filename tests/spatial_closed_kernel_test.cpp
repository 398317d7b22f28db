// Generated spatial kernels of closed chains (issue 11): rsur (one circuit with spherical and
// universal joints), chebyshev_spatial (parallel revolute axes: three redundant closure rows)
// and quadruped_leg (four circuits)
// against the numeric reference solver: every kinematic sweep column, the screw Jacobians, the
// closure checks.
#include <gtest/gtest.h>

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

// A non-finite input is unreachable and leaves the warm start as it was; the default warm start
// is the assembly, so the kernel closes at t0 from a fresh State; control() checks the closure
// too and equals evaluate() on what it writes.
TEST(SpatialClosedKernel, RsurClosureChecks) {
  const k::Params<double> p;
  k::State<double> s;
  k::Inputs<double> in;
  k::driver_inputs(p, 0.3, in);
  ASSERT_EQ(k::evaluate(p, in, s), k::Status::ok);
  EXPECT_LT(s.closure.residual, 1e-28);
  double before[6];
  for (int i = 0; i < 6; ++i) before[i] = s.closure.q[i];
  k::Inputs<double> bad = in;
  bad.theta = std::nan("");
  EXPECT_EQ(k::evaluate(p, bad, s), k::Status::unreachable);
  bad = in;
  bad.theta = std::numeric_limits<double>::infinity();
  bad.t = 0;
  EXPECT_EQ(k::kinematics(p, bad, s), k::Status::unreachable);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(s.closure.q[i], before[i]);
  k::State<double> c = s;
  ASSERT_EQ(k::evaluate(p, in, s), k::Status::ok);
  ASSERT_EQ(k::control(p, in, c), k::Status::ok);
  EXPECT_EQ(c.points.C.x, s.points.C.x);
  EXPECT_EQ(c.point_jacobians.C[1][0], s.point_jacobians.C[1][0]);
}

}  // namespace
}  // namespace mechgen::spatial
