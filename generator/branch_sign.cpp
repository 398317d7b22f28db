#include "branch_sign.hpp"

namespace mechgen::gen {
namespace {

using GiNaC::ex;

// A real number gives its sign (0 counts as +1: both roots are equal there); anything else stays
// symbolic.
ex branch_sign_eval(const ex& x) {
  if (GiNaC::is_a<GiNaC::numeric>(x) && GiNaC::ex_to<GiNaC::numeric>(x).is_real())
    return GiNaC::ex_to<GiNaC::numeric>(x).is_negative() ? -1 : 1;
  return branch_sign(x).hold();
}

ex branch_sign_evalf(const ex& x) {
  return branch_sign_eval(x.evalf());
}

// Piecewise constant: its derivative is zero wherever it is defined.
ex branch_sign_derivative(const ex&, unsigned) {
  return 0;
}

}  // namespace

REGISTER_FUNCTION(branch_sign, eval_func(branch_sign_eval)
                                   .evalf_func(branch_sign_evalf)
                                   .derivative_func(branch_sign_derivative))

const GiNaC::symbol& follow_symbol() {
  static const GiNaC::symbol follow("s.closure.follow");
  return follow;
}

GiNaC::ex followed_branch(const GiNaC::ex& indicator, double indicator_at_assembly) {
  const GiNaC::ex& follow = follow_symbol();
  return follow * branch_sign(indicator) + (1 - follow) * (indicator_at_assembly >= 0 ? 1 : -1);
}

}  // namespace mechgen::gen
