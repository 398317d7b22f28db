// The Bioloid single-support samples (issue 13): whole-body states of the walking gait (right foot
// in support, 64 samples of the first step, solved beforehand by the numeric solver) and the
// generated kernel generated/bioloid_support_r_foot's inputs and placement for each. One set,
// shared by bioloid_support/* (bench/support_bench.cpp) and bioloid_support/mujoco
// (bench/mujoco_bench.cpp), so their timings are like for like.
#pragma once

#include <cmath>
#include <stdexcept>
#include <vector>

#include "bioloid_support_r_foot/bioloid_support_r_foot.hpp"
#include "model/support_model.hpp"
#include "spatial/humanoid_gait.hpp"
#include "spatial/spatial_solver.hpp"

// The real joints of models/bioloid.yaml, each driven by <joint>_drive in the kernel.
// clang-format off
#define MECHGEN_BIOLOID_JOINTS \
  X(RL1) X(RL2) X(RL3) X(RL4) X(RL5) X(RL6) \
  X(LL1) X(LL2) X(LL3) X(LL4) X(LL5) X(LL6) \
  X(RA1) X(RA2) X(RA3) X(RA4) X(RA5) X(RA6) \
  X(LA1) X(LA2) X(LA3) X(LA4) X(LA5) X(LA6)
// clang-format on

namespace mechgen::bench {

struct BioloidSupport {
  using Inputs = gen::bioloid_support_r_foot::Inputs<double>;
  using Params = gen::bioloid_support_r_foot::Params<double>;

  SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/bioloid.yaml");
  spatial::SpatialSolver solver{model, {}};
  spatial::HumanoidGait gait{solver, spatial::gait_settings(solver)};
  SpatialModel welded = weld_support(model, "r_foot");
  int foot = model.body_index("r_foot");
  std::vector<spatial::SpatialState> states;
  std::vector<Inputs> inputs;
  std::vector<Params> params;

  // The foot's point RF at the reference pose: the placement parameters' defaults.
  spatial::V3 at_reference() const {
    const std::vector<double> p = welded.common.default_parameters();
    const auto i = static_cast<size_t>(welded.common.parameter_index(kSupportPlacement[0]));
    return {p[i], p[i + 1], p[i + 2]};
  }

  BioloidSupport() {
    const double T = gait.settings().step_time;
    for (int i = 0; i < 64; ++i) {
      spatial::SpatialState s;
      gait.solve(T * (i + 0.5) / 64, s);
      if (gait.support(s.t) != 0) throw std::logic_error("bioloid_support: not on the right foot");
      Inputs in;
      in.t = s.t;
#define X(J)                                                                               \
  {                                                                                        \
    const int c = solver.graph().joint_column[static_cast<size_t>(model.joint_index(#J))]; \
    in.J##_drive = s.q[c], in.J##_drive_d = s.qd[c], in.J##_drive_dd = s.qdd[c];           \
  }
      MECHGEN_BIOLOID_JOINTS
#undef X
      // The placement: the foot's point RF and its heading (flat: a turn about z).
      const spatial::Pose& D = s.D[static_cast<size_t>(foot)];
      const spatial::V3 at = geometry::apply(D, at_reference());
      Params p;
      p.support_x = at[0], p.support_y = at[1], p.support_z = at[2];
      p.support_heading = std::atan2(D.R(1, 0), D.R(0, 0));
      states.push_back(s);
      inputs.push_back(in);
      params.push_back(p);
    }
  }
};

// The one set (built on first use: the gait's 64 whole-body solves).
inline const BioloidSupport& bioloid_support() {
  static const BioloidSupport samples;
  return samples;
}

}  // namespace mechgen::bench
