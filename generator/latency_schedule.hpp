// The order in which a kernel's statements are printed. The compiler keeps the source order of
// straight-line floating-point code nearly as written (x86-64 GCC does not schedule before
// register allocation), and the kernels are latency-bound along their dependency chains, so the
// printed order decides how much independent work the processor finds next to a long chain.
#pragma once

#include <set>
#include <vector>

#include <ginac/ginac.h>

#include "staged_program.hpp"

namespace mechgen::gen {

// Indices into `statements` of those whose symbol is in `needed`, in a valid program order:
// list scheduling by height (the estimated latency from a statement to the end of the program
// along its longest chain of users), highest first, ties in the original order. Definitions
// follow what they read; checks keep their original relative order (the first failing check
// decides the status) and follow the quantity they check.
std::vector<size_t> latency_order(const std::vector<Statement>& statements,
                                  const std::set<GiNaC::ex, GiNaC::ex_is_less>& needed);

}  // namespace mechgen::gen
