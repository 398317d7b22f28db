// The closed-form pre-pass's driver (spatial_closed_form.hpp).
#include "spatial_closed_form.hpp"

#include <limits>

#include "spatial_link_loops.hpp"

namespace mechgen::gen {

double ClosureContext::value(const GiNaC::ex& e) const {
  const GiNaC::ex v = e.subs(assembly).evalf();
  return GiNaC::is_a<GiNaC::numeric>(v) ? GiNaC::ex_to<GiNaC::numeric>(v).to_double()
                                        : std::numeric_limits<double>::quiet_NaN();
}

bool ClosureContext::pose_known(int body) const {
  const std::vector<int>& path = graph.path_sign[static_cast<size_t>(body)];
  for (size_t c = 0; c < path.size(); ++c)
    if (path[c] != 0 && !known[c]) return false;
  return true;
}

std::vector<ClosedFormGroup> closed_form_groups(ClosureContext& ctx) {
  // The recognisers, in turn; a group found by one may make another's known.
  const std::vector<ClosedFormSolver> solvers{link_loop_groups};
  std::vector<ClosedFormGroup> groups;
  for (bool found = true; found;) {
    found = false;
    for (const ClosedFormSolver& solver : solvers) found = solver(ctx, groups) || found;
  }
  return groups;
}

}  // namespace mechgen::gen
