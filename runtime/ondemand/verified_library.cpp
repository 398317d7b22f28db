#include "ondemand/verified_library.hpp"

#include <dlfcn.h>
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "ondemand/cache_folder.hpp"
#include "ondemand/sha256.hpp"

namespace mechgen::ondemand {

namespace {

std::string record_of(const std::string& library) {
  return library + ".sha256";
}

// The hash recorded for `library`, or "" with the reason in `problem`.
std::string recorded_hash(const std::string& library, std::string& problem) {
  const int fd = ::open(record_of(library).c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) {
    problem = errno == ENOENT
                  ? "no content hash recorded beside it: not built by mechgen"
                  : "its hash record " + record_of(library) + ": " + std::strerror(errno);
    return "";
  }
  std::string text(512, '\0');
  const std::string why = untrusted_file_reason(fd);
  const ssize_t n = why.empty() ? ::read(fd, text.data(), text.size()) : 0;
  ::close(fd);
  if (!why.empty()) {
    problem = "its hash record " + record_of(library) + ": " + why;
    return "";
  }
  text.resize(n > 0 ? static_cast<size_t>(n) : 0);
  const std::string name = std::filesystem::path(library).filename().string();
  if (text.size() != 64 + 2 + name.size() + 1 ||
      text.compare(64, std::string::npos, "  " + name + "\n") != 0) {
    problem = "its hash record " + record_of(library) + " is not of this file";
    return "";
  }
  return text.substr(0, 64);
}

}  // namespace

void record_library_hash(const std::string& built, const std::string& final_name,
                         const std::string& record) {
  const int fd = ::open(built.c_str(), O_RDONLY | O_CLOEXEC);
  const std::string hash = fd < 0 ? "" : sha256_of_fd(fd);
  if (fd >= 0) ::close(fd);
  std::ofstream out(record, std::ios::binary | std::ios::trunc);
  out << hash << "  " << final_name << "\n";
  out.close();
  if (hash.empty() || !out) throw std::runtime_error("cannot record the hash of " + built);
}

void* open_verified_library(const std::string& library, std::string& problem) {
  const int fd = ::open(library.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) {
    problem = errno == ELOOP ? "a symbolic link" : std::strerror(errno);
    return nullptr;
  }
  problem = untrusted_file_reason(fd);
  const std::string expected = problem.empty() ? recorded_hash(library, problem) : "";
  if (!expected.empty() && sha256_of_fd(fd) != expected)
    problem =
        "its content is not what was built (its SHA-256 differs from the one recorded beside it: "
        "truncated, corrupt or replaced)";
  if (expected.empty() || !problem.empty()) {
    ::close(fd);
    return nullptr;
  }
  // The descriptor is never closed: the loader knows the library by this name, which must not
  // come to mean another file.
  void* handle = ::dlopen(("/proc/self/fd/" + std::to_string(fd)).c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) problem = ::dlerror();
  return handle;
}

}  // namespace mechgen::ondemand
