// Kernels built on demand: generated for a model, compiled by the system compiler into a shared
// library for this machine's instruction set, and kept in a cache so that later runs load them at
// once.
//
// The cache folder is $MECHGEN_CACHE (what `mechgen --cache DIR` sets), else
// $XDG_CACHE_HOME/mechgen, else ~/.cache/mechgen. A kernel's file is
// <model>-<fingerprint>-<build key>.so: the fingerprint is the description's and templates'
// (generator/kernel_fingerprint.hpp), the build key hashes the compiler's command and its
// expansion of -march=native (the compiler version, the CPU), the CompiledKernel ABI and this
// mechgen binary's build id (so a changed generator never loads an older one's kernels). A kernel
// is built in a private temporary folder and renamed into place: processes that build the same
// kernel at once each rename a complete file, never a partial one.
//
// The compiler is $MECHGEN_CXX, else `c++`, run as
//   c++ -std=c++17 -O2 -march=native -shared -fPIC -fvisibility=hidden -ffp-contract=off
//       -fno-math-errno -fno-trapping-math -DMECHGEN_KERNEL_SHARED ...
// (the build's own floating-point flags, never fast-math).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "kernel_fingerprint.hpp"
#include "model/model.hpp"
#include "sweep/compiled_kernel.hpp"

namespace mechgen::ondemand {

// The cache folder (above); std::runtime_error when no variable names one.
std::string cache_dir();

// The compiler command without its input and output files.
std::vector<std::string> compile_command();

// The kernel of `model` whose fingerprint is `fingerprint`: loaded from the cache, else generated,
// compiled (saying so on stderr, with the time it took) and cached. Throws std::runtime_error when
// it cannot be generated, compiled (the message names the compiler's log file) or loaded. A spatial
// kernel (`kind`) is generated from the description's file, model.file, by the spatial emitter,
// standing on `support` when one is named (a single-support kernel, model/support_model.hpp).
const CompiledKernel& cached_kernel(const Model& model, std::uint64_t fingerprint,
                                    const std::string& reason,
                                    gen::KernelKind kind = gen::KernelKind::planar,
                                    const std::string& support = "");

}  // namespace mechgen::ondemand
