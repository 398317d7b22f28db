// Generated spatial kernels of closed chains (issue 11): rsur (one circuit with spherical and
// universal joints), chebyshev_spatial (parallel revolute axes: three redundant closure rows)
// and quadruped_leg (four circuits)
// against the numeric reference solver: every kinematic sweep column, the screw Jacobians, the
// closure checks.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "rsur/rsur.hpp"
#include "spatial/spatial_kernel_sweep.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"

namespace mechgen::spatial {
namespace {

namespace k = gen::rsur;

bool is_reaction(const std::string& column) {
  for (const char* suffix : {".fx", ".fy", ".fz", ".mx", ".my", ".mz"}) {
    const std::string s(suffix);
    if (column.size() > s.size() && column.compare(column.size() - s.size(), s.size(), s) == 0)
      return true;
  }
  return false;
}

// Small changes: every parameter by a few per cent (the reference pose stays assembled).
std::vector<double> changed_parameters(const SpatialModel& model) {
  std::vector<double> p = model.common.default_parameters();
  for (size_t i = 0; i < p.size(); ++i) p[i] *= 1.0 + 0.03 * static_cast<double>(i % 3 + 1);
  return p;
}

// The whole step through the registry's kernel (warm-started from one call to the next) and the
// numeric sweep: every kinematic column and the driver efforts to 1e-9 of its scale (the
// column's largest magnitude, at least 1 % of the largest of its kind, as the leg6 test); the
// reactions are not generated for closed chains yet and must be NaN.
// Random geometry: every parameter by up to +-3 %, drawn from `seed`.
std::vector<double> perturbed_parameters(const SpatialModel& model, unsigned seed) {
  std::vector<double> p = model.common.default_parameters();
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> factor(0.97, 1.03);
  for (double& value : p) value *= factor(random);
  return p;
}

void sweep_equals_numeric(const std::string& name, int perturbed = 0) {
  const SpatialModel model =
      read_spatial_model(std::string(MECHGEN_SOURCE_DIR "/models/") + name + ".yaml");
  const CompiledKernel* kernel = find_compiled_kernel(name);
  ASSERT_NE(kernel, nullptr);
  std::vector<std::vector<double>> sets{model.common.default_parameters(),
                                        changed_parameters(model)};
  for (int k = 0; k < perturbed; ++k)
    sets.push_back(perturbed_parameters(model, static_cast<unsigned>(k + 1)));
  for (const std::vector<double>& parameters : sets) {
    const SpatialSweepOptions options = default_spatial_sweep(model, parameters);
    const SpatialSweepResult numeric = run_spatial_sweep(model, options);
    const SpatialSweepResult generated = run_spatial_kernel_sweep(model, options, *kernel);
    ASSERT_EQ(numeric.columns, generated.columns);
    ASSERT_EQ(numeric.rows.size(), generated.rows.size());
    // The kind: the suffix without digits (a spherical joint's q1, q2, q3 are one kind).
    auto kind = [](const std::string& c) {
      std::string k;
      for (const char ch : c.substr(c.rfind('.') + 1))
        if (ch < '0' || ch > '9') k += ch;
      return k;
    };
    std::map<std::string, double> kind_scale;
    for (const auto& row : numeric.rows)
      for (size_t c = 0; c < numeric.columns.size(); ++c)
        kind_scale[kind(numeric.columns[c])] =
            std::max(kind_scale[kind(numeric.columns[c])], std::abs(row[c]));
    double worst = 0;
    std::string where;
    int compared = 0;
    for (size_t c = 0; c < numeric.columns.size(); ++c) {
      if (is_reaction(numeric.columns[c])) {
        for (const auto& row : generated.rows)
          EXPECT_TRUE(std::isnan(row[c])) << numeric.columns[c];
        continue;
      }
      ++compared;
      double scale = std::max(1e-300, 0.01 * kind_scale[kind(numeric.columns[c])]);
      for (const auto& row : numeric.rows) scale = std::max(scale, std::abs(row[c]));
      for (size_t r = 0; r < numeric.rows.size(); ++r) {
        const double e = std::abs(generated.rows[r][c] - numeric.rows[r][c]) / scale;
        if (!(e <= worst)) worst = e, where = numeric.columns[c];
      }
    }
    EXPECT_GT(compared, 80);
    EXPECT_LT(worst, 1e-9) << where;
    std::cout << name << " sweep (" << numeric.rows.size() << " samples, " << compared
              << " kinematic and effort columns), generated against numeric: worst " << worst
              << " (" << where << ")\n";
  }
}

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

// Property: the closed-form groups (rsur's RSUR link, the quadruped leg's cylinders and coupler)
// equal the numeric solver on perturbed geometry too.
TEST(SpatialClosedKernel, ClosedFormGroupsEqualTheNumericSweepOnPerturbedGeometry) {
  sweep_equals_numeric("rsur", 4);
  sweep_equals_numeric("quadruped_leg", 4);
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
