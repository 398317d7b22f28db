// The generated closed-chain kernels' Newton-Euler system and applied loads (rsur,
// chebyshev_spatial, quadruped_leg): ne_system()'s A and b equal the numeric solver's
// (newton_euler_system) along the step and the kernel's own reactions and efforts solve them;
// quadruped_leg with a foot load (seed 002's statics) equals the numeric sweep on every column,
// and at rest the load reaches the cylinders as -J_D^T F through the kernel's own foot Jacobian;
// a failed closure leaves A and b zero.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "chebyshev_spatial/chebyshev_spatial.hpp"
#include "quadruped_leg/quadruped_leg.hpp"
#include "rsur/rsur.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"
#include "spatial_sweep_equivalence.hpp"

namespace mechgen::spatial {
namespace {

// One kernel's entry points on double, under one name per model (each kernel has its namespace).
#define MECHGEN_KERNEL(NS)                                                                    \
  struct NS {                                                                                 \
    using Params = gen::NS::Params<double>;                                                   \
    using Inputs = gen::NS::Inputs<double>;                                                   \
    using State = gen::NS::State<double>;                                                     \
    static constexpr int rows = gen::NS::ne_rows, size = gen::NS::ne_size;                    \
    static constexpr int columns = gen::NS::column_count;                                     \
    static constexpr const char* const* unknowns = gen::NS::ne_unknowns;                      \
    static constexpr const char* const* column_names = gen::NS::column_names;                 \
    static Params params(const std::vector<double>& values) {                                 \
      Params p;                                                                               \
      gen::NS::set_parameters(p, values.data());                                              \
      return p;                                                                               \
    }                                                                                         \
    static Inputs inputs(const Params& p, double t) {                                         \
      Inputs in;                                                                              \
      gen::NS::driver_inputs(p, t, in);                                                       \
      return in;                                                                              \
    }                                                                                         \
    static int evaluate(const Params& p, const Inputs& in, State& s) {                        \
      return static_cast<int>(gen::NS::evaluate(p, in, s));                                   \
    }                                                                                         \
    static int ne_system(const Params& p, const Inputs& in, State& s, double* A, double* b) { \
      return static_cast<int>(gen::NS::ne_system(p, in, s, A, b));                            \
    }                                                                                         \
    static void to_columns(const Inputs& in, const State& s, double* row) {                   \
      gen::NS::to_columns(in, s, row);                                                        \
    }                                                                                         \
  }
MECHGEN_KERNEL(rsur);
MECHGEN_KERNEL(chebyshev_spatial);
MECHGEN_KERNEL(quadruped_leg);
#undef MECHGEN_KERNEL

SpatialModel shipped(const std::string& name) {
  return read_spatial_model(std::string(MECHGEN_SOURCE_DIR "/models/") + name + ".yaml");
}

std::vector<double> with(const SpatialModel& model, std::vector<double> values,
                         const std::map<std::string, double>& set) {
  for (const auto& [name, value] : set) {
    const auto& ps = model.common.parameters;
    const auto it =
        std::find_if(ps.begin(), ps.end(), [&](const auto& p) { return p.name == name; });
    EXPECT_NE(it, ps.end()) << name;
    if (it != ps.end()) values[static_cast<size_t>(it - ps.begin())] = value;
  }
  return values;
}

// Along the step (each sample warm-started from the previous one, as a sweep): ne_system() from
// the State evaluate() started from, A and b against the numeric solver's at the same instant,
// and A x = b with x the kernel's own reactions and efforts (ne_unknowns[] looked up among the
// CSV columns by name), to 1e-10 of the largest term A_rc x_c or b_r (a row of zero work on a
// screw sums terms that are round-off of structurally zero entries: no scale of its own).
template <class K>
void ne_system_equals_numeric(const std::string& name, const std::vector<double>& parameters,
                              int samples = 60) {
  const SpatialModel model = shipped(name);
  const SpatialSolver solver(model, parameters);
  const SpatialSweepOptions options = default_spatial_sweep(model, parameters);
  const typename K::Params p = K::params(parameters);
  typename K::State s;
  SpatialState st;
  std::vector<double> A(static_cast<size_t>(K::rows * K::size)), b(K::rows), row(K::columns);
  std::map<std::string, size_t> column;
  for (int c = 0; c < K::columns; ++c) column[K::column_names[c]] = static_cast<size_t>(c);
  double worst_A = 0, scale_A = 0, worst_b = 0, scale_b = 0, worst_residual = 0, scale_terms = 0;
  for (int i = 0; i < samples; ++i) {
    const double t = options.t0 + (options.t1 - options.t0) * i / samples;
    const typename K::Inputs in = K::inputs(p, t);
    typename K::State start = s;
    ASSERT_EQ(K::evaluate(p, in, s), 0) << name << " t = " << t;
    ASSERT_EQ(K::ne_system(p, in, start, A.data(), b.data()), 0) << name << " t = " << t;
    solver.solve(t, st);
    const NewtonEulerSystem numeric = newton_euler_system(solver, st);
    ASSERT_EQ(numeric.A.rows(), K::rows);
    ASSERT_EQ(numeric.A.cols(), K::size);
    for (int r = 0; r < K::rows; ++r) {
      for (int c = 0; c < K::size; ++c) {
        worst_A =
            std::max(worst_A, std::abs(A[static_cast<size_t>(r * K::size + c)] - numeric.A(r, c)));
        scale_A = std::max(scale_A, std::abs(numeric.A(r, c)));
      }
      worst_b = std::max(worst_b, std::abs(b[static_cast<size_t>(r)] - numeric.b[r]));
      scale_b = std::max(scale_b, std::abs(numeric.b[r]));
    }
    K::to_columns(in, s, row.data());
    std::vector<double> x;
    for (int c = 0; c < K::size; ++c) {
      ASSERT_TRUE(column.count(K::unknowns[c])) << K::unknowns[c];
      x.push_back(row[column.at(K::unknowns[c])]);
    }
    for (int r = 0; r < K::rows; ++r) {
      double sum = -b[static_cast<size_t>(r)];
      scale_terms = std::max(scale_terms, std::abs(b[static_cast<size_t>(r)]));
      for (int c = 0; c < K::size; ++c) {
        const double term = A[static_cast<size_t>(r * K::size + c)] * x[static_cast<size_t>(c)];
        sum += term;
        scale_terms = std::max(scale_terms, std::abs(term));
      }
      worst_residual = std::max(worst_residual, std::abs(sum));
    }
  }
  EXPECT_GT(scale_b, 1e-3);
  EXPECT_LT(worst_A, 1e-9 * scale_A) << name;
  EXPECT_LT(worst_b, 1e-9 * scale_b) << name;
  EXPECT_LT(worst_residual, 1e-10 * scale_terms) << name;
  std::cout << name << " ne_system (" << K::rows << " x " << K::size << "), " << samples
            << " samples: A - numeric " << worst_A << " of " << scale_A << ", b - numeric "
            << worst_b << " of " << scale_b << ", own solution's residual " << worst_residual
            << " of the largest term " << scale_terms << "\n";
}

TEST(SpatialNeSystem, RsurOwnSolutionSolvesTheNumericSolversSystem) {
  const SpatialModel model = shipped("rsur");
  ne_system_equals_numeric<rsur>("rsur", model.common.default_parameters());
}

// Redundant circuits: the kernel's minimum-norm reactions are one solution of A x = b.
TEST(SpatialNeSystem, ChebyshevSpatialOwnSolutionSolvesTheNumericSolversSystem) {
  const SpatialModel model = shipped("chebyshev_spatial");
  ne_system_equals_numeric<chebyshev_spatial>("chebyshev_spatial",
                                              model.common.default_parameters());
}

TEST(SpatialNeSystem, QuadrupedLegOwnSolutionSolvesTheNumericSolversSystem) {
  const SpatialModel model = shipped("quadruped_leg");
  ne_system_equals_numeric<quadruped_leg>("quadruped_leg", model.common.default_parameters(), 30);
  // With a foot load, b carries it.
  ne_system_equals_numeric<quadruped_leg>(
      "quadruped_leg",
      with(model, model.common.default_parameters(),
           {{"F_foot_x", 40}, {"F_foot_y", -25}, {"F_foot_z", 150}}),
      30);
}

// The foot load through the registry's kernel sweep against the numeric sweep: every column
// (efforts and reactions included) to 1e-9 of its scale, default and changed geometry.
TEST(SpatialNeSystem, QuadrupedLegWithAFootLoadEqualsTheNumericSweep) {
  const SpatialModel model = shipped("quadruped_leg");
  const std::map<std::string, double> load{{"F_foot_x", 40}, {"F_foot_y", -25}, {"F_foot_z", 150}};
  sweep_equals_numeric("quadruped_leg", 0,
                       {with(model, model.common.default_parameters(), load),
                        with(model, changed_parameters(model), load)});
}

// Seed 002's statics: at rest, a force F on the foot D changes the cylinders' forces by -J_D^T F
// (virtual power: effort . q' + F . v_D = 0 for the load's share), J_D the kernel's own foot
// velocity Jacobian, over a grid of the stroke box.
TEST(SpatialNeSystem, QuadrupedFootLoadReachesTheCylindersAsTheJacobianTransposed) {
  const SpatialModel model = shipped("quadruped_leg");
  const std::vector<double> defaults = model.common.default_parameters();
  const quadruped_leg::Params bare = quadruped_leg::params(defaults);
  const double F[3] = {40, -25, 150};
  const quadruped_leg::Params loaded = quadruped_leg::params(
      with(model, defaults, {{"F_foot_x", F[0]}, {"F_foot_y", F[1]}, {"F_foot_z", F[2]}}));
  // The strokes' mid-range coordinates (the reference lengths are those at t = 0 minus the law).
  const quadruped_leg::Inputs mid = quadruped_leg::inputs(bare, 0);
  double worst = 0, largest = 0;
  for (const double d1 : {-0.04, 0.0, 0.04})
    for (const double d2 : {-0.04, 0.0, 0.04})
      for (const double d3 : {-0.015, 0.0, 0.015}) {
        quadruped_leg::Inputs in;
        in.l1 = mid.l1 + d1, in.l2 = mid.l2 + d2, in.l3 = mid.l3 + d3;
        quadruped_leg::State a, b;
        ASSERT_EQ(quadruped_leg::evaluate(bare, in, a), 0);
        ASSERT_EQ(quadruped_leg::evaluate(loaded, in, b), 0);
        const double change[3] = {b.drivers.l1.effort - a.drivers.l1.effort,
                                  b.drivers.l2.effort - a.drivers.l2.effort,
                                  b.drivers.l3.effort - a.drivers.l3.effort};
        for (int k = 0; k < 3; ++k) {
          double expected = 0;
          for (int r = 0; r < 3; ++r) expected -= b.point_jacobians.D[r][k] * F[r];
          worst = std::max(worst, std::abs(change[k] - expected));
          largest = std::max(largest, std::abs(expected));
        }
      }
  EXPECT_GT(largest, 10.0);
  EXPECT_LT(worst, 1e-10 * largest);
  std::cout << "quadruped_leg at rest, 27 poses: cylinder force change - (-J_D^T F) " << worst
            << " of " << largest << " N\n";
}

// An unreachable configuration (cylinder 1 beyond its stroke): ne_system() says so, naming the
// group as evaluate() does, and leaves A and b zero.
TEST(SpatialNeSystem, UnreachableLeavesTheSystemZero) {
  const SpatialModel model = shipped("quadruped_leg");
  const quadruped_leg::Params p = quadruped_leg::params(model.common.default_parameters());
  quadruped_leg::Inputs in = quadruped_leg::inputs(p, 0);
  in.l1 = 1.0;
  quadruped_leg::State s;
  std::vector<double> A(static_cast<size_t>(quadruped_leg::rows * quadruped_leg::size), 7.0),
      b(quadruped_leg::rows, 7.0);
  EXPECT_EQ(quadruped_leg::ne_system(p, in, s, A.data(), b.data()),
            static_cast<int>(gen::quadruped_leg::Status::unreachable));
  EXPECT_EQ(std::string(gen::quadruped_leg::group_names[s.failed_group]), "hip (link rod1)");
  EXPECT_TRUE(std::all_of(A.begin(), A.end(), [](double v) { return v == 0; }));
  EXPECT_TRUE(std::all_of(b.begin(), b.end(), [](double v) { return v == 0; }));
}

}  // namespace
}  // namespace mechgen::spatial
