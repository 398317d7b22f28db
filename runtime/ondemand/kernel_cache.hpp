// Kernels built on demand: generated for a model, compiled by the system compiler into a shared
// library for this machine's instruction set, and kept in a cache so that later runs load them at
// once.
//
// The cache folder is $MECHGEN_CACHE (what `mechgen --cache DIR` sets), else
// $XDG_CACHE_HOME/mechgen, else ~/.cache/mechgen, created mode 0700 and checked before use
// (cache_folder.hpp: no folder on its path writable by another user). A kernel's file is
// <model>-<fingerprint>-<build key>.so: the fingerprint is the description's and templates'
// (generator/kernel_fingerprint.hpp); the build key hashes this mechgen binary's build id (a
// changed generator never loads an older one's kernels), the CompiledKernel ABI, the compiler
// command and the CPU (/proc/cpuinfo's identity and feature flags, what -march=native compiles
// for). The key is computed without running the compiler or writing anything, so a cached kernel
// loads from a read-only cache on a machine without a compiler.
//
// Loading: the library and its recorded content hash (<file>.sha256, `sha256sum -c` format) must
// be trusted files (cache_folder.hpp), and the library's SHA-256 must be the recorded one; it is
// then loaded through the very descriptor that was hashed (/proc/self/fd/N, kept open: a library
// rebuilt in the same run is a new file and gets a new mapping). A library that fails a check
// (planted, truncated, corrupt, replaced, writable by others, of another description) is never
// loaded: it is rebuilt, or, in a read-only cache, an error.
//
// Building: under an exclusive lock on <file>.lock (flock), so that of many processes needing the
// same kernel one compiles and the others wait ($MECHGEN_CACHE_LOCK_TIMEOUT seconds at most,
// default 900) and load its library. The build runs in a private folder .build-<model>-XXXXXX,
// removed on every error and on SIGINT/SIGTERM; one left by a killed run (SIGKILL) is removed by
// the next build in the cache once its owner's lock is free and it is a minute old
// (report/temporary_files.hpp). The compiler dies with mechgen (process.hpp). The hash, then the
// library, are renamed into place (atomic): a reader never sees a partial file.
//
// The compiler is $MECHGEN_CXX, else $CXX, else `c++`; either variable may hold a program and its
// arguments separated by spaces ("ccache g++", "g++-12 -Wno-psabi"; no quotes). It runs as
//   c++ -std=c++17 -O2 -march=native -shared -fPIC -fvisibility=hidden -ffp-contract=off
//       -fno-math-errno -fno-trapping-math -DMECHGEN_KERNEL_SHARED ...
// (the build's own floating-point flags, never fast-math).
//
// Budget (kernel_budget.hpp): the generated header's size is checked against
// $MECHGEN_MAX_KERNEL_MB before the compiler starts (a larger one is an error, no compiler run);
// the compiler runs under a time limit and an address-space limit, and says its progress on a
// terminal.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "kernel_fingerprint.hpp"
#include "model/model.hpp"
#include "sweep/compiled_kernel.hpp"

namespace mechgen::ondemand {

// The cache folder (above) as configured, unchecked; std::runtime_error when no variable names one.
std::string cache_dir();

// The compiler command without its input and output files; std::runtime_error when MECHGEN_CXX or
// CXX holds quotes or backslashes (not split like a shell would).
std::vector<std::string> compile_command();

// The kernel of `model` whose fingerprint is `fingerprint`: loaded from the cache, else generated,
// compiled (saying so on stderr, with the time it took) and cached. Throws std::runtime_error when
// it cannot be generated, is over the size limit, cannot be compiled within the time and memory
// limits (the message names the compiler's log file) or loaded. A spatial
// kernel (`kind`) is generated from the description's file, model.file, by the spatial emitter,
// standing on `support` when one is named (a single-support kernel, model/support_model.hpp).
const CompiledKernel& cached_kernel(const Model& model, std::uint64_t fingerprint,
                                    const std::string& reason,
                                    gen::KernelKind kind = gen::KernelKind::planar,
                                    const std::string& support = "");

}  // namespace mechgen::ondemand
