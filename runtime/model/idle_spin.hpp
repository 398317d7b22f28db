// Idle spins of links between two spherical joints (issue 27 item 7), shared by the URDF / MJCF
// importer and the spatial reader: a binary link between spherical joints A and B (a rod), or a
// chain joined by prismatics along the line through the two centres and revolutes about it (a
// cylinder and its piston), spins about that line and no driver can fix it. The remedy of both:
// B becomes universal, its axes normal to the line, which holds the spin at its reference.
#pragma once

#include <array>
#include <cmath>
#include <optional>
#include <vector>

namespace mechgen {

using SpinVec = std::array<double, 3>;

enum class SpinJointKind { spherical, prismatic, revolute, other };

struct SpinJoint {
  SpinJointKind kind = SpinJointKind::other;
  int first = -1, second = -1;
  SpinVec s0{}, s{};  // a point of the joint and its unit axis (ground frame, reference pose)
};

struct IdleSpin {
  int a = -1, b = -1;       // the spherical joints at the two ends; b is the one made universal
  std::vector<int> bodies;  // the links between them, from a's side
  SpinVec u{};              // unit direction from a's centre to b's
  int normal = 0;           // the unit axis (0 x, 1 y, 2 z) least aligned with u: s = u x e
};

namespace idle_spin_detail {
inline double dot(const SpinVec& a, const SpinVec& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline SpinVec cross(const SpinVec& a, const SpinVec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline SpinVec minus(const SpinVec& a, const SpinVec& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline double norm(const SpinVec& a) {
  return std::sqrt(dot(a, a));
}
// Distance between two lines (point, unit direction); parallel lines: their separation.
inline double line_distance(const SpinVec& p1, const SpinVec& d1, const SpinVec& p2,
                            const SpinVec& d2) {
  const SpinVec n = cross(d1, d2), w = minus(p2, p1);
  if (norm(n) < 1e-12) {
    const double along = dot(d1, w);
    return norm({w[0] - d1[0] * along, w[1] - d1[1] * along, w[2] - d1[2] * along});
  }
  return std::abs(dot(w, n)) / norm(n);
}
}  // namespace idle_spin_detail

// The first such link, joints in order, each spherical joint looked at from its second body then
// from its first; `ground[b]`: body b is the ground; `tiny`: the distance below which points
// coincide and lines meet (m).
inline std::optional<IdleSpin> find_idle_spin(const std::vector<SpinJoint>& joints,
                                              const std::vector<bool>& ground, double tiny) {
  using namespace idle_spin_detail;
  auto joints_of = [&](int body) {
    std::vector<int> out;
    for (size_t j = 0; j < joints.size(); ++j)
      if (joints[j].first == body || joints[j].second == body) out.push_back(static_cast<int>(j));
    return out;
  };
  for (size_t a_index = 0; a_index < joints.size(); ++a_index) {
    const SpinJoint& a = joints[a_index];
    if (a.kind != SpinJointKind::spherical) continue;
    for (const bool forward : {true, false}) {
      int body = forward ? a.second : a.first;
      int came = static_cast<int>(a_index);
      std::vector<int> bodies, between;
      int b_index = -1;
      for (int step = 0; step < 4 && b_index < 0; ++step) {
        if (ground[static_cast<size_t>(body)]) break;
        const std::vector<int> js = joints_of(body);
        if (js.size() != 2) break;
        bodies.push_back(body);
        const int next = js[0] == came ? js[1] : js[0];
        const SpinJoint& k = joints[static_cast<size_t>(next)];
        if (k.kind == SpinJointKind::spherical) {
          b_index = next;
        } else if (k.kind == SpinJointKind::prismatic || k.kind == SpinJointKind::revolute) {
          between.push_back(next);
          body = k.first == body ? k.second : k.first;
          came = next;
        } else {
          break;
        }
      }
      if (b_index < 0) continue;
      const SpinVec d = minus(joints[static_cast<size_t>(b_index)].s0, a.s0);
      if (!(norm(d) > tiny)) continue;
      const SpinVec u{d[0] / norm(d), d[1] / norm(d), d[2] / norm(d)};
      bool along = true;
      for (const int k : between) {
        const SpinJoint& j = joints[static_cast<size_t>(k)];
        along = along && std::abs(std::abs(dot(j.s, u)) - 1) < 1e-9 &&
                (j.kind == SpinJointKind::prismatic || line_distance(j.s0, j.s, a.s0, u) < tiny);
      }
      if (!along) continue;
      IdleSpin spin{static_cast<int>(a_index), b_index, bodies, u, 0};
      if (std::abs(u[1]) < std::abs(u[0]) && std::abs(u[1]) <= std::abs(u[2]))
        spin.normal = 1;
      else if (std::abs(u[2]) < std::abs(u[0]))
        spin.normal = 2;
      return spin;
    }
  }
  return std::nullopt;
}

}  // namespace mechgen
