#include "report/atomic_output.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "report/temporary_files.hpp"

namespace mechgen::report {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void cannot_write(const std::string& path, const std::string& reason) {
  throw std::runtime_error("cannot write '" + path + "': " + reason);
}

std::string folder_of(const std::string& path) {
  const std::string parent = fs::path(path).parent_path().string();
  return parent.empty() ? "." : parent;
}

// "1.2 GB", "300 MB", "12 kB"
std::string size_text(double bytes) {
  const char* units[] = {"bytes", "kB", "MB", "GB", "TB", "PB", "EB"};
  int unit = 0;
  while (bytes >= 1000 && unit < 6) bytes /= 1000, ++unit;
  char text[32];
  std::snprintf(text, sizeof text, unit ? "%.3g %s" : "%.0f %s", bytes, units[unit]);
  return text;
}

// The temporaries of `target` (".<name>.XXXXXX" beside it), as AtomicOutput names them.
bool is_temporary_of(const std::string& entry, const std::string& name) {
  const std::string prefix = "." + name + ".";
  if (entry.size() != prefix.size() + 6 || entry.rfind(prefix, 0) != 0) return false;
  for (size_t i = prefix.size(); i < entry.size(); ++i)
    if (!std::isalnum(static_cast<unsigned char>(entry[i]))) return false;
  return true;
}

// Removes what killed writers of `target` left (temporary_files.hpp: abandoned and old enough).
void remove_stale_temporaries(const fs::path& target) {
  std::error_code error;
  const std::string name = target.filename().string();
  for (const auto& entry : fs::directory_iterator(folder_of(target.string()), error))
    if (is_temporary_of(entry.path().filename().string(), name) &&
        is_abandoned(entry.path().string(), kStaleAge))
      fs::remove(entry.path(), error);
}

}  // namespace

std::string output_target(const std::string& path) {
  fs::path target = path;
  std::error_code error;
  for (int hops = 0; hops < 40 && fs::is_symlink(target, error); ++hops) {
    const fs::path link = fs::read_symlink(target, error);
    if (error) break;
    target = link.is_absolute() ? link : target.parent_path() / link;
  }
  return target.string();
}

// A device or a pipe (/dev/null, /dev/stdout): written in place, never replaced.
bool is_special(const std::string& path) {
  std::error_code error;
  const auto status = fs::status(path, error);
  return !error && fs::exists(status) && !fs::is_regular_file(status) && !fs::is_directory(status);
}

void check_output_path(const std::string& path) {
  if (path.empty()) cannot_write(path, "empty file name");
  std::error_code error;
  if (fs::is_directory(path, error)) cannot_write(path, "is a folder");
  if (is_special(path)) return;
  const std::string target = output_target(path);
  if (fs::is_symlink(target, error)) cannot_write(path, "too many levels of symbolic links");
  const std::string link_note = target == path ? "" : " (the target of the symbolic link)";
  struct stat info {};
  if (::stat(target.c_str(), &info) == 0 && S_ISREG(info.st_mode) &&
      ((info.st_mode & 0222) == 0 || ::access(target.c_str(), W_OK) != 0)) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(info.st_mode & 07777));
    cannot_write(path, "'" + target + "'" + link_note + " is read-only (mode " + mode +
                           "): make it writable (chmod u+w) or remove it first");
  }
  const std::string folder = folder_of(target);
  if (!fs::is_directory(folder, error))
    cannot_write(path, "no folder '" + folder + "'" + link_note);
  if (::access(folder.c_str(), W_OK) != 0)
    cannot_write(path, "folder '" + folder + "': " + std::strerror(errno));
}

void check_free_space(const std::string& path, std::uint64_t bytes) {
  if (bytes == 0 || is_special(path)) return;
  const std::string folder = folder_of(output_target(path));
  struct statvfs space {};
  if (::statvfs(folder.c_str(), &space) != 0) return;  // unknown: the write itself reports
  const double available =
      static_cast<double>(space.f_bavail) * static_cast<double>(space.f_frsize);
  if (static_cast<double>(bytes) > available)
    cannot_write(path, "it needs about " + size_text(static_cast<double>(bytes)) + " and only " +
                           size_text(available) + " are free in '" + folder + "'");
}

AtomicOutput::AtomicOutput(const std::string& path, std::uint64_t expected_bytes) : path_(path) {
  check_output_path(path);
  if (is_special(path)) {
    out_.open(path, std::ios::binary);
    if (!out_) cannot_write(path, "cannot open");
    return;
  }
  target_ = output_target(path);
  check_free_space(path, expected_bytes);
  remove_stale_temporaries(target_);
  std::string pattern =
      (fs::path(folder_of(target_)) / ("." + fs::path(target_).filename().string() + ".XXXXXX"))
          .string();
  int error = 0;
  {
    const SignalsHeld held;  // until the temporary is registered
    lock_fd_ = ::mkostemp(pattern.data(), O_CLOEXEC);
    error = errno;
    if (lock_fd_ >= 0) {
      temporary_ = pattern;
      slot_ = register_temporary(fs::absolute(temporary_).string(), false);
    }
  }
  if (lock_fd_ < 0) cannot_write(path, std::strerror(error));
  lock_exclusively(lock_fd_);  // a fresh file: nobody else holds it
  // mkstemp creates the file 0600: a replaced file keeps its mode, a new one gets what a plain open
  // would (0666 less the umask).
  struct stat info {};
  mode_t mode = 0;
  if (::stat(target_.c_str(), &info) == 0 && S_ISREG(info.st_mode)) {
    mode = info.st_mode & 07777;
  } else {
    const mode_t mask = ::umask(0);
    ::umask(mask);
    mode = 0666 & ~mask;
  }
  ::fchmod(lock_fd_, mode);
  out_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    discard();
    cannot_write(path, "cannot open a temporary file");
  }
}

void AtomicOutput::discard() {
  out_.close();
  if (!temporary_.empty()) std::remove(temporary_.c_str());
  unregister_temporary(slot_);
  if (lock_fd_ >= 0) ::close(lock_fd_);
  lock_fd_ = slot_ = -1;
  committed_ = true;
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) discard();
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
    discard();
    cannot_write(path_, "write error (disk full?)");
  }
  if (std::rename(temporary_.c_str(), target_.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    discard();
    cannot_write(path_, reason);
  }
  temporary_.clear();  // renamed: nothing to remove
  discard();
}

void write_file_atomically(const std::string& path, const std::string& text) {
  AtomicOutput output(path);
  output.stream() << text;
  output.commit();
}

}  // namespace mechgen::report
