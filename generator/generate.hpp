// One call from a model file to its kernel files: read, plan, assemble (for branches), derive,
// emit. Shared by `mechgen generate` and the build's mechgen_generate tool.
#pragma once

#include <string>
#include <vector>

#include "kernel_emitter.hpp"

namespace mechgen::gen {

struct GenerateOptions {
  std::string model_path;
  std::string output_dir;     // default: generated/<model name> under the source tree
  std::string templates_dir;  // default: templates/ of the source tree
  bool bake = false;
  // Spatial only: the body to stand on; the kernel is then the single-support model's
  // (model/support_model.hpp), named <model>_support_<body>.
  std::string support;
};

struct GenerateResult {
  std::string model;
  std::vector<std::string> written;  // paths
  std::vector<std::string> notes;    // branch choices
};

// Throws ModelError for description problems and std::runtime_error for derivation problems.
GenerateResult generate(const GenerateOptions& options);
// The same for a model already read (options.model_path only names it in the banners): what was
// read is what is generated, even if the file changes meanwhile.
GenerateResult generate(const Model& model, const GenerateOptions& options);

// The files generate(model, options) writes, in memory (nothing written; options.output_dir
// unused), with the notes and branches branch_notes() gives when asked: what `mechgen check`
// measures. Same exceptions.
std::vector<EmittedFile> emit_files(const Model& model, const GenerateOptions& options,
                                    std::vector<std::string>* notes = nullptr,
                                    std::vector<BranchChoice>* branches = nullptr);

// The branch generate() picks for each group ("g2_l7_l9: branch -1"), derived the same way but
// without emitting or writing anything: what `mechgen check` prints. Same exceptions.
// With each closed-form group's branches (BranchChoice) in `branches` when given.
std::vector<std::string> branch_notes(const Model& model,
                                      std::vector<BranchChoice>* branches = nullptr);

// The part of a path from its "models/" component on, so banners do not depend on where the
// tree is checked out.
std::string display_path(const std::string& path);

}  // namespace mechgen::gen
