// The one way the runtime finds a model's generated kernel: never one generated from another
// description. A compiled-in kernel is used when its fingerprint is the description's; otherwise
// the kernel is loaded from the on-demand cache or built into it (ondemand/kernel_cache.hpp).
#pragma once

#include <cstdint>
#include <string>

#include "model/model.hpp"
#include "model/spatial_model.hpp"
#include "sweep/compiled_kernel.hpp"

namespace mechgen::ondemand {

// The fingerprint a kernel of `model` generated now carries (generator/kernel_fingerprint.hpp,
// with this mechgen's templates and run-time parameters).
std::uint64_t expected_fingerprint(const Model& model);

// The kernel compiled into this binary for `model` if it was generated from this very description,
// else nullptr.
const CompiledKernel* current_compiled_kernel(const Model& model);

// The kernel for `model`: the current compiled-in one, else the cached or freshly built one.
// Thread-safe (one build at a time; a kernel is resolved once per process). Throws
// std::runtime_error when no kernel can be had: the generated solver never falls back silently.
const CompiledKernel& kernel_for(const Model& model);

// The same for a spatial model (`dimension: spatial`): its kernels come from the spatial templates,
// so their fingerprint is another (generator/kernel_fingerprint.hpp, KernelKind::spatial); an
// on-demand one is generated from model.common.file.
std::uint64_t expected_fingerprint(const SpatialModel& model);
const CompiledKernel* current_compiled_kernel(const SpatialModel& model);
const CompiledKernel& kernel_for(const SpatialModel& model);
// A single-support kernel: `welded` is weld_support(description, support)
// (model/support_model.hpp), whose fingerprint covers the support; one built on demand is
// generated from welded.common.file standing on `support`.
const CompiledKernel& kernel_for(const SpatialModel& welded, const std::string& support);

}  // namespace mechgen::ondemand
