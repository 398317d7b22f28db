// Forward dynamics per sample (issue 22 item 5): the drivers' accelerations under given efforts at
// given (q, qd), the mass matrix built on the way.
//   <model>/fd_generated: the kernel's forward_dynamics entry through CompiledKernel (mass_bias by
//     n + 1 evaluations of its inverse dynamics, then its unrolled LDL^T), as `simulate` calls it;
//   <model>/fd_numeric: what `simulate --solver numeric` does per stage: the numeric solver placed
//     at (q, qd) (Newton from the previous sample for closed chains), M and h by unit
//     accelerations, numeric::forward_accelerations (LDL^T);
//   leg6/fd_kdl: Orocos KDL's ChainDynParam (JntToMass + JntToCoriolis + JntToGravity) and an
//     Eigen LDLT solve, on the chain tests/kdl_model.hpp builds.
// PASIBOT and the quadruped leg on their model's step (forth and back, so that every sample
// continues from its neighbour), leg6 on 256 random samples. Every solver's accelerations are
// checked equal before timing (1e-8 of max(1, |qdd|)).
#include <benchmark/benchmark.h>

#include <Eigen/Dense>
#include <kdl/chaindynparam.hpp>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/simulate.hpp"
#include "kdl_model.hpp"
#include "model/model.hpp"
#include "model/spatial_model.hpp"
#include "numeric/mass_bias.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"
#include "sweep/compiled_kernel.hpp"
#include "sweep/sweep.hpp"

namespace mechgen::bench {
namespace {

using Eigen::VectorXd;

// One model's samples: time, drivers (q, qd, 0 per driver, the kernel's layout) and efforts.
struct Samples {
  std::string name;
  std::vector<double> parameters;
  std::vector<double> t;
  std::vector<VectorXd> q, qd, effort;
  std::vector<std::vector<double>> drivers;
  std::shared_ptr<sim::Plant> numeric;
  const CompiledKernel* kernel = nullptr;
  // The numeric benchmark's next sample, kept across its runs: the solver continues from the last
  // one it was placed at (check() leaves it next to sample 0).
  size_t next = 0;

  void add(double time, const VectorXd& a, const VectorXd& b, const VectorXd& e) {
    t.push_back(time), q.push_back(a), qd.push_back(b), effort.push_back(e);
    std::vector<double> d;
    for (Eigen::Index i = 0; i < a.size(); ++i) d.insert(d.end(), {a[i], b[i], 0.0});
    drivers.push_back(d);
  }
  // The model's step, forth and back; efforts that make every driver accelerate.
  void along_step(double t0, double t1, int samples) {
    std::vector<double> times;
    for (int i = 0; i < samples; ++i) times.push_back(t0 + (t1 - t0) * i / (samples - 1));
    for (int i = samples - 2; i > 0; --i) times.push_back(times[static_cast<size_t>(i)]);
    for (const double time : times) {
      VectorXd a, b;
      numeric->motion(time, a, b);
      add(time, a, b, VectorXd::LinSpaced(a.size(), 0.5, 1.5));
    }
  }

