// Closed-form inverse kinematics of the Table 1 leg (leg_ik.hpp).
#include "spatial/leg_ik.hpp"

#include <algorithm>
#include <cmath>

namespace mechgen::spatial {

LegGeometry leg_geometry(const SpatialSolver& solver, const std::array<std::string, 6>& names) {
  const SpatialModel& m = solver.model();
  const SpatialInstance& in = solver.instance();
  LegGeometry leg;
  const V3 axes[6] = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {1, 0, 0}};
  for (size_t k = 0; k < 6; ++k) {
    const int j = m.joint_index(names[k]);
    if (j < 0) throw ModelError({m.common.file, 0, 0}, "leg: no joint '" + names[k] + "'");
    const SpatialJoint& joint = m.joints[static_cast<size_t>(j)];
    const auto& axis =
        in.axes[static_cast<size_t>(solver.graph().joint_column[static_cast<size_t>(j)])];
    const V3 d = axis.s - axes[k];
    if (joint.type != SpatialJointType::revolute || geometry::dot(d, d) > 1e-18 ||
        (k > 0 && joint.first != m.joints[static_cast<size_t>(leg.joints[k - 1])].second))
      throw ModelError(joint.loc, "joint '" + joint.name +
                                      "' does not follow seed 001's Table 1 leg (revolutes about "
                                      "z, x, y, y, y, x in a serial chain)");
    leg.joints[k] = j;
  }
  auto point = [&](size_t k) { return in.joint_point[static_cast<size_t>(leg.joints[k])]; };
  auto dist = [](const V3& a, const V3& b) { return std::sqrt(geometry::dot(a - b, a - b)); };
  leg.hip = point(0), leg.ankle = point(4);
  // The knee on the pitch axis below the hip, the ankle's two axes crossing.
  const V3 knee = point(3);
  if (dist(point(1), leg.hip) > 1e-12 || dist(point(2), leg.hip) > 1e-12 ||
      dist(point(5), leg.ankle) > 1e-12 || std::abs(knee[0] - leg.hip[0]) > 1e-12 ||
      std::abs(leg.ankle[0] - leg.hip[0]) > 1e-12)
    throw ModelError(m.joints[static_cast<size_t>(leg.joints[0])].loc,
                     "leg: the hip axes must meet at one point, the ankle axes at another, knee "
                     "and ankle straight below the hip at the reference pose");
  leg.thigh = dist(leg.hip, knee);
  leg.calf = dist(knee, leg.ankle);
  leg.waist = m.joints[static_cast<size_t>(leg.joints[0])].first;
  leg.foot = m.joints[static_cast<size_t>(leg.joints[5])].second;
  leg.file = m.common.file;
  return leg;
}

std::array<double, 6> leg_inverse_kinematics(const LegGeometry& leg, const Pose& waist,
                                             const Pose& foot) {
  // Everything in the waist's reference frame: the foot's displacement relative to the waist.
  const Pose G = geometry::inverse(waist) * foot;
  const M3& R = G.R;
  const V3 ankle = geometry::apply(G, leg.ankle);
  const V3 r = geometry::transpose(R) * (leg.hip - ankle);
  const double A = leg.thigh, B = leg.calf, C = std::sqrt(geometry::dot(r, r));
  const double c = (C * C - A * A - B * B) / (2 * A * B);
  if (!(c >= -1 - 1e-12 && c <= 1 + 1e-12))
    throw ModelError({"", 0, 0},
                     "leg: the ankle is out of reach (hip to ankle " + std::to_string(C) + " m)");
  const double knee = std::acos(std::clamp(c, -1.0, 1.0));
  const double alpha = std::asin(std::clamp(A * std::sin(M_PI - knee) / C, -1.0, 1.0));
  const double roll_a = std::atan2(r[1], r[2]);
  const double pitch_a =
      -std::atan2(r[0], (r[2] >= 0 ? 1 : -1) * std::sqrt(r[1] * r[1] + r[2] * r[2])) - alpha;
  const M3 Rh = R * geometry::transpose(geometry::rodrigues(V3{1, 0, 0}, roll_a)) *
                geometry::transpose(geometry::rodrigues(V3{0, 1, 0}, knee + pitch_a));
  const double yaw = std::atan2(-Rh(0, 1), Rh(1, 1));
  const double cz = std::cos(yaw), sz = std::sin(yaw);
  const double roll = std::atan2(Rh(2, 1), -Rh(0, 1) * sz + Rh(1, 1) * cz);
  const double pitch = std::atan2(-Rh(2, 0), Rh(2, 2));
  return {yaw, roll, pitch, knee, pitch_a, roll_a};
}

}  // namespace mechgen::spatial
