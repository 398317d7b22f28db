// The walking lecture's minimal walking function (seed 003) as a controller loop: at 1 kHz the
// phase advances, the step motion pattern generator gives each leg's extension and leg angle, the
// abstract kinematics turns them into joint angles (what the loop would send to the robot), and
// the generated forward kinematics of models/lecture_leg.yaml (generated/lecture_leg/) gives the
// foot position relative to the hip. Two legs in antiphase; float; no heap, no exceptions, no RTTI.
//
//   walking [--seconds T] [--realtime] [OUT.csv]
// writes one CSV row per tick (stdout without OUT.csv): t, then for each leg (right, left) the
// phase mu, extension eta, leg angle theta_leg, joint angles q1 q2 q3, and the ankle and toe
// positions from the generated FK. --realtime paces the ticks by the monotonic clock (1 ms apart)
// and reports the longest tick's computation. A summary goes to stderr.
#include <fcntl.h>
#include <time.h>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "lecture_leg/lecture_leg.hpp"
#include "step_pattern.hpp"

namespace k = mechgen::gen::lecture_leg;

namespace {

constexpr int rate = 1000;   // Hz: ticks per second
constexpr int cycle = 1000;  // ticks per gait cycle (mu from -pi to pi): 1 s, one step a leg
constexpr float S = 0.25f;   // rad: leg swing amplitude
constexpr float C1 = 0.1f;   // leg lifting: extension 0.9 -> 0.8 at mid-swing
constexpr float eta0 = 0.9f;

struct LegRow {
  float mu, eta, theta_leg;
  walking::Joints<float> q;
  float ankle_x, ankle_y, toe_x, toe_y;
};

// The phase mu = mu + dmu of the lecture's loop, kept as a tick count modulo the cycle so that a
// float phase does not drift over a long run: mu = -pi + 2 pi (tick mod cycle) / cycle.
float phase(long tick) {
  const long k = ((tick % cycle) + cycle) % cycle;
  return -walking::pi_value<float>() +
         2.0f * walking::pi_value<float>() * static_cast<float>(k) / static_cast<float>(cycle);
}

bool leg_tick(const walking::StepPattern<float>& pattern, const k::Params<float>& params, long tick,
              LegRow& row) {
  row.mu = phase(tick);
  row.eta = walking::leg_extension(pattern, row.mu);
  row.theta_leg = walking::leg_angle(pattern, row.mu);
  row.q = walking::abstract_kinematics(row.eta, row.theta_leg, 0.0f);
  // sendToRobot(q1, q2, q3) would go here; the generated FK says where the foot is.
  k::Inputs<float> in;
  in.q1 = row.q.q1, in.q2 = row.q.q2, in.q3 = row.q.q3;
  k::State<float> s;
  if (k::kinematics(params, in, s) != k::Status::ok) return false;
  row.ankle_x = s.points.ankle.x, row.ankle_y = s.points.ankle.y;
  row.toe_x = s.points.toe.x, row.toe_y = s.points.toe.y;
  return true;
}

// The stream goes out through a static buffer and write(2): stdio would allocate its own buffer.
class Stream {
 public:
  explicit Stream(int fd) : fd_(fd) {}
  template <class... A>
  void print(const char* format, A... args) {
    if (used_ + line > sizeof buffer_) flush();
    const int n = std::snprintf(buffer_ + used_, sizeof buffer_ - used_, format, args...);
    if (n > 0) used_ += static_cast<size_t>(n);
  }
  bool flush() {
    size_t done = 0;
    while (done < used_) {
      const ssize_t n = ::write(fd_, buffer_ + done, used_ - done);
      if (n <= 0) ok_ = false;
      if (n <= 0) break;
      done += static_cast<size_t>(n);
    }
    used_ = 0;
    return ok_;
  }