  VectorXd numeric_qdd(size_t i) const {
    numeric::MassBias mb;
    std::string why;
    VectorXd qdd;
    if (!numeric->place(t[i], q[i], qd[i], mb, why) ||
        !numeric::forward_accelerations(mb, effort[i], qdd))
      throw std::runtime_error(name + ": numeric forward dynamics failed: " + why);
    return qdd;
  }
  VectorXd generated_qdd(size_t i) const {
    VectorXd qdd(q[i].size());
    int group = -1;
    if (kernel->forward_dynamics_double(parameters.data(), t[i], drivers[i].data(),
                                        effort[i].data(), qdd.data(), &group) != 0)
      throw std::runtime_error(name + ": generated forward dynamics failed");
    return qdd;
  }
  void check() const {
    for (size_t i = 0; i < t.size(); ++i) {
      const VectorXd a = numeric_qdd(i), b = generated_qdd(i);
      if ((a - b).cwiseAbs().maxCoeff() > 1e-8 * std::max(1.0, a.cwiseAbs().maxCoeff()))
        throw std::runtime_error(name + ": generated and numeric accelerations differ");
    }
  }
  void register_pair() const {
    auto self = std::make_shared<Samples>(*this);
    benchmark::RegisterBenchmark((name + "/fd_generated").c_str(), [self](benchmark::State& s) {
      size_t i = 0;
      for (auto _ : s) {
        benchmark::DoNotOptimize(self->generated_qdd(i));
        i = (i + 1) % self->t.size();
      }
    })->Unit(benchmark::kNanosecond);
    benchmark::RegisterBenchmark((name + "/fd_numeric").c_str(), [self](benchmark::State& s) {
      for (auto _ : s) {
        benchmark::DoNotOptimize(self->numeric_qdd(self->next));
        self->next = (self->next + 1) % self->t.size();
      }
    })->Unit(benchmark::kNanosecond);
  }
};

const CompiledKernel& kernel_of(const std::string& name) {
  const CompiledKernel* kernel = find_compiled_kernel(name);
  if (kernel == nullptr) throw std::runtime_error("no compiled kernel " + name);
  return *kernel;
}

// The description outlives every plant made from it.
template <class M>
const M& keep(M model) {
  static std::vector<std::shared_ptr<M>> kept;
  kept.push_back(std::make_shared<M>(std::move(model)));
  return *kept.back();
}

void register_pasibot() {
  const Model& model = keep(read_model(MECHGEN_SOURCE_DIR "/models/pasibot.yaml"));
  Samples s;
  s.name = "pasibot";
  s.parameters = model.default_parameters();
  s.kernel = &kernel_of("pasibot");
  s.numeric = sim::planar_plant(model, s.parameters);
  const SweepOptions step = default_sweep(model, s.parameters);
  s.along_step(step.t0, step.t1, step.samples);
  s.check();
  s.register_pair();
}

void register_spatial(const std::string& name, bool random) {
  const SpatialModel& model =
      keep(read_spatial_model(std::string(MECHGEN_SOURCE_DIR) + "/models/" + name + ".yaml"));
  const spatial::SpatialSweepOptions step = spatial::default_spatial_sweep(model);
  Samples s;
  s.name = name;
  s.parameters = step.parameters;
  s.kernel = &kernel_of(name);
  s.numeric = sim::spatial_plant(model, s.parameters);
  if (!random) {
    s.along_step(step.t0, step.t1, step.samples);
  } else {  // the samples of bench/spatial_bench.cpp (seed 3)
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 256; ++i) {
      VectorXd a(6), b(6), c(6);
      for (int k = 0; k < 6; ++k) a[k] = 1.5 * u(rng), b[k] = 2 * u(rng), c[k] = 5 * u(rng);
      s.add(step.t0, a, b, c);
    }
  }
  s.check();
  s.register_pair();
  if (!random) return;
  // KDL: M, C qd and G from ChainDynParam, then Eigen's LDLT.
  const spatial::SpatialSolver solver(model, s.parameters);
  auto chain = std::make_shared<KDL::Chain>(kdl_model::chain(solver, "foot"));
  auto dyn =
      std::make_shared<KDL::ChainDynParam>(*chain, kdl_model::vec(solver.instance().gravity));
  auto samples = std::make_shared<Samples>(s);
  const auto kdl_qdd = [chain, dyn, samples](size_t i, KDL::JntSpaceInertiaMatrix& M,
                                             KDL::JntArray& c, KDL::JntArray& g) {
    KDL::JntArray q(6), qd(6);
    q.data = samples->q[i];
    qd.data = samples->qd[i];
    dyn->JntToMass(q, M);
    dyn->JntToCoriolis(q, qd, c);
    dyn->JntToGravity(q, g);
    return VectorXd(M.data.ldlt().solve(samples->effort[i] - c.data - g.data));
  };
  for (size_t i = 0; i < s.t.size(); ++i) {
    KDL::JntSpaceInertiaMatrix M(6);
    KDL::JntArray c(6), g(6);
    const VectorXd a = kdl_qdd(i, M, c, g), b = s.generated_qdd(i);
    if ((a - b).cwiseAbs().maxCoeff() > 1e-8 * std::max(1.0, a.cwiseAbs().maxCoeff()))
      throw std::runtime_error(name + ": generated and KDL accelerations differ");
  }
  benchmark::RegisterBenchmark((name + "/fd_kdl").c_str(), [kdl_qdd,
                                                            samples](benchmark::State& state) {
    KDL::JntSpaceInertiaMatrix M(6);
    KDL::JntArray c(6), g(6);
    size_t i = 0;
    for (auto _ : state) {
      benchmark::DoNotOptimize(kdl_qdd(i, M, c, g));
      i = (i + 1) % samples->t.size();
    }
  })->Unit(benchmark::kNanosecond);
}

[[maybe_unused]] const bool registered = [] {
  register_pasibot();
  register_spatial("quadruped_leg", false);
  register_spatial("leg6", true);
  return true;
}();

}  // namespace
}  // namespace mechgen::bench
