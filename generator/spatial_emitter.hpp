// Emission of a spatial model's kernel (spatial_derivation.hpp) through
// templates/spatial_kernel.hpp.in and templates/spatial_kernel_entry.cpp.in, and the one call
// from a spatial description to its written files.
#pragma once

#include <vector>

#include "generate.hpp"
#include "kernel_emitter.hpp"
#include "model/spatial_model.hpp"
#include "spatial_derivation.hpp"

namespace mechgen::gen {

std::vector<EmittedFile> emit_spatial_kernel(const SpatialModel& model,
                                             const SpatialDerivation& derivation,
                                             const EmitOptions& options);

// The files generate_spatial(options) writes for `model` (read and, for options.support, welded as
// it does) and its derivation, in memory: what `mechgen check` measures.
std::vector<EmittedFile> emit_spatial_files(const SpatialModel& model,
                                            const SpatialDerivation& derivation,
                                            const GenerateOptions& options);

// generate() for a `dimension: spatial` description (same options and result).
GenerateResult generate_spatial(const GenerateOptions& options);

}  // namespace mechgen::gen
