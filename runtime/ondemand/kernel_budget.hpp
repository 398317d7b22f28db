// The size and compile-cost budget of a kernel built on demand (issue 26 item 2, issue 27 item 5).
//
// A kernel's header is generated (in memory, then into the build folder) before the compiler
// starts, so its size is known first; the cost of compiling it is estimated from that size by a
// linear model fitted on this machine's shipped kernels (kernel_budget.cpp; README, "The kernel
// cache"). Then:
// - a header larger than the limit ($MECHGEN_MAX_KERNEL_MB, `--max-kernel-mb MB`; default
//   kDefaultMaxKernelMb, above the largest shipped kernel) is refused before any compiler runs,
//   with an error naming the model, the header's size, the expected time and memory, the limit and
//   what to do;
// - the compiler runs under a wall-clock limit ($MECHGEN_COMPILE_TIMEOUT seconds,
//   `--compile-timeout S`; default: 4 times the expected time, at least 600 s) and an address-space
//   limit of each of its processes (RLIMIT_AS, $MECHGEN_COMPILE_MEMORY_MB, `--compile-memory-mb
//   MB`; default: the machine's physical memory); 0 lifts either. A compiler killed at the time
//   limit or out of memory is an error naming the model, the size and the limit.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "kernel_emitter.hpp"

namespace mechgen::ondemand {

// The default of $MECHGEN_MAX_KERNEL_MB: the largest shipped kernel (bioloid, 2.3 MB; the imported
// cassie_like, 3.0 MB) passes with room; the Newton fallbacks of issue 26/27 (14.8 to 43 MB, 15
// minutes and more, 7.8 GB) are refused.
inline constexpr double kDefaultMaxKernelMb = 8;

// The estimate's stated accuracy (kernel_budget.cpp: the measured compiles against the model).
inline constexpr const char* kCostAccuracy =
    "estimate: time within a factor of 4, more on a machine loaded past its cores; memory within a "
    "factor of 2";

struct CompileCost {
  double header_mb = 0;  // 10^6 bytes
  double seconds = 0;    // expected wall-clock time of the compile (c++ -O2, one job)
  double peak_mb = 0;    // expected peak resident memory of the compiler
};

// The expected cost of compiling a kernel whose header has `header_bytes` bytes.
CompileCost expected_compile_cost(std::uintmax_t header_bytes);

// "2.32 MB header: about 46 s and 650 MB to compile".
std::string describe(const CompileCost& cost);

struct CompileLimits {
  double max_kernel_mb = kDefaultMaxKernelMb;
  double timeout_seconds = 0;  // 0: none
  double memory_mb = 0;        // 0: none
};

// The limits for a kernel of cost `cost`, from the environment (above). Throws std::runtime_error
// naming the variable when one holds something else than a number >= 0.
CompileLimits compile_limits(const CompileCost& cost);

// Whether the header is over the size limit (0: none).
bool over_limit(const CompileCost& cost, const CompileLimits& limits);

// Throws std::runtime_error when the header is over the limit: the refusal (model, size, expected
// cost, limit, what to do).
void check_kernel_size(const std::string& model, const CompileCost& cost,
                       const CompileLimits& limits);

// What `mechgen check` says of the kernel it plans, from `files`, the generator's output for the
// description made in memory in `generate_seconds` (so the header's size is exact): the header's
// size, the expected compile cost (or that the kernel is compiled into mechgen) and, when the
// header is over the limit, a warning that its first use will be refused. Lines indented by two.
std::string kernel_cost_report(const std::vector<gen::EmittedFile>& files, double generate_seconds,
                               bool compiled_in);

// `value` printed through snprintf's `pattern` (one conversion of a double): "%.2f MB".
std::string printf_number(const char* pattern, double value);

// The value of `variable` as a number >= 0, or `fallback` when it is unset or empty; throws
// std::runtime_error naming it otherwise (`what`: "seconds", "MB").
double environment_number(const char* variable, double fallback, const char* what);

}  // namespace mechgen::ondemand
