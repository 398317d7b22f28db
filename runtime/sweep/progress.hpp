// A progress line for long runs: samples done, rate and time left, redrawn in place on stderr at
// most ten times a second from 0.3 s into the run (a short run draws nothing), and only when
// stderr is a terminal (silent in pipes, logs and tests).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

namespace mechgen {

// "sweep pasibot: 412000 / 1000000 samples (41%), 1.6e+06 samples/s, 0.4 s left"
std::string progress_line(const std::string& label, size_t done, size_t total, double seconds);

class Progress {
 public:
  // Draws on `out` when `enabled` (by default: when stderr is a terminal).
  Progress(std::string label, size_t total, std::FILE* out = stderr,
           bool enabled = stderr_is_tty());
  ~Progress();  // clears the line
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // `n` more samples done; safe from any thread.
  void advance(size_t n);
  static bool stderr_is_tty();

 private:
  void draw(size_t done);
  std::string label_;
  size_t total_;
  std::FILE* out_;
  bool enabled_;
  std::atomic<size_t> done_{0};
  std::mutex draw_lock_;
  bool started_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
  size_t width_ = 0;  // of the last line drawn
};

}  // namespace mechgen
