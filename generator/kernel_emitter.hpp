// Emission of a derived model as C++17 kernels through the text templates in templates/.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "derivation.hpp"
#include "model/model.hpp"
#include "model/solve_plan.hpp"
#include "staged_program.hpp"

namespace mechgen::gen {

struct EmitOptions {
  std::string templates_dir;  // the folder holding kernel.hpp.in and kernel_entry.cpp.in
  std::string source;         // the model's path as shown in the banner, e.g. models/pasibot.yaml
  std::string command;        // the command that regenerates the files
  bool bake = false;          // parameter values as constants instead of run-time fields
  std::uint64_t fingerprint = 0;  // kernel_fingerprint() of the model, templates and bake
};

struct EmittedFile {
  std::string name;  // relative to the output folder
  std::string text;
};

std::vector<EmittedFile> emit_kernel(const Model& model, const SolvePlan& plan,
                                     const Derivation& derivation, const StagedProgram& program,
                                     const EmitOptions& options);

}  // namespace mechgen::gen
