// Runs a program (no shell: arguments are passed as they are) with its stdout and stderr written to
// a file, and waits for it.
#pragma once

#include <string>
#include <vector>

namespace mechgen::ondemand {

// The exit code; 127 when the program cannot be started, 128 + N when signal N ended it. Throws
// std::runtime_error when the output file cannot be created.
int run_to_file(const std::vector<std::string>& argv, const std::string& output_path);

}  // namespace mechgen::ondemand
