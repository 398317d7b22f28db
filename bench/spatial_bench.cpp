// rsur/numeric, chebyshev_spatial/numeric: the spatial reference solver per sample along the
// model's step (closed chains).
// leg6/numeric: the spatial reference solver per sample (product of exponentials, twists and
// their rates, the foot's screw Jacobian, the spatial Newton-Euler solve), beside leg6/kdl: Orocos
// KDL's ChainFkSolverPos_recursive + ChainJntToJacSolver + ChainIdSolver_RNE on the same chain
// (tests/kdl_model.hpp builds it from the same numbers). The baseline the generated spatial
// kernels of issue 11 must beat.
#include "spatial_bench.hpp"

#include <benchmark/benchmark.h>

#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <memory>
#include <random>
#include <stdexcept>

#include "kdl_model.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"

namespace mechgen::bench {
namespace {

struct Leg6 {
  SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/leg6.yaml");
  spatial::SpatialSolver solver{model, {}};
  KDL::Chain chain = kdl_model::chain(solver, "foot");
  std::vector<Eigen::VectorXd> q, qd, qdd;  // 256 random samples
  int foot = model.body_index("foot_link");

  Leg6() {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 256; ++i) {
      Eigen::VectorXd a(6), b(6), c(6);
      for (int k = 0; k < 6; ++k) a[k] = 1.5 * u(rng), b[k] = 2 * u(rng), c[k] = 5 * u(rng);
      q.push_back(a), qd.push_back(b), qdd.push_back(c);
    }
  }
  // The numeric solver's sample i: torques, with the foot's Jacobian and position kept alive.
  Eigen::VectorXd numeric(size_t i, spatial::SpatialState& s, Eigen::MatrixXd& J,
                          spatial::V3& x) const {
    s.q = q[i];
    solver.place(s);
    solver.rates(s, qd[i], qdd[i]);
    x = solver.point_position(s, foot, solver.instance().points[static_cast<size_t>(foot)][0]);
    J = solver.point_jacobian(s, foot, x);
    return spatial::inverse_dynamics(solver, s).effort;
  }
};

KDL::JntArray jnt(const Eigen::VectorXd& x) {
  KDL::JntArray a(static_cast<unsigned>(x.size()));
  a.data = x;
  return a;
}

// <model>/numeric for a closed chain: SpatialSolver::solve (Newton closure from the previous
// sample, Davies' velocities, exact accelerations) + inverse dynamics, walking the model's default
// step forth and back so each sample continues from its neighbour.
void register_closed_chain(const std::string& name) {
  auto model = std::make_shared<SpatialModel>(
      read_spatial_model(std::string(MECHGEN_SOURCE_DIR) + "/models/" + name + ".yaml"));
  auto solver = std::make_shared<spatial::SpatialSolver>(*model, std::vector<double>{});
  const spatial::SpatialSweepOptions step = spatial::default_spatial_sweep(*model);
  std::vector<double> times;
  for (int i = 0; i < step.samples; ++i)
    times.push_back(step.t0 + (step.t1 - step.t0) * i / (step.samples - 1));
  for (int i = step.samples - 2; i > 0; --i) times.push_back(times[static_cast<size_t>(i)]);
  benchmark::RegisterBenchmark((name + "/numeric").c_str(), [model, solver,
                                                             times](benchmark::State& state) {
    spatial::SpatialState s;
    size_t i = 0;
    for (auto _ : state) {
      solver->solve(times[i], s);
      benchmark::DoNotOptimize(spatial::inverse_dynamics(*solver, s).effort.data());
      i = (i + 1) % times.size();
    }
  })->Unit(benchmark::kNanosecond);
}

}  // namespace

void register_spatial_benchmarks() {
  register_closed_chain("rsur");
  register_closed_chain("chebyshev_spatial");
  register_closed_chain("quadruped_leg");
  register_closed_chain("quadruped_leg_swing");
  auto leg = std::make_shared<Leg6>();
  {  // The two must agree before either is timed.
    KDL::ChainIdSolver_RNE id(leg->chain, kdl_model::vec(leg->solver.instance().gravity));
    KDL::Wrenches none(leg->chain.getNrOfSegments(), KDL::Wrench::Zero());
    for (size_t i = 0; i < leg->q.size(); ++i) {
      spatial::SpatialState s;
      Eigen::MatrixXd J;
      spatial::V3 x;
      KDL::JntArray torque(6);
      id.CartToJnt(jnt(leg->q[i]), jnt(leg->qd[i]), jnt(leg->qdd[i]), none, torque);
      if ((leg->numeric(i, s, J, x) - torque.data).cwiseAbs().maxCoeff() > 1e-12)
        throw std::runtime_error("leg6: numeric and KDL torques differ");
    }
  }
  benchmark::RegisterBenchmark("leg6/numeric", [leg](benchmark::State& state) {
    spatial::SpatialState s;
    Eigen::MatrixXd J;
    spatial::V3 x;
    size_t i = 0;
    for (auto _ : state) {
      benchmark::DoNotOptimize(leg->numeric(i, s, J, x));
      benchmark::DoNotOptimize(J.data());
      i = (i + 1) % leg->q.size();
    }
  })->Unit(benchmark::kNanosecond);
  benchmark::RegisterBenchmark("leg6/kdl", [leg](benchmark::State& state) {
    KDL::ChainFkSolverPos_recursive fk(leg->chain);
    KDL::ChainJntToJacSolver jac(leg->chain);
    KDL::ChainIdSolver_RNE id(leg->chain, kdl_model::vec(leg->solver.instance().gravity));
    const KDL::Wrenches none(leg->chain.getNrOfSegments(), KDL::Wrench::Zero());
    std::vector<KDL::JntArray> q, qd, qdd;
    for (size_t k = 0; k < leg->q.size(); ++k)
      q.push_back(jnt(leg->q[k])), qd.push_back(jnt(leg->qd[k])), qdd.push_back(jnt(leg->qdd[k]));
    KDL::Frame frame;
    KDL::Jacobian J(6);
    KDL::JntArray torque(6);
    size_t i = 0;
    for (auto _ : state) {
      fk.JntToCart(q[i], frame);
      jac.JntToJac(q[i], J);
      id.CartToJnt(q[i], qd[i], qdd[i], none, torque);
      benchmark::DoNotOptimize(frame.p.data);
      benchmark::DoNotOptimize(J.data.data());
      benchmark::DoNotOptimize(torque.data.data());
      i = (i + 1) % q.size();
    }
  })->Unit(benchmark::kNanosecond);
}

}  // namespace mechgen::bench
