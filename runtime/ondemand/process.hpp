// Runs a program (no shell: arguments are passed as they are) with its stdout and stderr written to
// a file, and waits for it.
//
// The program never outlives mechgen: it runs in a process group of its own under a small
// supervisor (a fork of mechgen) that the kernel signals when mechgen dies, even by SIGKILL
// (PR_SET_PDEATHSIG); the supervisor then kills the whole group, so a compiler's own children
// (cc1plus, as, ld) die too. On SIGINT/SIGTERM/SIGHUP mechgen's handler kills the group first
// (report/temporary_files.hpp). Its stdin is /dev/null.
//
// Limits (kernel_budget.hpp): a wall-clock time after which the whole group is killed (SIGKILL),
// and an address-space limit (RLIMIT_AS, set in the program's process before exec, so inherited by
// its children: each of cc1plus, as, ld gets it).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace mechgen::ondemand {

struct RunLimits {
  double timeout_seconds = 0;      // 0: none
  std::uint64_t memory_bytes = 0;  // RLIMIT_AS of the program and its children; 0: none
  // Called from the waiting thread about every `tick_seconds` while the program runs, with the
  // seconds since it started.
  std::function<void(double)> tick;
  double tick_seconds = 1;
};

struct RunResult {
  // The exit code; 127 when the program cannot be started, 128 + N when signal N ended it.
  int status = 0;
  bool timed_out = false;  // killed (with its whole group) at limits.timeout_seconds
  double seconds = 0;      // wall-clock time it ran
};

// Throws std::runtime_error when the output file cannot be created.
RunResult run_to_file(const std::vector<std::string>& argv, const std::string& output_path,
                      const RunLimits& limits = {});

}  // namespace mechgen::ondemand
