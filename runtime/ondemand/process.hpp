// Runs a program (no shell: arguments are passed as they are) with its stdout and stderr written to
// a file, and waits for it.
//
// The program never outlives mechgen: it runs in a process group of its own under a small
// supervisor (a fork of mechgen) that the kernel signals when mechgen dies, even by SIGKILL
// (PR_SET_PDEATHSIG); the supervisor then kills the whole group, so a compiler's own children
// (cc1plus, as, ld) die too. On SIGINT/SIGTERM/SIGHUP mechgen's handler kills the group first
// (report/temporary_files.hpp). Its stdin is /dev/null.
#pragma once

#include <string>
#include <vector>

namespace mechgen::ondemand {

// The exit code; 127 when the program cannot be started, 128 + N when signal N ended it. Throws
// std::runtime_error when the output file cannot be created.
int run_to_file(const std::vector<std::string>& argv, const std::string& output_path);

}  // namespace mechgen::ondemand
