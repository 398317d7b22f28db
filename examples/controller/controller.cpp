// A controller loop calling a generated kernel: float, no heap, no exceptions. At each tick it
// evaluates the slider-crank at its driver's set point (the model's own motion) and takes the
// torque the motor must give as its feed-forward; over one crank turn it prints the range of that
// torque and the largest crank-bearing force. The kernel comes from the installed mechgen package
// (mechgen_add_kernel in CMakeLists.txt).
#include <cmath>
#include <cstdio>

#include "slider_crank.hpp"

namespace k = mechgen::gen::slider_crank;

int main() {
  const k::Params<float> p;  // the model's defaults; any field may change at run time
  constexpr int ticks = 1001;  // samples of one crank turn, both ends included
  const float period = 2.0f * 3.14159265358979f / p.w;
  float lowest = INFINITY, highest = -INFINITY, bearing = 0.0f;
  k::State<float> s;
  for (int i = 0; i < ticks; ++i) {
    k::Inputs<float> in;
    k::driver_inputs(p, period * static_cast<float>(i) / (ticks - 1), in);
    if (k::evaluate(p, in, s) != k::Status::ok) {
      std::printf("tick %d: %s failed\n", i, k::group_names[s.failed_group]);
      return 1;
    }
    const float feed_forward = s.drivers.crank_angle.effort;
    lowest = std::fmin(lowest, feed_forward);
    highest = std::fmax(highest, feed_forward);
    bearing = std::fmax(bearing, std::hypot(s.joints.O_ground_crank.fx, s.joints.O_ground_crank.fy));
  }
  std::printf("crank_angle.effort min %.6g max %.6g N m\n", lowest, highest);
  std::printf("O_ground_crank largest force %.6g N\n", bearing);
  return 0;
}
