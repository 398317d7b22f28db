#include "report/temporary_files.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <ctime>
#include <mutex>

namespace mechgen::report {

namespace {

// A fixed table the signal handler can read without locks or allocation.
enum State : int { kFree, kFilling, kFile, kFolder, kGroup };
struct Slot {
  std::atomic<int> state{kFree};
  int group = 0;
  char path[4096] = {};
};
constexpr int kSlots = 64;
Slot g_slots[kSlots];

// Removes the files of a flat folder, then the folder (async-signal-safe: raw getdents64).
void remove_flat_folder(const char* path) {
  const int dir = ::open(path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (dir >= 0) {
    alignas(8) char buffer[4096];
    for (;;) {
      const long n = ::syscall(SYS_getdents64, dir, buffer, sizeof buffer);
      if (n <= 0) break;
      for (long at = 0; at < n;) {
        struct Entry {
          ino64_t ino;
          off64_t off;
          unsigned short reclen;
          unsigned char type;
          char name[1];
        };
        const auto* entry = reinterpret_cast<const Entry*>(buffer + at);
        const char* name = entry->name;
        if (std::strcmp(name, ".") != 0 && std::strcmp(name, "..") != 0) ::unlinkat(dir, name, 0);
        at += entry->reclen;
      }
    }
    ::close(dir);
  }
  ::rmdir(path);
}

void on_signal(int signal) {
  for (Slot& slot : g_slots)
    if (slot.state.load() == kGroup) ::kill(-slot.group, SIGKILL);
  for (Slot& slot : g_slots) {
    const int state = slot.state.load();
    if (state == kFile) ::unlink(slot.path);
    if (state == kFolder) remove_flat_folder(slot.path);
  }
  ::signal(signal, SIG_DFL);
  ::raise(signal);
}

void install_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
      struct sigaction old {};
      if (::sigaction(signal, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
      struct sigaction action {};
      action.sa_handler = &on_signal;
      sigemptyset(&action.sa_mask);
      ::sigaction(signal, &action, nullptr);
    }
  });
}

int take_slot(int state, const std::string& path, int group) {
  if (path.size() >= sizeof g_slots[0].path) return -1;
  install_handlers();
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (!g_slots[i].state.compare_exchange_strong(expected, kFilling)) continue;
    std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
    g_slots[i].group = group;
    g_slots[i].state.store(state);
    return i;
  }
  return -1;
}

bool old_enough(const struct stat& info, std::chrono::seconds min_age) {
  return std::time(nullptr) - info.st_mtime >= min_age.count();
}

}  // namespace

int register_temporary(const std::string& path, bool folder) {
  return take_slot(folder ? kFolder : kFile, path, 0);
}

int register_process_group(int group) {
  return take_slot(kGroup, "", group);
}

SignalsHeld::SignalsHeld() {
  install_handlers();
  sigset_t held;
  sigemptyset(&held);
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&held, signal);
  ::pthread_sigmask(SIG_BLOCK, &held, &previous_);
}

SignalsHeld::~SignalsHeld() {
  ::pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
}

void unregister_temporary(int slot) {
  if (slot >= 0 && slot < kSlots) g_slots[slot].state.store(kFree);
}

bool lock_exclusively(int fd) {
  return ::flock(fd, LOCK_EX | LOCK_NB) == 0;
}

bool is_abandoned(const std::string& lock_file, std::chrono::seconds min_age,
                  const std::string& when_missing) {
  const int fd = ::open(lock_file.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
  struct stat info {};
  if (fd < 0) {
    if (errno != ENOENT || when_missing.empty()) return false;
    return ::lstat(when_missing.c_str(), &info) == 0 && info.st_uid == ::geteuid() &&
           old_enough(info, min_age);
  }
  const bool abandoned = ::fstat(fd, &info) == 0 && S_ISREG(info.st_mode) &&
                         info.st_uid == ::geteuid() && old_enough(info, min_age) &&
                         lock_exclusively(fd);
  ::close(fd);  // releases the lock just taken
  return abandoned;
}

}  // namespace mechgen::report
