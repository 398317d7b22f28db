// A branch choice is never silent: a closed-form group with two assembly branches that no
// `assembly:` hint of its bodies tells apart is reported with both branches' body angles and the
// hint that pins the one taken.
#pragma once

#include <string>
#include <vector>

#include "derivation.hpp"
#include "model/model.hpp"

namespace mechgen::gen {

// True when a hint of one of the group's bodies lies within the model's assembly_tolerance of
// the branch taken and outside it for the other branch (default parameters, t0).
bool branch_pinned(const Model& model, const BranchChoice& choice);

// One line per group whose branch no hint pins: which branch was taken, both branches' body
// angles (rad, ground frame, at t0), and the `assembly` hint that pins it. Empty when every
// branch is pinned.
std::vector<std::string> unpinned_branch_warnings(const Model& model,
                                                  const std::vector<BranchChoice>& choices);

}  // namespace mechgen::gen
