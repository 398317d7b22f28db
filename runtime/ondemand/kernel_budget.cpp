#include "ondemand/kernel_budget.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace mechgen::ondemand {

namespace {

// The cost model: time and peak memory linear in the header's size, fitted on the on-demand
// compiles (c++ -O2 -march=native -shared, one job) of the shipped kernels on this 2-core machine,
// 0.05 to 2.3 MB (README, "The kernel cache": the table of the fit). Memory is the least-squares
// line (rounded); it also gives the 34 MB Newton Delta of issue 27 to 10% (7.8 GB). Time depends on
// the machine's load as much as on the size: the line is fitted to the compiles with at most one
// other build running (bioloid 39 s, quadruped_leg 9 to 52 s); at a load of 8 on 2 cores bioloid
// took 3.3 times as long, and a 3.98 MB spatial serial chain of 48 revolutes 4.3 times (443 s, at
// a load of 6; its memory, 1.49 GB, is 1.4 times the line's).
constexpr double kSecondsAtZero = 2, kSecondsPerMb = 25;
constexpr double kPeakMbAtZero = 60, kPeakMbPerMb = 250;
// The default time limit: this many times the expected time, and at least kMinTimeout seconds.
constexpr double kTimeoutFactor = 4, kMinTimeout = 600;

// The machine's physical memory in MB (sysconf), 0 when unknown.
double physical_memory_mb() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) / 1e6 : 0;
}

}  // namespace

std::string printf_number(const char* pattern, double value) {
  char text[128];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

CompileCost expected_compile_cost(std::uintmax_t header_bytes) {
  CompileCost cost;
  cost.header_mb = static_cast<double>(header_bytes) / 1e6;
  cost.seconds = kSecondsAtZero + kSecondsPerMb * cost.header_mb;
  cost.peak_mb = kPeakMbAtZero + kPeakMbPerMb * cost.header_mb;
  return cost;
}

std::string describe(const CompileCost& cost) {
  const double minutes = cost.seconds / 60;
  return printf_number("%.2f MB header: about ", cost.header_mb) +
         (minutes >= 2 ? printf_number("%.0f min", minutes)
                       : printf_number("%.0f s", cost.seconds)) +
         printf_number(" and %.0f MB to compile", cost.peak_mb);
}

double environment_number(const char* variable, double fallback, const char* what) {
  const char* text = std::getenv(variable);
  if (!text || !*text) return fallback;
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (*end != '\0' || !std::isfinite(value) || value < 0)
    throw std::runtime_error(std::string(variable) + "='" + text + "' is not a number of " + what +
                             " (0 or more)");
  return value;
}

CompileLimits compile_limits(const CompileCost& cost) {
  CompileLimits limits;
  limits.max_kernel_mb = environment_number("MECHGEN_MAX_KERNEL_MB", kDefaultMaxKernelMb, "MB");
  limits.timeout_seconds = environment_number(
      "MECHGEN_COMPILE_TIMEOUT", std::max(kMinTimeout, kTimeoutFactor * cost.seconds), "seconds");
  limits.memory_mb = environment_number("MECHGEN_COMPILE_MEMORY_MB", physical_memory_mb(), "MB");
  return limits;
}

bool over_limit(const CompileCost& cost, const CompileLimits& limits) {
  return limits.max_kernel_mb > 0 && cost.header_mb > limits.max_kernel_mb;
}

void check_kernel_size(const std::string& model, const CompileCost& cost,
                       const CompileLimits& limits) {
  if (!over_limit(cost, limits)) return;
  throw std::runtime_error(
      "the kernel of '" + model + "' is too large to compile: " + describe(cost) + " (" +
      kCostAccuracy + "), over the limit of " + printf_number("%g MB", limits.max_kernel_mb) +
      " (--max-kernel-mb, MECHGEN_MAX_KERNEL_MB); no compiler was started. Use --solver numeric, "
      "or raise the limit" +
      printf_number(" (--max-kernel-mb %.0f)", std::ceil(cost.header_mb)) +
      " if the time and memory are acceptable");
}

}  // namespace mechgen::ondemand

namespace mechgen::ondemand {

std::string kernel_cost_report(const std::vector<gen::EmittedFile>& files, double generate_seconds,
                               bool compiled_in) {
  std::uintmax_t bytes = 0;
  for (const gen::EmittedFile& file : files)
    if (file.name.size() > 4 && file.name.compare(file.name.size() - 4, 4, ".hpp") == 0)
      bytes += file.text.size();
  const CompileCost cost = expected_compile_cost(bytes);
  const CompileLimits limits = compile_limits(cost);
  std::string out = "  kernel size: " + std::to_string(bytes) +
                    " bytes of header (exact: generated " +
                    printf_number("in memory in %.2f s)", generate_seconds) + "; ";
  out += (compiled_in ? "compiled into this mechgen (an edited copy's first use: "
                      : "first use (unless cached): ") +
         describe(cost) + " (" + std::string(kCostAccuracy) + ")" +
         (limits.max_kernel_mb > 0 ? printf_number("; limit %g MB", limits.max_kernel_mb)
                                   : std::string("; no size limit")) +
         (compiled_in ? ")\n" : "\n");
  if (over_limit(cost, limits))
    out += printf_number("  warning: the header is over the limit of %g MB", limits.max_kernel_mb) +
           " (--max-kernel-mb, MECHGEN_MAX_KERNEL_MB): its first use will be refused; sweep with "
           "--solver numeric, or raise the limit\n";
  return out;
}

}  // namespace mechgen::ondemand
