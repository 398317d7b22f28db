#include "ondemand/cache_folder.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace mechgen::ondemand {

namespace fs = std::filesystem;

namespace {

std::string mode_text(mode_t mode) {
  char text[8];
  std::snprintf(text, sizeof text, "%04o", static_cast<unsigned>(mode & 07777));
  return text;
}

// Why `info` (a folder or file in the cache's path) could have been changed by another user, or "".
std::string unsafe_reason(const struct stat& info, bool sticky_allowed) {
  if (info.st_uid != ::geteuid() && info.st_uid != 0)
    return "owned by another user (uid " + std::to_string(info.st_uid) + ")";
  const bool shared = (info.st_mode & (S_IWGRP | S_IWOTH)) != 0;
  if (shared && !(sticky_allowed && (info.st_mode & S_ISVTX)))
    return std::string("writable by ") + ((info.st_mode & S_IWOTH) ? "others" : "its group") +
           " (mode " + mode_text(info.st_mode) + ")";
  return "";
}

// Every folder from the root down to `path` (which exists), checked.
void check_folders(const fs::path& path, const std::string& dir) {
  fs::path prefix;
  for (const fs::path& part : path) {
    prefix /= part;
    struct stat info {};
    if (::stat(prefix.c_str(), &info) != 0) continue;  // a relative path's "." and such
    const bool is_cache = prefix == path;
    if (const std::string why = unsafe_reason(info, !is_cache); !why.empty())
      throw std::runtime_error(
          "the kernel cache " + dir + " is not safe to load kernels from: " +
          (is_cache ? "the folder" : "its parent folder " + prefix.string()) + " is " + why +
          ", so another user could plant a library there (make it owned by you and not writable "
          "by others, e.g. chmod go-w, or give --cache a private folder)");
  }
}

// Creates the missing folders of `dir`, each mode 0700.
void create_private(const fs::path& dir) {
  fs::path prefix;
  for (const fs::path& part : dir) {
    prefix /= part;
    if (::mkdir(prefix.c_str(), 0700) == 0 || errno == EEXIST) continue;
    throw std::runtime_error("cannot create the kernel cache " + dir.string() + ": " +
                             prefix.string() + ": " + std::strerror(errno));
  }
}

}  // namespace

CacheFolder open_cache_folder(const std::string& dir) {
  std::error_code error;
  const fs::path given = dir;
  if (fs::is_symlink(given, error) && !fs::exists(given, error))
    throw std::runtime_error("the kernel cache " + dir +
                             " is a symbolic link to a missing folder (" +
                             fs::read_symlink(given, error).string() +
                             "): create that folder or point --cache elsewhere");
  if (!fs::exists(given, error)) create_private(given);
  if (!fs::is_directory(given, error))
    throw std::runtime_error("the kernel cache " + dir + " is not a folder");
  const fs::path resolved = fs::canonical(given, error);
  if (error)
    throw std::runtime_error("cannot resolve the kernel cache " + dir + ": " + error.message());
  check_folders(fs::absolute(given), dir);
  check_folders(resolved, dir);
  return {resolved.string(), ::access(resolved.c_str(), W_OK) == 0};
}

std::string untrusted_file_reason(int fd) {
  struct stat info {};
  if (::fstat(fd, &info) != 0) return std::strerror(errno);
  if (!S_ISREG(info.st_mode)) return "not a regular file";
  const std::string why = unsafe_reason(info, false);
  return why.empty() ? "" : "it is " + why;
}

}  // namespace mechgen::ondemand
