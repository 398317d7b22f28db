// Large spatial kernels as shared stages instead of one straight line per entry point.
//
// A spatial kernel's entry points nest: velocities() is positions and first rates, kinematics()
// adds the accelerations and the Jacobians, evaluate(), control() and ne_fill() add forces.
// Emitted as straight lines, each entry repeats the program before its own part (five copies of
// the positions and Davies' rates: bioloid 2.3 MB, a Delta on Newton 12 MB). Above a size the
// kernel emits instead each shared stage once, as a function (detail::motion,
// detail::accelerations, ...), and each entry calls those it needs, then runs its own tail. What a
// later stage or tail reads from an earlier stage travels in one workspace, `detail::Shared<T>`, on
// the entry's stack: one field per such quantity. Below that size the straight lines stay: there
// the compiler keeps every value in registers across the stages, and a small kernel's calls and
// workspace stores would cost (README, "Performance": where the cross-over lies).
#pragma once

#include <ginac/ginac.h>

#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "code_block.hpp"
#include "spatial_derivation.hpp"

namespace mechgen::gen {

struct SharedStage {
  std::string name;  // the function in detail::, e.g. "motion"
  std::string doc;   // one comment line: what it computes
  std::vector<SpatialOutput> outputs;
  std::vector<GiNaC::ex> quantities;  // defined names it computes besides its outputs' (for later)
  std::vector<size_t> after;          // the earlier stages whose results it reads (all run first)
};

struct StagedEntry {
  std::string name;            // the entry's key in the template ("kinematics", "ne", ...)
  std::vector<size_t> stages;  // the shared stages it runs, in order (each with its `after`)
  std::vector<SpatialOutput> outputs;  // what it writes after them
};

struct StagedKernel {
  std::string functions;                    // struct Shared and the stage functions
  std::map<std::string, std::string> body;  // per entry: the stage calls, then its tail
  std::map<std::string, std::string> using_lines;
  std::map<std::string, int> ops;  // per entry: its stages' and its tail's
};

struct StagedProgramView {
  const std::vector<std::pair<GiNaC::symbol, GiNaC::ex>>& definitions;  // program order
  // Every symbol these outputs read, through the definitions.
  std::function<std::set<GiNaC::ex, GiNaC::ex_is_less>(const std::vector<SpatialOutput>&)> needed;
  // Called after each definition a block emits (a closed form's reach check).
  std::function<void(CodeBlock&, const GiNaC::symbol&)> after_define;
  // `using ...;` lines for the math functions a block calls.
  std::function<std::string(const CodeBlock&)> using_lines;
};

StagedKernel emit_shared_stages(const StagedProgramView& program,
                                const std::vector<SharedStage>& stages,
                                const std::vector<StagedEntry>& entries);

}  // namespace mechgen::gen
