#include "sweep/progress.hpp"

#include <unistd.h>

#include <algorithm>

namespace mechgen {

std::string progress_line(const std::string& label, size_t done, size_t total, double seconds) {
  char text[160];
  const double rate = seconds > 0 ? static_cast<double>(done) / seconds : 0;
  const int percent =
      total ? static_cast<int>(100.0 * static_cast<double>(done) / static_cast<double>(total))
            : 100;
  std::string left = "estimating";
  if (rate > 0) {
    char remaining[32];
    std::snprintf(remaining, sizeof remaining, "%.1f s left",
                  static_cast<double>(total - std::min(done, total)) / rate);
    left = remaining;
  }
  std::snprintf(text, sizeof text, "%s: %zu / %zu samples (%d%%), %.2g samples/s, %s",
                label.c_str(), done, total, percent, rate, left.c_str());
  return text;
}

bool Progress::stderr_is_tty() {
  return ::isatty(STDERR_FILENO) == 1;
}

Progress::Progress(std::string label, size_t total, std::FILE* out, bool enabled)
    : label_(std::move(label)),
      total_(total),
      out_(out),
      enabled_(enabled),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

Progress::~Progress() {
  if (!enabled_ || width_ == 0) return;
  std::fprintf(out_, "\r%*s\r", static_cast<int>(width_), "");
  std::fflush(out_);
}

void Progress::advance(size_t n) {
  const size_t done = done_ += n;
  if (!enabled_) return;
  const std::unique_lock<std::mutex> lock(draw_lock_, std::try_to_lock);
  if (!lock.owns_lock()) return;  // another thread is drawing
  const auto now = std::chrono::steady_clock::now();
  if (!started_) {  // the rate counts from the first samples, not from the set-up before them
    started_ = true;
    start_ = last_draw_ = now;
    return;
  }
  // A short run draws nothing; a long one from 0.3 s on, ten times a second, and its end.
  const bool finished = done >= total_ && width_ > 0;
  if (!finished && (now - start_ < std::chrono::milliseconds(300) ||
                    now - last_draw_ < std::chrono::milliseconds(100)))
    return;
  last_draw_ = now;
  draw(done);
}

void Progress::draw(size_t done) {
  const std::string line = progress_line(
      label_, done, total_, std::chrono::duration<double>(last_draw_ - start_).count());
  // Pad over a longer previous line.
  std::fprintf(out_, "\r%s%*s", line.c_str(),
               static_cast<int>(width_ > line.size() ? width_ - line.size() : 0), "");
  std::fflush(out_);
  width_ = std::max(width_, line.size());
}

}  // namespace mechgen
