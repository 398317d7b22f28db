// Output files that are never seen half written: the text goes to a temporary file in the same
// folder, renamed over the final path only when complete (rename(2) is atomic within a file
// system), so a process killed mid-write leaves the previous file intact; a write that fails
// (or is abandoned by an exception) removes its temporary. A device or a pipe (/dev/null) is
// written in place.
#pragma once

#include <fstream>
#include <string>

namespace mechgen::report {

class AtomicOutput {
 public:
  // Creates the temporary `<folder>/.<name>.XXXXXX`; throws std::runtime_error
  // "cannot write 'PATH': REASON" when it cannot.
  explicit AtomicOutput(const std::string& path);
  ~AtomicOutput();  // not committed: the temporary is removed, the final path untouched
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  std::ostream& stream() { return out_; }
  // Flushes, closes and renames the temporary over the final path; throws std::runtime_error
  // "cannot write 'PATH': ..." on a write error (the temporary is then removed).
  void commit();

 private:
  std::string path_, temporary_;
  std::ofstream out_;
  bool committed_ = false;
};

// Writes `text` to `path` through an AtomicOutput.
void write_file_atomically(const std::string& path, const std::string& text);

// Checks, before any computation, that `path` can be written: not a folder, in a folder that
// exists and is writable. Throws std::runtime_error "cannot write 'PATH': REASON".
void check_output_path(const std::string& path);

}  // namespace mechgen::report
