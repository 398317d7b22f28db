// Single-support inverse dynamics of the real-body tree and the two ZMPs (floating_base.hpp).
#include "spatial/floating_base.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

namespace mechgen::spatial {

namespace {

using geometry::cross;

// Rate of momentum minus gravity of one body, about the ground origin.
Wrench body_wrench(const SpatialSolver& solver, const SpatialState& s, int b) {
  const SpatialInstance& in = solver.instance();
  const auto bi = static_cast<size_t>(b);
  const double m = in.mass[bi];
  const Pose frame = solver.body_pose(s, b);
  const M3 I = frame.R * in.inertia[bi] * geometry::transpose(frame.R);
  const V3 c = geometry::apply(frame, in.com[bi]);
  const V3 w = s.V[bi].w, al = s.A[bi].w;
  const V3 f = m * (solver.point_acceleration(s, b, in.com[bi]) - in.gravity);
  return {f, I * al + cross(w, I * w) + cross(c, f)};
}

}  // namespace

FloatingBaseLoads single_support_dynamics(const SpatialSolver& solver, const SpatialState& s,
                                          int support) {
  const SpatialModel& model = solver.model();
  const size_t nb = model.bodies.size(), nj = model.joints.size();
  FloatingBaseLoads out;
  out.torque.assign(nj, 0.0);
  // The real bodies' tree from the support foot, breadth first.
  std::vector<int> parent_joint(nb, -1), order;
  std::vector<bool> reached(nb, false);
  std::deque<int> queue{support};
  reached[static_cast<size_t>(support)] = true;
  while (!queue.empty()) {
    const int b = queue.front();
    queue.pop_front();
    order.push_back(b);
    for (size_t j = 0; j < nj; ++j) {
      const SpatialJoint& joint = model.joints[j];
      if (joint.is_virtual || (joint.first != b && joint.second != b)) continue;
      const int other = joint.first == b ? joint.second : joint.first;
      if (reached[static_cast<size_t>(other)]) {
        if (parent_joint[static_cast<size_t>(b)] != static_cast<int>(j))
          throw ModelError(joint.loc, "joint '" + joint.name +
                                          "' closes a loop of real bodies: single-support "
                                          "dynamics needs a tree");
        continue;
      }
      if (joint.columns.size() != 1)
        throw ModelError(joint.loc, "joint '" + joint.name +
                                        "': single-support dynamics takes one coordinate per "
                                        "real joint");
      reached[static_cast<size_t>(other)] = true;
      parent_joint[static_cast<size_t>(other)] = static_cast<int>(j);
      queue.push_back(other);
    }
  }
  for (size_t b = 0; b < nb; ++b)
    if (!reached[b] && !model.bodies[b].is_virtual && !model.bodies[b].ground)
      throw ModelError(model.bodies[b].loc, "body '" + model.bodies[b].name +
                                                "' is not connected to the support foot by real "
                                                "joints");
  // Leaves inwards: each body's wrench plus what lies beyond it.
  std::vector<Wrench> beyond(nb);
  for (size_t b = 0; b < nb; ++b)
    if (reached[b]) {
      beyond[b] = body_wrench(solver, s, static_cast<int>(b));
      out.momentum_rate = out.momentum_rate + beyond[b];
    }
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    const auto b = static_cast<size_t>(*it);
    const int j = parent_joint[b];
    if (j < 0) continue;
    const SpatialJoint& joint = model.joints[static_cast<size_t>(j)];
    const int parent = joint.first == *it ? joint.second : joint.first;
    beyond[static_cast<size_t>(parent)] = beyond[static_cast<size_t>(parent)] + beyond[b];
    // beyond[b]: the wrench of the parent on the subtree; as the first body's effort on the
    // second about the joint's screw.
    const int c = solver.graph().joint_column[static_cast<size_t>(j)];
    const double tau = geometry::reciprocal(s.screw[static_cast<size_t>(c)], beyond[b]);
    out.torque[static_cast<size_t>(j)] = joint.second == *it ? tau : -tau;
  }
  out.floor = beyond[static_cast<size_t>(support)];
  return out;
}

V3 zmp_of(const Wrench& w, double floor_z) {
  if (w.f[2] == 0) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan, nan};
  }
  // Moment about p = (x, y, floor_z): m - p x f, its x and y components zero.
  return {(floor_z * w.f[0] - w.m[1]) / w.f[2], (w.m[0] + floor_z * w.f[1]) / w.f[2], floor_z};
}

V3 lip_zmp(const V3& com, const V3& a, double g, double floor_z) {
  const double k = (com[2] - floor_z) / g;
  return {com[0] - k * a[0], com[1] - k * a[1], floor_z};
}

std::vector<V3> convex_hull_xy(std::vector<V3> pts) {
  std::sort(pts.begin(), pts.end(),
            [](const V3& a, const V3& b) { return a[0] < b[0] || (a[0] == b[0] && a[1] < b[1]); });
  if (pts.size() < 3) return pts;
  auto turn = [](const V3& o, const V3& a, const V3& b) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  };
  std::vector<V3> hull(2 * pts.size());
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) {  // lower hull
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, lower = k + 1; i-- > 0;) {  // upper hull
    while (k >= lower && turn(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  hull.resize(k - 1);
  return hull;
}

double polygon_margin(const std::vector<V3>& poly, const V3& p) {
  const size_t n = poly.size();
  double area = 0;
  for (size_t i = 0; i < n; ++i) {
    const V3& a = poly[i];
    const V3& b = poly[(i + 1) % n];
    area += a[0] * b[1] - b[0] * a[1];
  }
  const double sign = area >= 0 ? 1 : -1;  // counter-clockwise: the inside is on the left
  double margin = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < n; ++i) {
    const V3& a = poly[i];
    const V3& b = poly[(i + 1) % n];
    const double ex = b[0] - a[0], ey = b[1] - a[1];
    const double d = sign * (ex * (p[1] - a[1]) - ey * (p[0] - a[0])) / std::hypot(ex, ey);
    margin = std::min(margin, d);
  }
  return margin;
}

}  // namespace mechgen::spatial
