#include "model/link_mass.hpp"

namespace mechgen {

PlanarMass bars_mass(const std::vector<std::pair<PointEx, PointEx>>& bars, const GiNaC::ex& width,
                     const GiNaC::ex& thickness, const GiNaC::ex& density) {
  GiNaC::ex mass = 0, mx = 0, my = 0, own = 0, second = 0;  // second: sum m |c|^2
  for (const auto& [a, b] : bars) {
    const GiNaC::ex dx = b.x - a.x, dy = b.y - a.y;
    const GiNaC::ex m = density * width * thickness * GiNaC::sqrt(dx * dx + dy * dy);
    const GiNaC::ex cx = (a.x + b.x) / 2, cy = (a.y + b.y) / 2;
    mass += m;
    mx += m * cx;
    my += m * cy;
    own += m * (dx * dx + dy * dy + width * width) / 12;
    second += m * (cx * cx + cy * cy);
  }
  const GiNaC::ex com_x = mx / mass, com_y = my / mass;
  return {mass, com_x, com_y, own + second - mass * (com_x * com_x + com_y * com_y)};
}

GiNaC::ex signed_area(const std::vector<PointEx>& v) {
  GiNaC::ex twice = 0;
  for (size_t i = 0; i < v.size(); ++i) {
    const PointEx& a = v[i];
    const PointEx& b = v[(i + 1) % v.size()];
    twice += a.x * b.y - b.x * a.y;
  }
  return twice / 2;
}

PlanarMass plate_mass(const std::vector<PointEx>& v, const GiNaC::ex& thickness,
                      const GiNaC::ex& density, int orientation) {
  GiNaC::ex twice_area = 0, sx = 0, sy = 0, polar = 0;
  for (size_t i = 0; i < v.size(); ++i) {
    const PointEx& a = v[i];
    const PointEx& b = v[(i + 1) % v.size()];
    const GiNaC::ex cross = a.x * b.y - b.x * a.y;
    twice_area += cross;
    sx += cross * (a.x + b.x);
    sy += cross * (a.y + b.y);
    polar += cross * (a.x * a.x + a.x * b.x + b.x * b.x + a.y * a.y + a.y * b.y + b.y * b.y);
  }
  // Signed sums: the orientation makes the area, and with it every moment, positive.
  const GiNaC::ex area = orientation * twice_area / 2;
  const GiNaC::ex com_x = sx / (3 * twice_area), com_y = sy / (3 * twice_area);
  const GiNaC::ex mass = density * thickness * area;
  const GiNaC::ex polar_origin = density * thickness * orientation * polar / 12;
  return {mass, com_x, com_y, polar_origin - mass * (com_x * com_x + com_y * com_y)};
}

}  // namespace mechgen
