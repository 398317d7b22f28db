#include "ondemand/cache_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <stdexcept>
#include <thread>

#include "ondemand/cache_folder.hpp"
#include "ondemand/kernel_budget.hpp"

namespace mechgen::ondemand {

CacheLock::CacheLock(const std::string& path, const std::string& what, double timeout_seconds) {
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (fd_ < 0)
    throw std::runtime_error("cannot create the lock file " + path + ": " + std::strerror(errno));
  if (const std::string why = untrusted_file_reason(fd_); !why.empty()) {
    ::close(fd_);
    throw std::runtime_error("the lock file " + path + " is not safe to use: " + why);
  }
  const auto start = std::chrono::steady_clock::now();
  bool said = false;
  while (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const double waited =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (errno != EWOULDBLOCK && errno != EINTR) {
      const std::string reason = std::strerror(errno);
      ::close(fd_);
      throw std::runtime_error("cannot lock " + path + ": " + reason);
    }
    if (waited >= timeout_seconds) {
      ::close(fd_);
      char seconds[32];
      std::snprintf(seconds, sizeof seconds, "%g s", timeout_seconds);
      throw std::runtime_error("gave up after " + std::string(seconds) +
                               " waiting for another process building " + what +
                               " (it holds the lock " + path +
                               "; set MECHGEN_CACHE_LOCK_TIMEOUT to wait longer, or use --solver "
                               "numeric)");
    }
    if (!said) {
      std::cerr << "mechgen: waiting for another process building " << what << " (lock " << path
                << ")\n";
      said = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

CacheLock::~CacheLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

double cache_lock_timeout() {
  return environment_number("MECHGEN_CACHE_LOCK_TIMEOUT", 900, "seconds");
}

}  // namespace mechgen::ondemand
