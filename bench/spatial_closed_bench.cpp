// rsur/generated: the generated closed-chain kernel (generated/rsur/rsur.hpp) per sample,
// evaluate(): 5 unrolled Newton-Raphson steps on the closure from the previous sample's
// secondary coordinates, Davies' velocities and accelerations, every body's pose, twist and twist
// rate, the named points, the screw Jacobians, the driver effort (virtual power) and every joint
// reaction (N_s transposed). rsur/numeric_kinematics: the reference solver's
// SpatialSolver::solve on the same walk (Newton closure from the previous sample, Davies'
// velocities, exact accelerations); rsur/numeric (bench/spatial_bench.cpp) adds its inverse
// dynamics: the like-for-like baseline of evaluate(). The model's step walked forth and back;
// checked equal to the numeric solver (1e-9) before timing.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <stdexcept>

#include "rsur/rsur.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"

namespace mechgen::bench {
namespace {

namespace k = gen::rsur;

struct RsurWalk {
  SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/rsur.yaml");
  spatial::SpatialSolver solver{model, {}};
  std::vector<double> times;
  std::vector<k::Inputs<double>> inputs;
  k::Params<double> params;

  RsurWalk() {
    const spatial::SpatialSweepOptions step = spatial::default_spatial_sweep(model);
    for (int i = 0; i < step.samples; ++i)
      times.push_back(step.t0 + (step.t1 - step.t0) * i / (step.samples - 1));
    for (int i = step.samples - 2; i > 0; --i) times.push_back(times[static_cast<size_t>(i)]);
    for (const double t : times) {
      k::Inputs<double> in;
      k::driver_inputs(params, t, in);
      inputs.push_back(in);
    }
  }
};

void check_against_numeric(const RsurWalk& walk) {
  spatial::SpatialState st;
  k::State<double> s;
  int coupler = -1;
  for (size_t b = 0; b < walk.model.bodies.size(); ++b)
    if (walk.model.bodies[b].name == "coupler") coupler = static_cast<int>(b);
  for (size_t i = 0; i < walk.times.size(); ++i) {
    walk.solver.solve(walk.times[i], st);
    if (k::evaluate(walk.params, walk.inputs[i], s) != k::Status::ok)
      throw std::runtime_error("rsur: the generated kernel did not close the circuit");
    const geometry::Twist<double>& V = st.V[static_cast<size_t>(coupler)];
    if (std::abs(s.bodies.coupler.wx - V.w[0]) + std::abs(s.bodies.coupler.wy - V.w[1]) +
            std::abs(s.bodies.coupler.wz - V.w[2]) >
        1e-9)
      throw std::runtime_error("rsur: generated and numeric coupler twists differ");
  }
}

[[maybe_unused]] const bool registered = [] {
  auto walk = std::make_shared<RsurWalk>();
  check_against_numeric(*walk);
  benchmark::RegisterBenchmark("rsur/generated", [walk](benchmark::State& state) {
    k::State<double> s;
    size_t i = 0;
    for (auto _ : state) {
      benchmark::DoNotOptimize(k::evaluate(walk->params, walk->inputs[i], s));
      benchmark::DoNotOptimize(&s);
      i = (i + 1) % walk->inputs.size();
    }
  })->Unit(benchmark::kNanosecond);
  benchmark::RegisterBenchmark("rsur/numeric_kinematics", [walk](benchmark::State& state) {
    spatial::SpatialState s;
    size_t i = 0;
    for (auto _ : state) {
      walk->solver.solve(walk->times[i], s);
      benchmark::DoNotOptimize(s.qdd.data());
      i = (i + 1) % walk->times.size();
    }
  })->Unit(benchmark::kNanosecond);
  return true;
}();

}  // namespace
}  // namespace mechgen::bench
