// Closed-form inverse kinematics of pose-driven limbs (spatial_limb_ik.hpp).
#include "spatial_limb_ik.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "branch_sign.hpp"
#include "spatial_limb_circuit.hpp"

namespace mechgen::gen {

using GiNaC::ex;
using geometry::operator+;
using geometry::operator-;
using geometry::operator*;

namespace {

using V = geometry::Vec3<ex>;
using Pose = geometry::Pose<ex>;

constexpr double kTwoPi = 2 * 3.14159265358979323846;

bool vanishes(const ex& e) {
  return e.expand().is_zero();
}

// A limb joint's screw seen along the limb: rotation by theta = direction * q about the axis.
struct LimbAxis {
  V w, r;         // direction, a point
  ex direction;   // +1 or -1
  size_t column;  // graph column
};

// Axis points are named parameter expressions: the layout is recognised at the default
// parameters (a --set that breaks it leaves the circuit open, which the closure check reports
// as unreachable).
bool small(const CircuitSolverContext& c, const ex& e) {
  return std::abs(c.at_assembly(e)) < 1e-9;
}
bool meets(const CircuitSolverContext& c, const LimbAxis& a, const LimbAxis& b) {
  const V n = geometry::cross(a.w, b.w);
  return !(small(c, n[0]) && small(c, n[1]) && small(c, n[2])) &&
         small(c, geometry::dot(b.r - a.r, n));
}
// The point where two meeting axes cross.
V crossing(const LimbAxis& a, const LimbAxis& b) {
  const V n = geometry::cross(a.w, b.w);
  const ex t = geometry::dot(geometry::cross(b.r - a.r, b.w), n) / geometry::dot(n, n);
  return a.r + t * a.w;
}
bool passes_through(const CircuitSolverContext& c, const LimbAxis& a, const V& x) {
  const V d = geometry::cross(x - a.r, a.w);
  return small(c, d[0]) && small(c, d[1]) && small(c, d[2]);
}

}  // namespace

std::optional<CircuitClosedForm> planar_limb_ik(const CircuitSolverContext& c, int circuit) {
  const std::optional<LimbCircuit> found = limb_circuit(c, circuit);
  if (!found || found->limb.size() != 3) return std::nullopt;
  const LimbCircuit& lc = *found;
  const SpatialGraph& g = c.graph;
  const auto column = [&](const LimbStep& s) {
    return static_cast<size_t>(g.joint_column[static_cast<size_t>(s.joint)]);
  };
  const V n = c.columns[column(lc.limb[0])].axis.s;
  std::vector<ex> sign;  // theta_i = sign_i q_i about n
  for (const LimbStep& s : lc.limb) {
    const V& si = c.columns[column(s)].axis.s;
    if (!vanishes(geometry::cross(si, n)[0]) || !vanishes(geometry::cross(si, n)[1]) ||
        !vanishes(geometry::cross(si, n)[2]))
      return std::nullopt;
    sign.push_back((s.direction * geometry::dot(si, n)).expand());
  }
  // The rest stays in the plane: rotations about n, translations normal to n; its free
  // coordinates are the translation along n and two rotations normal to it (all zero).
  ex phi = 0;  // the limb's total rotation about n
  int free_translations = 0, free_rotations = 0;
  for (const LimbStep& s : lc.rest) {
    const SpatialJoint& j = c.model.joints[static_cast<size_t>(s.joint)];
    for (size_t i = 0; i < j.columns.size(); ++i) {
      const size_t col = column(s) + i;
      const CircuitColumn& cc = c.columns[col];
      const bool primary = g.columns[col].primary;
      const ex along = geometry::dot(cc.axis.s, n).expand();
      if (cc.axis.kind == geometry::ScrewKind::helical) return std::nullopt;
      if (cc.axis.kind == geometry::ScrewKind::translation) {
        if (primary ? !along.is_zero() : vanishes(along)) return std::nullopt;
        free_translations += primary ? 0 : 1;
      } else if (primary) {
        if (!vanishes(along * along - 1)) return std::nullopt;
        phi -= s.direction * along * cc.q;
      } else {
        if (!along.is_zero()) return std::nullopt;
        ++free_rotations;
      }
      if (!primary && std::abs(c.assembly_q[col]) > 1e-9) return std::nullopt;
    }
  }
  if (free_translations != 1 || free_rotations != 2) return std::nullopt;
  const std::string name = limb_group_name(c, lc, circuit);
  const std::string prefix = name + "_";
  // The limb's motion equals the inverse of the rest's; the ankle axis point P3 is fixed by the
  // last joint, so E1 E2 P3 = T P3: a two-link problem in the plane normal to n.
  const Pose rest = rest_motion(c, lc, prefix);
  const Pose T = geometry::inverse(rest);
  const V P1 = c.columns[column(lc.limb[0])].axis.s0, P2 = c.columns[column(lc.limb[1])].axis.s0,
          P3 = c.columns[column(lc.limb[2])].axis.s0;
  const auto in_plane = [&n](const V& x) { return x - geometry::dot(x, n) * n; };
  const V a = named_vector(c, prefix + "reach_vector", in_plane(geometry::apply(T, P3) - P1));
  const V l1 = in_plane(P2 - P1), l2 = in_plane(P3 - P2);
  const ex K = c.named(prefix + "link_dot", geometry::dot(l1, l2));
  const ex S = c.named(prefix + "link_cross", geometry::dot(geometry::cross(l1, l2), n));
  const ex rho =
      c.named(prefix + "link_product", GiNaC::sqrt(geometry::dot(l1, l1) * geometry::dot(l2, l2)));
  const ex cos_middle =
      c.named(prefix + "cos",
              (geometry::dot(a, a) - geometry::dot(l1, l1) - geometry::dot(l2, l2)) / (2 * rho));
  const ex reach = c.named(prefix + "reach", 1 - cos_middle * cos_middle);
  // The root nearer the warm start of theta2 at run time: theta2 = +-gamma - psi with
  // psi = atan2(S, K); the + root is the nearer to w exactly where sin(w + psi) > 0, that is
  // K sin w + S cos w > 0. Both angles unwound to their warm starts.
  LimbIk ik{c, prefix, {}, {}};
  const LimbIk::Target t1 = ik.target(column(lc.limb[0]), sign[0]);
  const LimbIk::Target t2 = ik.target(column(lc.limb[1]), sign[1]);
  const ex nearer = K * GiNaC::sin(t2.warm) + S * GiNaC::cos(t2.warm);
  const ex branch = c.named(prefix + "branch", followed_branch(nearer, c.at_assembly(nearer)));
  const ex sin_gamma = c.named(prefix + "sin", branch * GiNaC::sqrt(reach));
  const ex theta2 =
      ik.angle("theta2", GiNaC::atan2(sin_gamma, cos_middle) - GiNaC::atan2(S, K), t2);
  const ex c2 = c.named(prefix + "c2", (cos_middle * K + sin_gamma * S) / rho);
  const ex s2 = c.named(prefix + "s2", (sin_gamma * K - cos_middle * S) / rho);
  const V w = named_vector(c, prefix + "w", l1 + c2 * l2 + s2 * geometry::cross(n, l2));
  const ex theta1 = ik.angle(
      "theta1", GiNaC::atan2(geometry::dot(geometry::cross(w, a), n), geometry::dot(w, a)), t1);
  const ex theta3 =
      ik.angle("theta3", phi - theta1 - theta2, ik.target(column(lc.limb[2]), sign[2]));
  CircuitClosedForm out;
  out.name = name;
  const std::vector<ex> theta{theta1, theta2, theta3};
  std::string joints;
  for (size_t i = 0; i < 3; ++i) {
    out.coordinates.emplace_back(static_cast<int>(column(lc.limb[i])),
                                 (sign[i] * theta[i]).expand());
    joints += (i ? ", " : "") + c.model.joints[static_cast<size_t>(lc.limb[i].joint)].name;
  }
  for (const int col : lc.free) out.coordinates.emplace_back(col, 0);
  out.reach.push_back(reach);
  // At the assembly the run-time choice must give the assembly itself (else Newton closes it).
  for (size_t i = 0; i < 3; ++i)
    if (!(std::abs(std::remainder(
              c.at_assembly(sign[i] * theta[i]) - c.assembly_q[column(lc.limb[i])], kTwoPi)) <
          1e-8))
      return std::nullopt;
  out.plan = "pose-driven planar limb " + joints +
             " (parallel axes) in closed form: law of cosines (the root nearer the warm start), "
             "free virtual coordinates zero";
  return out;
}

namespace {

// The limb's axes (in order from its start) when they are in Pieper's layout, else nullopt.
std::optional<std::vector<LimbAxis>> pieper_layout(const CircuitSolverContext& c,
                                                   const std::vector<LimbStep>& limb) {
  std::vector<LimbAxis> axes;
  for (const LimbStep& s : limb) {
    const auto col = static_cast<size_t>(c.graph.joint_column[static_cast<size_t>(s.joint)]);
    axes.push_back({c.columns[col].axis.s, c.columns[col].axis.s0, ex(s.direction), col});
  }
  if (!meets(c, axes[3], axes[4]) || !meets(c, axes[4], axes[5]) || !meets(c, axes[0], axes[1]))
    return std::nullopt;
  const V W = crossing(axes[3], axes[4]), O = crossing(axes[0], axes[1]);
  if (!passes_through(c, axes[5], W) || passes_through(c, axes[2], O)) return std::nullopt;
  return axes;
}

}  // namespace

std::optional<CircuitClosedForm> six_revolute_limb_ik(const CircuitSolverContext& c, int circuit) {
  const std::optional<LimbCircuit> found = limb_circuit(c, circuit);
  if (!found || found->limb.size() != 6 || !found->free.empty()) return std::nullopt;
  LimbCircuit lc = *found;
  // The limb's motion from its start to its end is the inverse of the rest's; seen from the
  // other end, the rest's motion itself.
  const Pose rest = rest_motion(c, lc, limb_group_name(c, lc, circuit) + "_");
  Pose T = geometry::inverse(rest);
  std::optional<std::vector<LimbAxis>> axes = pieper_layout(c, lc.limb);
  if (!axes) {
    std::vector<LimbStep> reversed(lc.limb.rbegin(), lc.limb.rend());
    for (LimbStep& s : reversed) s.direction = -s.direction;
    axes = pieper_layout(c, reversed);
    if (!axes) return std::nullopt;
    lc.limb = reversed;
    T = rest;
  }
  const std::vector<LimbAxis>& a = *axes;
  LimbIk ik{c, limb_group_name(c, lc, circuit) + "_", {}, {}};
  ik.out.name = limb_group_name(c, lc, circuit);
  std::vector<LimbIk::Target> target;  // the angles theta_i = direction_i q_i
  for (const LimbAxis& x : a) target.push_back(ik.target(x.column, x.direction));
  const V W = named_vector(c, ik.prefix + "wrist_ref", crossing(a[3], a[4]));
  const V O = named_vector(c, ik.prefix + "base_ref", crossing(a[0], a[1]));
  const V Wt = named_vector(c, ik.prefix + "wrist", geometry::apply(T, W));
  // Subproblem 3: the third angle makes |R3 (W - r3) + r3 - O| = |Wt - O|.
  const V u = W - a[2].r, v = O - a[2].r;
  const ex wu = geometry::dot(a[2].w, u), wv = geometry::dot(a[2].w, v);
  const ex uu = c.named(ik.prefix + "arm_u", geometry::dot(u, u) - wu * wu);
  const ex vv = c.named(ik.prefix + "arm_v", geometry::dot(v, v) - wv * wv);
  const V d = Wt - O;
  const ex delta2 = geometry::dot(d, d) - (wu - wv) * (wu - wv);
  const ex cos_phi = c.named(ik.prefix + "cos", (uu + vv - delta2) / (2 * GiNaC::sqrt(uu * vv)));
  const ex reach = c.named(ik.prefix + "reach", 1 - cos_phi * cos_phi);
  ik.out.reach.push_back(reach);
  const ex y0 = geometry::dot(a[2].w, geometry::cross(u, v)), x0 = geometry::dot(u, v) - wu * wv;
  const ex sin_phi = c.named(ik.prefix + "sin", GiNaC::sqrt(reach));
  // theta3 = theta0 -+ phi (theta0 = atan2(y0, x0), phi in [0, pi]): the warm start is on the +
  // root's side where sin(theta0 - theta3) > 0, y0 cos theta3 - x0 sin theta3 > 0.
  const ex& w3 = target[2].warm;
  const ex sign = ik.branch(y0 * GiNaC::cos(w3) - x0 * GiNaC::sin(w3));
  const ex t3 =
      ik.angle("theta3", GiNaC::atan2(y0, x0) - GiNaC::atan2(sign * sin_phi, cos_phi), target[2]);
  const geometry::Mat3<ex> R3 = geometry::rodrigues(a[2].w, t3);
  const V p3 = named_vector(c, ik.prefix + "wrist_3", R3 * u + a[2].r - O);
  const std::vector<ex> t12 = ik.two_axes("theta12", a[0].w, a[1].w, p3, d, {target[0], target[1]});
  // The last three take the rest of the orientation: R4 R5 R6 = (R1 R2 R3)^T T.R.
  const geometry::Mat3<ex> R123 =
      geometry::rodrigues(a[0].w, t12[0]) * geometry::rodrigues(a[1].w, t12[1]) * R3;
  geometry::Mat3<ex> Rr = geometry::transpose(R123) * T.R;
  for (size_t k = 0; k < 9; ++k)
    Rr.m[k] = c.named(ik.prefix + "R_" + std::to_string(k / 3) + std::to_string(k % 3), Rr.m[k]);
  const std::vector<ex> t45 =
      ik.two_axes("theta45", a[3].w, a[4].w, a[5].w, Rr * a[5].w, {target[3], target[4]});
  const geometry::Mat3<ex> R45 =
      geometry::rodrigues(a[3].w, t45[0]) * geometry::rodrigues(a[4].w, t45[1]);
  const ex t6 =
      ik.angle("theta6", rotation_taking(a[5].w, a[4].w, geometry::transpose(R45) * (Rr * a[4].w)),
               target[5]);
  const std::vector<ex> theta{t12[0], t12[1], t3, t45[0], t45[1], t6};
  std::string joints;
  for (size_t i = 0; i < 6; ++i) {
    ik.out.coordinates.emplace_back(static_cast<int>(a[i].column),
                                    (a[i].direction * theta[i]).expand());
    joints += (i ? ", " : "") + c.model.joints[static_cast<size_t>(lc.limb[i].joint)].name;
  }
  ik.out.plan = "pose-driven 6R limb " + joints +
                " in closed form (Pieper: the first two axes and the last three meet; Paden-Kahan "
                "subproblems 3, 2, 2, 1; each root the one nearer the warm start: " +
                ik.branch_signs() + " at the assembly)";
  return ik.out;
}

}  // namespace mechgen::gen