// <model>/generated for the closed chains rsur, chebyshev_spatial, quadruped_leg and
// quadruped_leg_swing (the leg's inverse kinematics along the seed's swing, closed form): the
// generated kernel's evaluate() per sample (positions: closed-form link groups for rsur and
// quadruped_leg, the planar loop's RRR dyad in its plane for chebyshev_spatial (5 unrolled
// Newton-Raphson steps before it); Davies' velocities and accelerations, every body's pose, twist
// and twist rate, the named points, the screw Jacobians, the driver efforts by virtual power and
// every joint reaction through N_s transposed). <model>/numeric_kinematics: the reference solver's
// SpatialSolver::solve on the same walk (Newton closure from the previous sample, Davies'
// velocities, exact accelerations); <model>/numeric (bench/spatial_bench.cpp) adds its inverse
// dynamics: the like-for-like baseline of evaluate(). quadruped_leg/point_positions: one
// workspace sample (the foot and the other named points only, from the parameter set's
// constants). The model's step walked forth and back; checked equal to the numeric solver
// (1e-9) before timing.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "chebyshev_spatial/chebyshev_spatial.hpp"
#include "quadruped_leg/quadruped_leg.hpp"
#include "quadruped_leg_swing/quadruped_leg_swing.hpp"
#include "rsur/rsur.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"

namespace mechgen::bench {
namespace {

// A kernel namespace's types and entry points, so that one walk serves the three models.
template <class P, class I, class S, class St>
struct Kernel {
  St (*evaluate)(const P&, const I&, S&);
  void (*driver_inputs)(const P&, double, I&);
};

template <class P, class I, class S, class St>
struct Walk {
  SpatialModel model;
  spatial::SpatialSolver solver;
  std::vector<double> times;
  std::vector<I> inputs;
  P params;

