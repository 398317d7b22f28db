// leg6/generated: the generated spatial kernel (generated/leg6/leg6.hpp) per sample, evaluate():
// every body's pose, twist and twist rate, the screw Jacobians of every body and named point, and
// the inverse dynamics (every driver torque and joint reaction); leg6/generated_control: control(),
// the named points, the Jacobians and the driver torques only; beside leg6/kdl and leg6/numeric
// (bench/spatial_bench.cpp) on the same 256 random samples. Registered at start-up; checked equal
// to KDL's torques (1e-12) before timing.
#include <benchmark/benchmark.h>

#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <memory>
#include <random>
#include <stdexcept>

#include "kdl_model.hpp"
#include "leg6/leg6.hpp"
#include "spatial/spatial_solver.hpp"

namespace mechgen::bench {
namespace {

namespace k = gen::leg6;

struct Leg6Kernel {
  std::vector<k::Inputs<double>> inputs;  // the samples of bench/spatial_bench.cpp (seed 3)
  k::Params<double> params;

  Leg6Kernel() {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 256; ++i) {
      double q[6], qd[6], qdd[6];
      for (int j = 0; j < 6; ++j) q[j] = 1.5 * u(rng), qd[j] = 2 * u(rng), qdd[j] = 5 * u(rng);
      k::Inputs<double> in;
      in.q1 = q[0], in.q2 = q[1], in.q3 = q[2], in.q4 = q[3], in.q5 = q[4], in.q6 = q[5];
      in.q1_d = qd[0], in.q2_d = qd[1], in.q3_d = qd[2], in.q4_d = qd[3], in.q5_d = qd[4],
      in.q6_d = qd[5];
      in.q1_dd = qdd[0], in.q2_dd = qdd[1], in.q3_dd = qdd[2], in.q4_dd = qdd[3], in.q5_dd = qdd[4],
      in.q6_dd = qdd[5];
      inputs.push_back(in);
    }
  }
};

void check_against_kdl(const Leg6Kernel& leg) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/leg6.yaml");
  const spatial::SpatialSolver solver(model, {});
  const KDL::Chain chain = kdl_model::chain(solver, "foot");
  KDL::ChainIdSolver_RNE id(chain, kdl_model::vec(solver.instance().gravity));
  const KDL::Wrenches none(chain.getNrOfSegments(), KDL::Wrench::Zero());
  for (const k::Inputs<double>& in : leg.inputs) {
    KDL::JntArray q(6), qd(6), qdd(6), torque(6);
    const double a[] = {in.q1, in.q2, in.q3, in.q4, in.q5, in.q6};
    const double b[] = {in.q1_d, in.q2_d, in.q3_d, in.q4_d, in.q5_d, in.q6_d};
    const double c[] = {in.q1_dd, in.q2_dd, in.q3_dd, in.q4_dd, in.q5_dd, in.q6_dd};
    for (unsigned j = 0; j < 6; ++j) q(j) = a[j], qd(j) = b[j], qdd(j) = c[j];
    id.CartToJnt(q, qd, qdd, none, torque);
    k::State<double> s;
    k::evaluate(leg.params, in, s);
    const double effort[] = {s.drivers.q1.effort, s.drivers.q2.effort, s.drivers.q3.effort,
                             s.drivers.q4.effort, s.drivers.q5.effort, s.drivers.q6.effort};
    for (unsigned j = 0; j < 6; ++j)
      if (std::abs(effort[j] - torque(j)) > 1e-12)
        throw std::runtime_error("leg6: generated and KDL torques differ");
  }
}

[[maybe_unused]] const bool registered = [] {
  auto leg = std::make_shared<Leg6Kernel>();
  check_against_kdl(*leg);
  benchmark::RegisterBenchmark("leg6/generated", [leg](benchmark::State& state) {
    k::State<double> s;
    size_t i = 0;
    for (auto _ : state) {
      benchmark::DoNotOptimize(k::evaluate(leg->params, leg->inputs[i], s));
      benchmark::DoNotOptimize(&s);
      i = (i + 1) % leg->inputs.size();
    }
  })->Unit(benchmark::kNanosecond);
  // control(): the named points, every screw Jacobian and the driver torques only, the closest
  // to KDL's FK + Jacobian + RNE (which give one frame, one Jacobian and the torques).
  benchmark::RegisterBenchmark("leg6/generated_control", [leg](benchmark::State& state) {
    k::State<double> s;
    size_t i = 0;
    for (auto _ : state) {
      benchmark::DoNotOptimize(k::control(leg->params, leg->inputs[i], s));
      benchmark::DoNotOptimize(&s);
      i = (i + 1) % leg->inputs.size();
    }
  })->Unit(benchmark::kNanosecond);
  return true;
}();

}  // namespace
}  // namespace mechgen::bench
