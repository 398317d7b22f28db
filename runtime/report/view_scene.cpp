#include "report/view_scene.hpp"

#include <cmath>

namespace mechgen::report {

Quat planar_rotation(double th) {
  return {std::cos(th / 2), 0, 0, std::sin(th / 2)};
}

}  // namespace mechgen::report
