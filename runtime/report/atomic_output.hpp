// Output files that are never seen half written: the text goes to a temporary file in the same
// folder, renamed over the final path only when complete (rename(2) is atomic within a file
// system), so a process killed mid-write leaves the previous file intact. A device or a pipe
// (/dev/null) is written in place.
//
// The conventions of the tools users know (cp, sort -o, shell redirection):
// - a read-only file (no write permission for this user, or no write bit at all, even for root) is
//   refused with an error, never silently replaced;
// - a symbolic link is written through: its target (followed link by link) is replaced atomically,
//   with the temporary in the target's folder, and the link stays a link;
// - a replaced file keeps its permission bits; a new one gets 0666 less the umask.
//
// Temporaries (`<folder>/.<name>.XXXXXX`) never stay behind (report/temporary_files.hpp): removed
// on every error, by an abandoned write's destructor and on SIGINT/SIGTERM/SIGHUP; one of a run
// killed with SIGKILL is removed by the next write of the same output once it is a minute old and
// no live process holds its lock.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>

namespace mechgen::report {

class AtomicOutput {
 public:
  // Creates the temporary; throws std::runtime_error "cannot write 'PATH': REASON" when it cannot,
  // or when `expected_bytes` (0: unknown) exceed the free space of the target's file system.
  explicit AtomicOutput(const std::string& path, std::uint64_t expected_bytes = 0);
  ~AtomicOutput();  // not committed: the temporary is removed, the final path untouched
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  std::ostream& stream() { return out_; }
  // Flushes, closes and renames the temporary over the final path; throws std::runtime_error
  // "cannot write 'PATH': ..." on a write error (the temporary is then removed).
  void commit();

 private:
  void discard();

  std::string path_, target_, temporary_;
  std::ofstream out_;
  int lock_fd_ = -1;  // holds the temporary's lock: it belongs to a live process
  int slot_ = -1;     // its entry in the signal handler's table
  bool committed_ = false;
};

// Writes `text` to `path` through an AtomicOutput.
void write_file_atomically(const std::string& path, const std::string& text);

// Checks, before any computation, that `path` can be written: not a folder, not a read-only file,
// in a folder that exists and is writable (for a symbolic link: its target's). Throws
// std::runtime_error "cannot write 'PATH': REASON".
void check_output_path(const std::string& path);

// Checks that `bytes` fit in the free space of the file system `path` would be written to (its
// target's folder); throws std::runtime_error "cannot write 'PATH': it needs about ..." when not.
void check_free_space(const std::string& path, std::uint64_t bytes);

// The file `path` names, its symbolic links followed (a dangling link: the file it would create).
std::string output_target(const std::string& path);

}  // namespace mechgen::report
