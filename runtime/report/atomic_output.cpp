#include "report/atomic_output.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include <sys/stat.h>
#include <unistd.h>

namespace mechgen::report {

namespace {

[[noreturn]] void cannot_write(const std::string& path, const std::string& reason) {
  throw std::runtime_error("cannot write '" + path + "': " + reason);
}

std::string folder_of(const std::string& path) {
  const std::string parent = std::filesystem::path(path).parent_path().string();
  return parent.empty() ? "." : parent;
}

}  // namespace

// A device or a pipe (/dev/null, /dev/stdout): written in place, never replaced.
bool is_special(const std::string& path) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  return !error && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status) &&
         !std::filesystem::is_directory(status);
}

void check_output_path(const std::string& path) {
  if (path.empty()) cannot_write(path, "empty file name");
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) cannot_write(path, "is a folder");
  if (is_special(path)) return;
  const std::string folder = folder_of(path);
  if (!std::filesystem::is_directory(folder, error))
    cannot_write(path, "no folder '" + folder + "'");
  if (access(folder.c_str(), W_OK) != 0)
    cannot_write(path, "folder '" + folder + "': " + std::strerror(errno));
}

AtomicOutput::AtomicOutput(const std::string& path) : path_(path) {
  check_output_path(path);
  if (is_special(path)) {
    out_.open(path, std::ios::binary);
    if (!out_) cannot_write(path, "cannot open");
    return;
  }
  const std::filesystem::path target(path);
  std::string pattern =
      (std::filesystem::path(folder_of(path)) / ("." + target.filename().string() + ".XXXXXX"))
          .string();
  const int fd = mkstemp(pattern.data());
  if (fd < 0) cannot_write(path, std::strerror(errno));
  // mkstemp creates the file 0600; give it the mode a plain open would (0666 less the umask).
  const mode_t mask = umask(0);
  umask(mask);
  fchmod(fd, 0666 & ~mask);
  close(fd);
  temporary_ = pattern;
  out_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    std::remove(temporary_.c_str());
    cannot_write(path, "cannot open a temporary file");
  }
}

AtomicOutput::~AtomicOutput() {
  if (committed_) return;
  out_.close();
  if (!temporary_.empty()) std::remove(temporary_.c_str());
}

void AtomicOutput::commit() {
  out_.flush();
  out_.close();
  if (temporary_.empty()) {  // a device or a pipe, written in place
    committed_ = true;
    if (!out_) cannot_write(path_, "write error");
    return;
  }
  if (!out_) {
    std::remove(temporary_.c_str());
    committed_ = true;
    cannot_write(path_, "write error (disk full?)");
  }
  if (std::rename(temporary_.c_str(), path_.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary_.c_str());
    committed_ = true;
    cannot_write(path_, reason);
  }
  committed_ = true;
}

void write_file_atomically(const std::string& path, const std::string& text) {
  AtomicOutput output(path);
  output.stream() << text;
  output.commit();
}

}  // namespace mechgen::report
