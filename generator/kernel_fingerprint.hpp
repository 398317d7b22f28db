// The fingerprint a generated kernel carries (`fingerprint` in <model>.hpp, CompiledKernel's
// `fingerprint`): everything its code depends on. That is the description (its canonical parsed
// form, Model::description_hash), whether defaults are baked in, the text of the templates it is
// rendered from (planar: kernel.hpp.in and kernel_entry.cpp.in; spatial: spatial_kernel.hpp.in,
// spatial_kernel_entry.cpp.in and kernel.hpp.in, whose math functions it shares; both:
// forward_dynamics.hpp.in and forward_dynamics_entry.cpp.in), and
// kEmissionVersion for the generator's own part of the emitted code. mechgen evaluates a kernel
// only for a description whose fingerprint is the kernel's.
//
// The generator's code is in the fingerprint only through kEmissionVersion: the build regenerates
// every compiled-in kernel when the generator changes, and on-demand kernels are cached per
// mechgen binary (runtime/ondemand/kernel_cache.hpp), so a changed generator never meets a kernel
// of an older one. Bump kEmissionVersion when a kernel built by another binary (a consumer's
// CMake build, a copy in firmware) must be told apart from one emitted now.
#pragma once

#include <cstdint>
#include <string>

#include "model/model.hpp"

namespace mechgen::gen {

inline constexpr int kEmissionVersion = 2;

// Which emitter (and so which templates) a kernel comes from: a planar model's or a spatial one's
// (`dimension: spatial`, generator/spatial_emitter.hpp; never baked).
enum class KernelKind { planar, spatial };

// Reads the kind's templates from templates_dir; std::runtime_error when one is unreadable.
std::uint64_t kernel_fingerprint(const Model& model, const std::string& templates_dir, bool bake,
                                 KernelKind kind = KernelKind::planar);

}  // namespace mechgen::gen
