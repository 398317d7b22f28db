// branch_sign(x): +1 where x >= 0, -1 where x < 0, as a GiNaC function that kernels print as
// detail::branch_sign. A closed form with two roots (a circle intersection, a quadratic) picks the
// root nearer its warm start at run time through it (issue 28): x is a smooth expression of the
// warm start whose sign says which root is nearer, so the branch follows the motion along a sweep
// and the assembly of the run's parameters at t0, not the one of generation.
#pragma once

#include <ginac/ginac.h>

namespace mechgen::gen {

DECLARE_FUNCTION_1P(branch_sign)

// The kernel State's flag `s.closure.follow`: 0 in a fresh State, 1 once a call was accepted (or
// the runtime seeded the warm start).
const GiNaC::symbol& follow_symbol();

// The root a closed form takes, +1 or -1: in a State that follows a motion, the warm start's side
// (the sign of `indicator`); in a fresh one, the side the assembly is on (the sign of
// `indicator_at_assembly`), as the kernel was generated, so a first call without history (an
// inverse kinematics call, a workspace sample) keeps the assembly's configuration family.
GiNaC::ex followed_branch(const GiNaC::ex& indicator, double indicator_at_assembly);

}  // namespace mechgen::gen
