// The kernel cache's folder and files, checked before anything in them is trusted: a library found
// there is executed (dlopen), so only this user (or root) may have been able to put it there.
//
// - A missing cache folder is created mode 0700 (its missing parents too).
// - Symbolic links in its path are resolved; every folder on the path as given and on the resolved
//   path must be owned by this user or root and not writable by group or others (a parent such as
//   /tmp may be, when its sticky bit keeps others from replacing what is in it; the cache folder
//   itself never). Otherwise: an error naming the folder and the fix (no silent fallback
//   elsewhere).
// - A file in it is trusted when it is a regular file (not a link), owned by this user or root and
//   not writable by group or others.
#pragma once

#include <string>

namespace mechgen::ondemand {

struct CacheFolder {
  std::string path;       // resolved (no symbolic link)
  bool writable = false;  // false: a read-only cache, loaded from, never built into
};

// The checked cache folder for the configured `dir` (kernel_cache.hpp's cache_dir()); throws
// std::runtime_error with the reason when it cannot be created or is not safe to load from.
CacheFolder open_cache_folder(const std::string& dir);

// Why the open file `fd` may not be trusted, or "" when it may.
std::string untrusted_file_reason(int fd);

}  // namespace mechgen::ondemand
