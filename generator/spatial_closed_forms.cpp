// The closed-form solvers tried on each circuit (spatial_closed_forms.hpp).
#include "spatial_closed_forms.hpp"

#include "spatial_limb_ik.hpp"

namespace mechgen::gen {

const std::vector<ClosedFormSolver>& closed_form_solvers() {
  static const std::vector<ClosedFormSolver> solvers{planar_limb_ik, six_revolute_limb_ik};
  return solvers;
}

}  // namespace mechgen::gen
