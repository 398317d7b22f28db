// The order in which a kernel's statements and outputs are printed. The compiler keeps the source
// order of straight-line floating-point code nearly as written (x86-64 GCC does not schedule
// before register allocation), so the printed order decides both how much independent work the
// processor finds next to a long dependency chain and how many values are alive at once: with 16
// registers, every value beyond them is spilled to the stack and reloaded, and those moves (not
// the arithmetic) were most of a PASIBOT sample's instructions and code bytes.
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

// One printed step of a block: statement `index` of the program, or output `index`.
struct Step {
  bool output = false;
  size_t index = 0;
};

// Which order decides when a root (a check or an output) is ready.
enum class Readiness { latency, program };

// The printed order of a block with outputs (values over the statements' symbols). Its roots,
// the checks and the outputs, come in the order latency_order (or the program order) makes them
// ready (a root is ready once the last statement it reads is); each root is preceded, depth first,
// by the definitions it still needs, the most recently written first. So a value is computed right
// before its first use and an output is written as soon as it is known, instead of every quantity
// staying alive until the end of the block. Checks keep their original relative order and
// definitions follow what they read. Outputs flagged in `after_checks` come after every check (a
// value kept for the next call, such as a warm start, is only written when the whole block
// succeeded). Definitions that no root reads are left out.
std::vector<Step> emission_order(const std::vector<Statement>& statements,
                                 const std::set<GiNaC::ex, GiNaC::ex_is_less>& needed,
                                 const std::vector<GiNaC::ex>& outputs,
                                 const std::vector<bool>& after_checks, Readiness readiness);

}  // namespace mechgen::gen
