// The closed-form solvers tried on each circuit (spatial_circuit_solvers.hpp).
#include "spatial_circuit_solvers.hpp"

#include "spatial_limb_ik.hpp"
#include "spatial_link_loops.hpp"
#include "spatial_planar_loops.hpp"
#include "spatial_position_ik.hpp"

namespace mechgen::gen {

const std::vector<CircuitSolver>& circuit_solvers() {
  static const std::vector<CircuitSolver> solvers{planar_limb_ik, six_revolute_limb_ik,
                                                  link_loop_closed_form, planar_loop_closed_form,
                                                  position_limb_ik};
  return solvers;
}

const std::vector<CircuitSolver>& fallback_circuit_solvers() {
  static const std::vector<CircuitSolver> solvers{planar_loop_held_closed_form,
                                                  one_angle_closed_form, platform_closed_form};
  return solvers;
}

}  // namespace mechgen::gen