  explicit Walk(const std::string& name, const Kernel<P, I, S, St>& k)
      : model(read_spatial_model(std::string(MECHGEN_SOURCE_DIR) + "/models/" + name + ".yaml")),
        solver(model, {}) {
    const spatial::SpatialSweepOptions step = spatial::default_spatial_sweep(model);
    for (int i = 0; i < step.samples; ++i)
      times.push_back(step.t0 + (step.t1 - step.t0) * i / (step.samples - 1));
    for (int i = step.samples - 2; i > 0; --i) times.push_back(times[static_cast<size_t>(i)]);
    for (const double t : times) {
      I in;
      k.driver_inputs(params, t, in);
      inputs.push_back(in);
    }
  }
};

// One named point of the kernel against the numeric solver along the walk.
template <class P, class I, class S, class St, class Point>
void check_against_numeric(const std::string& name, const Walk<P, I, S, St>& walk,
                           const Kernel<P, I, S, St>& k, const std::string& point,
                           const Point& generated) {
  int body = -1;
  spatial::V3 local{};
  for (const auto& [n, b] : walk.model.named_points())
    if (n == point) {
      body = b;
      const auto& points = walk.model.bodies[static_cast<size_t>(b)].points;
      for (size_t index = 0; index < points.size(); ++index)
        if (points[index].name == point)
          local = walk.solver.instance().points[static_cast<size_t>(b)][index];
    }
  spatial::SpatialState st;
  S s;
  for (size_t i = 0; i < walk.times.size(); ++i) {
    walk.solver.solve(walk.times[i], st);
    if (k.evaluate(walk.params, walk.inputs[i], s) != St::ok)
      throw std::runtime_error(name + ": the generated kernel did not close the circuits");
    const spatial::V3 expected = walk.solver.point_position(st, body, local);
    const std::array<double, 3> x = generated(s);
    for (size_t a = 0; a < 3; ++a)
      if (!(std::abs(x[a] - expected[a]) <= 1e-9))
        throw std::runtime_error(name + ": generated and numeric point " + point + " differ");
  }
}

template <class P, class I, class S, class St, class Point>
void register_model(const std::string& name, const Kernel<P, I, S, St>& k, const std::string& point,
                    const Point& generated) {
  auto walk = std::make_shared<Walk<P, I, S, St>>(name, k);
  check_against_numeric(name, *walk, k, point, generated);
  benchmark::RegisterBenchmark((name + "/generated").c_str(), [walk, k](benchmark::State& state) {
    S s;
    size_t i = 0;
    for (auto _ : state) {
      benchmark::DoNotOptimize(k.evaluate(walk->params, walk->inputs[i], s));
      benchmark::DoNotOptimize(&s);
      i = (i + 1) % walk->inputs.size();
    }
  })->Unit(benchmark::kNanosecond);
  benchmark::RegisterBenchmark((name + "/numeric_kinematics").c_str(),
                               [walk](benchmark::State& state) {
                                 spatial::SpatialState s;
                                 size_t i = 0;
                                 for (auto _ : state) {
                                   walk->solver.solve(walk->times[i], s);
                                   benchmark::DoNotOptimize(s.qdd.data());
                                   i = (i + 1) % walk->times.size();
                                 }
                               })
      ->Unit(benchmark::kNanosecond);
}

namespace r = gen::rsur;
namespace c = gen::chebyshev_spatial;
namespace q = gen::quadruped_leg;
namespace qs = gen::quadruped_leg_swing;

[[maybe_unused]] const bool registered = [] {
  register_model("rsur",
                 Kernel<r::Params<double>, r::Inputs<double>, r::State<double>, r::Status>{
                     &r::evaluate<double>, &r::driver_inputs<double>},
                 "C", [](const r::State<double>& s) {
                   return std::array<double, 3>{s.points.C.x, s.points.C.y, s.points.C.z};
                 });
  register_model("chebyshev_spatial",
                 Kernel<c::Params<double>, c::Inputs<double>, c::State<double>, c::Status>{
                     &c::evaluate<double>, &c::driver_inputs<double>},
                 "C", [](const c::State<double>& s) {
                   return std::array<double, 3>{s.points.C.x, s.points.C.y, s.points.C.z};
                 });
  register_model("quadruped_leg",
                 Kernel<q::Params<double>, q::Inputs<double>, q::State<double>, q::Status>{
                     &q::evaluate<double>, &q::driver_inputs<double>},
                 "D", [](const q::State<double>& s) {
                   return std::array<double, 3>{s.points.D.x, s.points.D.y, s.points.D.z};
                 });
  // The leg's inverse kinematics along the seed's swing (closed form: side swing, planar 2R,
  // coupler, cylinders from their end centres); G, cylinder 1's end on the thigh, checked.
  register_model("quadruped_leg_swing",
                 Kernel<qs::Params<double>, qs::Inputs<double>, qs::State<double>, qs::Status>{
                     &qs::evaluate<double>, &qs::driver_inputs<double>},
                 "G", [](const qs::State<double>& s) {
                   return std::array<double, 3>{s.points.G.x, s.points.G.y, s.points.G.z};
                 });
  // One workspace sample: the stroke box walked on a 9 x 9 x 9 grid.
  benchmark::RegisterBenchmark("quadruped_leg/point_positions", [](benchmark::State& state) {
    const q::Params<double> p;
    q::PositionConstants<double> k;
    q::position_constants(p, k);
    std::vector<q::Inputs<double>> grid;
    for (int i = 0; i < 729; ++i) {
      q::Inputs<double> in;
      in.l1 = -0.06 + 0.015 * (i % 9);
      in.l2 = -0.06 + 0.015 * (i / 9 % 9);
      in.l3 = -0.02 + 0.005 * (i / 81);
      grid.push_back(in);
    }
    q::State<double> s;
    size_t i = 0;
    for (auto _ : state) {
      benchmark::DoNotOptimize(q::point_positions(p, k, grid[i], s));
      benchmark::DoNotOptimize(&s);
      i = (i + 1) % grid.size();
    }
  })->Unit(benchmark::kNanosecond);
  return true;
}();

}  // namespace
}  // namespace mechgen::bench
