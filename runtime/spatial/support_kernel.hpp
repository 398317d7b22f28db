// Single-support inverse dynamics through a generated kernel (issue 13): the kernel of
// weld_support(description, support) (model/support_model.hpp: the support foot welded to the
// floor at its placement, every real joint driven) fed from a whole-body state of the description
// (Davies' method on the virtual chains): the real joints' angles, rates and accelerations, and
// the support's placement read off the state (its pose driver's `at` point and its heading). It
// computes what single_support_dynamics (floating_base.hpp) computes numerically: every real
// joint's torque and the floor's wrench on the support foot.
#pragma once

#include <string>
#include <vector>

#include "model/spatial_model.hpp"
#include "spatial/spatial_solver.hpp"
#include "sweep/compiled_kernel.hpp"

namespace mechgen::spatial {

struct SupportKernelLoads {
  std::vector<double> torque;  // per joint of the description (0 for virtual joints)
  Wrench floor;                // on the support foot, about the ground origin
};

class SupportKernel {
 public:
  // `solver` solves the description (with its pose drivers) at its parameter values; `welded` is
  // weld_support(solver.model(), support name) and `kernel` its generated kernel (e.g.
  // ondemand::kernel_for(welded, support)). Throws ModelError when the kernel's columns or
  // parameters are not the welded model's.
  SupportKernel(const SpatialSolver& solver, const SpatialModel& welded, int support,
                const CompiledKernel& kernel);

  // Throws ModelError when the support foot is not flat (tilted by more than 1e-9 rad) or the
  // kernel reports a failure (naming its stage).
  SupportKernelLoads loads(const SpatialState& state) const;

  int support() const { return support_; }

 private:
  const SpatialSolver& solver_;
  const CompiledKernel& kernel_;
  int support_;
  V3 at_{0, 0, 0};              // the support's pose driver point, reference pose
  std::vector<double> params_;  // the description's values, then the placement
  std::vector<int> joint_;      // per kernel driver: the description's joint
  std::vector<int> column_;     // per kernel driver: the description's column
  std::vector<int> effort_;     // per kernel driver: its effort's row index
  int weld_ = -1;               // row index of the weld's fx (then fy, fz, mx, my, mz)
  size_t placement_ = 0;        // index of support_x in params_
};

}  // namespace mechgen::spatial