 private:
  static constexpr size_t line = 512;  // longer than any one print
  int fd_;
  bool ok_ = true;
  size_t used_ = 0;
  char buffer_[1 << 16];
};

void write_leg(Stream& out, const LegRow& r) {
  out.print(",%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g", r.mu, r.eta, r.theta_leg, r.q.q1,
            r.q.q2, r.q.q3, r.ankle_x, r.ankle_y, r.toe_x, r.toe_y);
}

// Bytes the heap hands out (glibc), to show the loop takes none.
long heap_in_use() {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  return static_cast<long>(mallinfo2().uordblks);
#else
  return -1;
#endif
}

double now() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 3.0;
  bool realtime = false;
  const char* path = nullptr;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--seconds") == 0 && i + 1 < argc) {
      seconds = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--realtime") == 0) {
      realtime = true;
    } else if (argv[i][0] != '-' && path == nullptr) {
      path = argv[i];
    } else {
      std::fprintf(stderr, "usage: walking [--seconds T] [--realtime] [OUT.csv]\n");
      return 1;
    }
  }
  if (!(seconds > 0 && seconds <= 3600)) {
    std::fprintf(stderr, "walking: --seconds must be in (0, 3600]\n");
    return 1;
  }
  const int fd = path ? ::open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644) : 1;
  if (fd < 0) {
    std::fprintf(stderr, "walking: cannot write '%s'\n", path);
    return 1;
  }
  const walking::StepPattern<float> pattern{S, C1, walking::level_stance_c2(S, eta0), eta0};
  const k::Params<float> params;  // the model's defaults: l = 0.2 m, f = 0.08 m
  static Stream out(fd);
  out.print("t");
  static const char* const legs[] = {"right", "left"};
  static const char* const columns[] = {"mu", "eta",     "theta_leg", "q1",    "q2",
                                        "q3", "ankle.x", "ankle.y",   "toe.x", "toe.y"};
  for (const char* leg : legs)
    for (const char* c : columns) out.print(",%s.%s", leg, c);
  out.print("\n");

  const long ticks = std::lround(seconds * rate);
  timespec next;
  clock_gettime(CLOCK_MONOTONIC, &next);
  double longest = 0;
  long overruns = 0;
  const long heap_before = heap_in_use();
  for (long tick = 0; tick <= ticks; ++tick) {
    const double start = now();
    // Right leg at touch-down (mu = 0) at t = 0, left leg half a cycle behind (lift-off).
    LegRow right, left;
    if (!leg_tick(pattern, params, tick + cycle / 2, right) ||
        !leg_tick(pattern, params, tick, left)) {
      std::fprintf(stderr, "walking: tick %ld: the kernel failed\n", tick);
      return 1;
    }
    const double spent = now() - start;
    longest = spent > longest ? spent : longest;
    out.print("%.9g", static_cast<double>(tick) / rate);
    write_leg(out, right);
    write_leg(out, left);
    out.print("\n");
    if (realtime) {
      next.tv_nsec += 1000000000L / rate;
      if (next.tv_nsec >= 1000000000L) next.tv_nsec -= 1000000000L, ++next.tv_sec;
      timespec current;
      clock_gettime(CLOCK_MONOTONIC, &current);
      if (current.tv_sec > next.tv_sec ||
          (current.tv_sec == next.tv_sec && current.tv_nsec > next.tv_nsec))
        ++overruns;
      clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr);
    }
  }
  const long heap_after = heap_in_use();
  if (!out.flush() || (path && ::close(fd) != 0)) {
    std::fprintf(stderr, "walking: cannot write '%s'\n", path);
    return 1;
  }
  std::fprintf(stderr,
               "walking: %ld ticks at %d Hz, S = %g rad, C1 = %g, C2 = %g, eta0 = %g; longest tick "
               "(pattern, abstract kinematics, FK, both legs) %.1f us",
               ticks + 1, rate, static_cast<double>(pattern.S), static_cast<double>(pattern.C1),
               static_cast<double>(pattern.C2), static_cast<double>(pattern.eta0), longest * 1e6);
  if (realtime) std::fprintf(stderr, ", %ld missed deadlines", overruns);
  std::fprintf(stderr, "\nwalking: heap bytes in use before the loop %ld, after it %ld\n",
               heap_before, heap_after);
  return 0;
}
