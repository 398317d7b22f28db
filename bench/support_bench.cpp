// bioloid_support/*: single-support inverse dynamics of the Bioloid (issue 13) per sample, on
// whole-body states of the walking gait (right foot in support, 64 samples of the first step,
// solved beforehand by the numeric solver; bench/bioloid_support_samples.hpp, shared with
// bioloid_support/mujoco in bench/mujoco_bench.cpp):
//  - generated: the generated kernel generated/bioloid_support_r_foot evaluate() from the joint
//    angles, rates and accelerations and the placement: every body's pose, twist and twist rate,
//    every screw Jacobian, every joint torque and reaction, the floor wrench;
//  - generated_control: its control(): Jacobians and joint torques (no reactions, no floor wrench);
//  - generated_runtime: spatial::SupportKernel::loads, what `mechgen humanoid-gait` calls (the
//    placement read off the state, the compiled kernel's row, the torques and floor wrench);
//  - numeric: spatial::single_support_dynamics (floating_base.hpp) on the solved whole-body state
//    (the kinematics already done: body wrenches and the recursion only);
//  - numeric_tree: the numeric reference solver on the welded tree from the kernel's own inputs
//    (positions, twists and twist rates from the joint angles, rates and accelerations, then its
//    dense Newton-Euler solve: every torque and reaction), the same work as `generated`.
// The generated torques are checked equal to the numeric ones (1e-9), and control()'s torques and
// Jacobians to evaluate()'s (1e-12), before timing.
#include <benchmark/benchmark.h>

#include <cmath>
#include <stdexcept>

#include "bioloid_support_samples.hpp"
#include "spatial/floating_base.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/support_kernel.hpp"

namespace mechgen::bench {
namespace {

namespace k = gen::bioloid_support_r_foot;

void check(const BioloidSupport& b) {
  for (size_t i = 0; i < b.states.size(); ++i) {
    const spatial::FloatingBaseLoads numeric =
        spatial::single_support_dynamics(b.solver, b.states[i], b.foot);
    k::State<double> s;
    if (k::evaluate(b.params[i], b.inputs[i], s) != k::Status::ok)
      throw std::runtime_error("bioloid_support: the kernel failed");
#define X(J)                                                                         \
  if (std::abs(s.drivers.J##_drive.effort -                                          \
               numeric.torque[static_cast<size_t>(b.model.joint_index(#J))]) > 1e-9) \
    throw std::runtime_error("bioloid_support: generated and numeric torques differ at " #J);
    MECHGEN_BIOLOID_JOINTS
#undef X
    if (std::abs(s.joints.r_foot_weld.fz - numeric.floor.f[2]) > 1e-9)
      throw std::runtime_error("bioloid_support: generated and numeric floor forces differ");
    // control() is its own straight line (spatial_emitter.cpp, kStraightControlBelow), not the
    // stages evaluate() calls: its torques and Jacobians must be evaluate()'s.
    k::State<double> c;
    if (k::control(b.params[i], b.inputs[i], c) != k::Status::ok)
      throw std::runtime_error("bioloid_support: control() failed");
#define X(J)                                                              \
  if (std::abs(c.drivers.J##_drive.effort - s.drivers.J##_drive.effort) > \
      1e-12 * (1 + std::abs(s.drivers.J##_drive.effort)))                 \
    throw std::runtime_error("bioloid_support: control() and evaluate() torques differ at " #J);
    MECHGEN_BIOLOID_JOINTS
#undef X
    const auto* jc = &c.body_jacobians.r_foot[0][0];
    const auto* je = &s.body_jacobians.r_foot[0][0];
    for (size_t e = 0; e < sizeof s.body_jacobians / sizeof(double); ++e)
      if (std::abs(jc[e] - je[e]) > 1e-12)
        throw std::runtime_error("bioloid_support: control() and evaluate() Jacobians differ");
  }
}

[[maybe_unused]] const bool registered = [] {
  const BioloidSupport* b = &bioloid_support();
  check(*b);
  benchmark::RegisterBenchmark("bioloid_support/generated", [b](benchmark::State& state) {
    k::State<double> s;
    size_t i = 0;
    for (auto _ : state) {
      benchmark::DoNotOptimize(k::evaluate(b->params[i], b->inputs[i], s));
      benchmark::DoNotOptimize(&s);
      i = (i + 1) % b->inputs.size();
    }
  })->Unit(benchmark::kNanosecond);
  benchmark::RegisterBenchmark("bioloid_support/generated_control", [b](benchmark::State& state) {
    k::State<double> s;
    size_t i = 0;
    for (auto _ : state) {
      benchmark::DoNotOptimize(k::control(b->params[i], b->inputs[i], s));
      benchmark::DoNotOptimize(&s);
      i = (i + 1) % b->inputs.size();
    }
  })->Unit(benchmark::kNanosecond);
  benchmark::RegisterBenchmark("bioloid_support/generated_runtime", [b](benchmark::State& state) {
    const CompiledKernel* kernel = find_compiled_kernel(b->welded.common.name);
    if (!kernel) {
      state.SkipWithError("bioloid_support_r_foot is not compiled in");
      return;
    }
    const spatial::SupportKernel support(b->solver, b->welded, b->foot, *kernel);
    size_t i = 0;
    for (auto _ : state) {
      benchmark::DoNotOptimize(support.loads(b->states[i]));
      i = (i + 1) % b->states.size();
    }
  })->Unit(benchmark::kNanosecond);
  benchmark::RegisterBenchmark("bioloid_support/numeric_tree", [b](benchmark::State& state) {
    // The welded tree placed where the samples' foot is (it stands still over the step).
    std::vector<double> params = b->solver.parameters();
    params.insert(params.end(), {b->params[0].support_x, b->params[0].support_y,
                                 b->params[0].support_z, b->params[0].support_heading});
    const spatial::SpatialSolver tree(b->welded, params);
    const SpatialGraph& g = tree.graph();
    const auto n = static_cast<Eigen::Index>(g.primary.size());
    std::vector<Eigen::VectorXd> q, qd, qdd;
    for (const spatial::SpatialState& s : b->states) {
      q.emplace_back(n), qd.emplace_back(n), qdd.emplace_back(n);
      for (Eigen::Index k = 0; k < n; ++k) {
        const SpatialColumn& c = g.columns[static_cast<size_t>(g.primary[static_cast<size_t>(k)])];
        const int j = b->model.joint_index(b->welded.joints[static_cast<size_t>(c.joint)].name);
        const int col = b->solver.graph().joint_column[static_cast<size_t>(j)] + c.index;
        q.back()[k] = s.q[col], qd.back()[k] = s.qd[col], qdd.back()[k] = s.qdd[col];
      }
    }
    spatial::SpatialState s;
    tree.solve(0, q[0], qd[0], qdd[0], s);
    size_t i = 0;
    for (auto _ : state) {
      tree.solve(b->states[i].t, q[i], qd[i], qdd[i], s);
      benchmark::DoNotOptimize(spatial::inverse_dynamics(tree, s));
      i = (i + 1) % b->states.size();
    }
  })->Unit(benchmark::kNanosecond);
  benchmark::RegisterBenchmark("bioloid_support/numeric", [b](benchmark::State& state) {
    size_t i = 0;
    for (auto _ : state) {
      benchmark::DoNotOptimize(spatial::single_support_dynamics(b->solver, b->states[i], b->foot));
      i = (i + 1) % b->states.size();
    }
  })->Unit(benchmark::kNanosecond);
  return true;
}();
}  // namespace
}  // namespace mechgen::bench
