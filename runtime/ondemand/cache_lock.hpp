// An exclusive lock on a file in the kernel cache (flock(2), released by the kernel when its holder
// dies, even by SIGKILL): one process builds a kernel while the others that need it wait.
#pragma once

#include <string>

namespace mechgen::ondemand {

class CacheLock {
 public:
  // Creates `path` (0600) if needed and locks it, waiting at most `timeout_seconds`; says once on
  // stderr that it waits for `what`. Throws std::runtime_error on a timeout (naming the lock file)
  // or when the file cannot be created.
  CacheLock(const std::string& path, const std::string& what, double timeout_seconds);
  ~CacheLock();
  CacheLock(const CacheLock&) = delete;
  CacheLock& operator=(const CacheLock&) = delete;

 private:
  int fd_ = -1;
};

// $MECHGEN_CACHE_LOCK_TIMEOUT (seconds) when set to a positive number, else 900.
double cache_lock_timeout();

}  // namespace mechgen::ondemand
