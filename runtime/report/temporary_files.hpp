// Temporary files and folders that must not outlive the process that made them (issue 26 item 3):
// an output's hidden temporary, a kernel's build folder, the compiler working in it.
//
// - Registered ones are removed by a handler of SIGINT, SIGTERM and SIGHUP (installed on the first
//   registration, unless the signal is ignored, as under nohup), which first kills the registered
//   process groups (a compiler and its children), then re-raises the signal: the process still
//   dies of it. Their owner removes them on every other path.
// - SIGKILL runs no handler: what a killed process left is found by the next process that uses the
//   same name. Its owner held an exclusive flock(2) on a lock file (the temporary itself, or a
//   folder's `owner.lock`); the kernel releases it when the owner dies, so a lock that can be taken
//   marks an abandoned temporary, and one still held a live process's. An age guards the moment
//   between creating a temporary and locking it.
#pragma once

#include <signal.h>

#include <chrono>
#include <string>

namespace mechgen::report {

// Removed by the signal handler until unregistered; a folder with the files in it (it must hold no
// sub-folder). Returns a slot for unregister_temporary, or -1 when every slot is taken (it is then
// only removed by its owner). `path` should be absolute or stay valid for the process's lifetime
// (the working folder never changes in mechgen).
int register_temporary(const std::string& path, bool folder);
// A process group killed (SIGKILL) by the handler before the temporaries are removed.
int register_process_group(int group);
void unregister_temporary(int slot);

// Holds SIGINT, SIGTERM and SIGHUP in this thread, the handler installed first, while a temporary
// is created and registered (scope it around both): a signal between the two would leave the
// temporary behind (seen under AddressSanitizer, whose allocations widen that moment). A held
// signal arrives when the guard ends, the temporary then registered.
class SignalsHeld {
 public:
  SignalsHeld();
  ~SignalsHeld();
  SignalsHeld(const SignalsHeld&) = delete;
  SignalsHeld& operator=(const SignalsHeld&) = delete;

 private:
  sigset_t previous_;
};

// Locks `fd` (flock LOCK_EX, without waiting): the open file then marks its temporary as live.
// False when another process holds the lock.
bool lock_exclusively(int fd);

// True when `lock_file` is owned by this user, was last modified at least `min_age` ago and its
// lock can be taken: its owner is gone. A missing lock file counts as free (`when_missing`, the
// modification time of what it guarded, decides the age then).
bool is_abandoned(const std::string& lock_file, std::chrono::seconds min_age,
                  const std::string& when_missing = "");

// Stale temporaries are cleaned only this long after their last change.
inline constexpr std::chrono::seconds kStaleAge{60};

}  // namespace mechgen::report
