// Pose-driven models' generated kernels (closed-form limb inverse kinematics, no Newton) against
// the reference solver, per sample over the model's step:
//  - bioloid/generated: kinematics() of seed 001's humanoid: the four 6R limbs' angles in closed
//    form from the five virtual chains, Davies' velocities and exact accelerations through the
//    fixed-pivot elimination of the 24 x 24 N_s (block-diagonal per limb: no fill between
//    limbs), every body's pose, twist and twist rate, the named points and the screw Jacobians;
//  - bioloid/generated_velocities: velocities(), the same without accelerations and Jacobians
//    (positions, Davies velocities, twists, point velocities);
//  - bioloid/numeric_davies: the reference solver's rates() at the same (already placed) pose:
//    N built, N_s q_s' = -N_p q_p' and the accelerations by its dense solve (issue 13's baseline:
//    the velocity solve alone, less than the generated kernel computes);
//  - bioloid/numeric_kinematics: SpatialSolver::solve (Newton closure from the previous sample,
//    velocities, accelerations);
//  - lecture_leg_ik/generated and lecture_leg_ik/numeric_kinematics: seed 003's leg, foot
//    pose-driven (law of cosines against Newton).
// Each kernel is checked equal to the numeric solver (1e-9) before timing.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bioloid/bioloid.hpp"
#include "lecture_leg_ik/lecture_leg_ik.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"

namespace mechgen::bench {
namespace {

// The model's step: times, the kernel's inputs, the numeric solver's states.
template <class Inputs, class Params>
struct PoseWalk {
  SpatialModel model;
  spatial::SpatialSolver solver;
  std::vector<double> times;
  std::vector<Inputs> inputs;
  std::vector<spatial::SpatialState> states;
  std::vector<Eigen::VectorXd> qpd, qpdd;
  Params params;

  template <class DriverInputs>
  PoseWalk(const std::string& name, DriverInputs driver_inputs)
      : model(read_spatial_model(MECHGEN_SOURCE_DIR "/models/" + name + ".yaml")),
        solver(model, {}) {
    const spatial::SpatialSweepOptions step = spatial::default_spatial_sweep(model);
    spatial::SpatialState st;
    for (int i = 0; i < step.samples; ++i) {
      const double t = step.t0 + (step.t1 - step.t0) * i / (step.samples - 1);
      times.push_back(t);
      Inputs in;
      driver_inputs(params, t, in);
      inputs.push_back(in);
      solver.solve(t, st);
      states.push_back(st);
      Eigen::VectorXd q, qd, qdd;
      solver.primary_motion(t, q, qd, qdd);
      qpd.push_back(qd);
      qpdd.push_back(qdd);
    }
  }
  // The kernel's value of each secondary coordinate's rate, against the solver's.
  template <class Rates>
  void check(const std::string& name, Rates kernel_rates) const {
    for (size_t i = 0; i < times.size(); ++i) {
      const std::vector<double> qd = kernel_rates(inputs[i]);
      for (size_t k = 0; k < qd.size(); ++k)
        if (!(std::abs(qd[k] - states[i].qd[solver.graph().secondary[k]]) <= 1e-9))
          throw std::runtime_error(name + ": generated and numeric Davies velocities differ");
    }
  }
};

template <class Walk, class Kinematics>
void register_pair(const std::string& name, std::shared_ptr<Walk> walk, Kinematics kinematics,
                   bool davies) {
  benchmark::RegisterBenchmark((name + "/generated").c_str(), [walk, kinematics](
                                                                  benchmark::State& state) {
    size_t i = 0;
    for (auto _ : state) {
      benchmark::DoNotOptimize(kinematics(walk->inputs[i]));
      i = (i + 1) % walk->inputs.size();
    }
  })->Unit(benchmark::kNanosecond);
  if (davies)
    benchmark::RegisterBenchmark((name + "/numeric_davies").c_str(), [walk](
                                                                         benchmark::State& state) {
      size_t i = 0;
      for (auto _ : state) {
        walk->solver.rates(walk->states[i], walk->qpd[i], walk->qpdd[i]);
        benchmark::DoNotOptimize(walk->states[i].qd.data());
        i = (i + 1) % walk->states.size();
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

namespace bio = gen::bioloid;
namespace leg = gen::lecture_leg_ik;

[[maybe_unused]] const bool registered = [] {
  auto bioloid = std::make_shared<PoseWalk<bio::Inputs<double>, bio::Params<double>>>(
      "bioloid", [](const bio::Params<double>& p, double t, bio::Inputs<double>& in) {
        bio::driver_inputs(p, t, in);
      });
  auto state = std::make_shared<bio::State<double>>();
  bioloid->check("bioloid", [&](const bio::Inputs<double>& in) {
    if (bio::kinematics(bioloid->params, in, *state) != bio::Status::ok)
      throw std::runtime_error("bioloid: the generated kernel failed");
    const auto& j = state->joints;
    return std::vector<double>{j.RL1.qd, j.RL2.qd, j.RL3.qd, j.RL4.qd, j.RL5.qd, j.RL6.qd};
  });
  register_pair(
      "bioloid", bioloid,
      [bioloid, state](const bio::Inputs<double>& in) {
        return bio::kinematics(bioloid->params, in, *state);
      },
      true);
  // Issue 13's like-for-like measure: positions and Davies velocities alone (velocities()).
  bioloid->check("bioloid velocities()", [&](const bio::Inputs<double>& in) {
    if (bio::velocities(bioloid->params, in, *state) != bio::Status::ok)
      throw std::runtime_error("bioloid: the generated velocities() failed");
    const auto& j = state->joints;
    return std::vector<double>{j.RL1.qd, j.RL2.qd, j.RL3.qd, j.RL4.qd, j.RL5.qd, j.RL6.qd};
  });
  benchmark::RegisterBenchmark("bioloid/generated_velocities", [bioloid,
                                                                state](benchmark::State& bench) {
    size_t i = 0;
    for (auto _ : bench) {
      benchmark::DoNotOptimize(bio::velocities(bioloid->params, bioloid->inputs[i], *state));
      i = (i + 1) % bioloid->inputs.size();
    }
  })->Unit(benchmark::kNanosecond);
  auto lecture = std::make_shared<PoseWalk<leg::Inputs<double>, leg::Params<double>>>(
      "lecture_leg_ik", [](const leg::Params<double>& p, double t, leg::Inputs<double>& in) {
        leg::driver_inputs(p, t, in);
      });
  auto leg_state = std::make_shared<leg::State<double>>();
  lecture->check("lecture_leg_ik", [&](const leg::Inputs<double>& in) {
    if (leg::kinematics(lecture->params, in, *leg_state) != leg::Status::ok)
      throw std::runtime_error("lecture_leg_ik: the generated kernel failed");
    return std::vector<double>{leg_state->joints.j1.qd, leg_state->joints.j2.qd,
                               leg_state->joints.j3.qd};
  });
  register_pair(
      "lecture_leg_ik", lecture,
      [lecture, leg_state](const leg::Inputs<double>& in) {
        return leg::kinematics(lecture->params, in, *leg_state);
      },
      false);
  return true;
}();

}  // namespace
}  // namespace mechgen::bench
