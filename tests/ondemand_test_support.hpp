// Shared by the on-demand kernel tests (ondemand_test, spatial_ondemand_test): files as text, a
// one-place edit, and the mechgen binary (MECHGEN_BINARY) run with its stderr captured.
#pragma once

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace mechgen::test {

// The sanitizer build (tests/CMakeLists.txt defines MECHGEN_SANITIZE_BUILD there) is for memory
// errors: a test skips there what only repeats the plain build's numbers at many times the cost
// (a kernel compiled on first use, a large symbolic derivation).
#if defined(MECHGEN_SANITIZE_BUILD)
inline constexpr bool kSanitizerBuild = true;
#else
inline constexpr bool kSanitizerBuild = false;
#endif

inline std::string file_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// `text` with the first occurrence of `from` replaced by `to` (a test failure when absent).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// Runs `mechgen arguments` in a shell; returns its exit code, with its stderr in `err` (kept in
// dir/stderr.txt).
inline int run_mechgen(const std::string& arguments, const std::filesystem::path& dir,
                       std::string& err) {
  const std::string command = std::string(MECHGEN_BINARY) + " " + arguments + " 2>" +
                              (dir / "stderr.txt").string() + " >/dev/null";
  const int status = std::system(command.c_str());
  err = file_text(dir / "stderr.txt");
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// An empty folder of this process under the system's temporary one: <prefix>_<pid>_<what>.
inline std::filesystem::path fresh_dir(const std::string& prefix, const std::string& what) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    (prefix + "_" + std::to_string(::getpid()) + "_" + what);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace mechgen::test
