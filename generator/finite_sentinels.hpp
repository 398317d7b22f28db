// Which outputs a stage's finiteness check must read (output_checks.hpp): the sentinels.
//
// IEEE arithmetic carries a non-finite operand through +, - and * (inf + x, inf * x, inf * 0 and
// NaN op x are all infinite or NaN), and through positive integer powers, whatever the grouping
// or the other operands. So when an output is a named intermediate x and x enters another output
// of the same stage only through such operations (directly or through other named
// intermediates), that other output is non-finite whenever x is: x needs no term of its own in
// the stage's sum. Division, sqrt and functions (sin, atan2, ...) can absorb a non-finite value
// (1/inf = 0) and stop the chain. Outputs that copy a driver input (checked before any
// computation) need no term either. The check then still fails exactly when some output of the
// stage is non-finite, and names the same stage.
// Assumes no -ffast-math (as the whole project: the checks themselves need IEEE semantics) and no
// contraction of a named intermediate's product into a later fused multiply-add (the project
// builds with -ffp-contract=off; every named intermediate is stored as computed).
#pragma once

#include <map>
#include <vector>

#include <ginac/ginac.h>

namespace mechgen::gen {

using SymbolDefinitions = std::map<GiNaC::ex, GiNaC::ex, GiNaC::ex_is_less>;

// Indices into `values` (one stage's outputs, each checked value once) of those whose own
// finiteness is not implied by another's; `definitions` maps each named intermediate to its
// expression; symbols named `in.*` are driver inputs.
std::vector<size_t> finite_sentinels(const std::vector<GiNaC::ex>& values,
                                     const SymbolDefinitions& definitions);

}  // namespace mechgen::gen
