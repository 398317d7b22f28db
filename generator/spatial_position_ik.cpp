// Closed-form inverse kinematics of a 3R limb with a position-only target
// (spatial_position_ik.hpp).
#include "spatial_position_ik.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "spatial_limb_circuit.hpp"

namespace mechgen::gen {

using GiNaC::ex;
using geometry::operator+;
using geometry::operator-;
using geometry::operator*;

namespace {

using V = geometry::Vec3<ex>;
using M = geometry::Mat3<ex>;

// The layout is recognised at the default parameters (axes and points are parameter
// expressions); a --set that broke it would leave the circuit open, which the closure check
// reports as unreachable.
bool small(const CircuitSolverContext& c, const V& v) {
  return std::abs(c.at_assembly(v[0])) < 1e-9 && std::abs(c.at_assembly(v[1])) < 1e-9 &&
         std::abs(c.at_assembly(v[2])) < 1e-9;
}

// A rotation of the circuit seen along it: theta = direction * q about (w, r).
struct Axis {
  V w, r;
  int direction = 1;
  size_t column = 0;
};

Axis axis_of(const CircuitSolverContext& c, int joint, int direction, size_t offset = 0) {
  const auto col = static_cast<size_t>(c.graph.joint_column[static_cast<size_t>(joint)]) + offset;
  return {c.columns[col].axis.s, c.columns[col].axis.s0, direction, col};
}

// The pose driver's free rotations: three independent axes through one point, on the steps of
// the rest next to the limb's end (so they turn about the target point before any prescribed
// motion); nothing else free.
std::optional<std::vector<Axis>> free_rotations(const CircuitSolverContext& c,
                                                const LimbCircuit& lc) {
  std::vector<Axis> out;
  bool prescribed_seen = false;
  for (const LimbStep& s : lc.rest) {
    const SpatialJoint& j = c.model.joints[static_cast<size_t>(s.joint)];
    const auto c0 = static_cast<size_t>(c.graph.joint_column[static_cast<size_t>(s.joint)]);
    for (size_t i = 0; i < j.columns.size(); ++i) {
      if (c.graph.columns[c0 + i].primary) {
        prescribed_seen = true;
        continue;
      }
      if (prescribed_seen || j.columns.size() != 1 ||
          c.columns[c0 + i].axis.kind != geometry::ScrewKind::rotation)
        return std::nullopt;
      out.push_back(axis_of(c, s.joint, s.direction));
    }
  }
  if (out.size() != 3) return std::nullopt;
  for (const Axis& a : out)
    if (!small(c, geometry::cross(a.r - out[0].r, a.w))) return std::nullopt;
  const ex volume = geometry::dot(out[0].w, geometry::cross(out[1].w, out[2].w));
  if (!(std::abs(c.at_assembly(volume)) > 1e-6)) return std::nullopt;
  return out;
}

// The same circuit walked the other way round.
LimbCircuit reversed(const LimbCircuit& lc) {
  LimbCircuit out = lc;
  out.limb.assign(lc.limb.rbegin(), lc.limb.rend());
  out.rest.assign(lc.rest.rbegin(), lc.rest.rend());
  for (LimbStep& s : out.limb) s.direction = -s.direction;
  for (LimbStep& s : out.rest) s.direction = -s.direction;
  return out;
}

}  // namespace

std::optional<CircuitClosedForm> position_limb_ik(const CircuitSolverContext& c, int circuit) {
  const std::optional<LimbCircuit> found = limb_circuit(c, circuit);
  if (!found || found->limb.size() != 3 || found->free.size() != 3) return std::nullopt;
  // Walked so that the limb runs towards the target's body (the free rotations next to it).
  LimbCircuit lc = *found;
  std::optional<std::vector<Axis>> free = free_rotations(c, lc);
  if (!free) free = free_rotations(c, lc = reversed(*found));
  if (!free) return std::nullopt;
  std::vector<Axis> a;
  for (const LimbStep& s : lc.limb) a.push_back(axis_of(c, s.joint, s.direction));
  // The last two parallel, the first across them.
  if (!small(c, geometry::cross(a[1].w, a[2].w)) || small(c, geometry::cross(a[0].w, a[1].w)))
    return std::nullopt;
  LimbIk ik{c, limb_group_name(c, lc, circuit) + "_", {}, {}};
  std::vector<LimbIk::Target> target;  // the angles theta_i = direction_i q_i
  for (const Axis& x : a) target.push_back(ik.target(x.column, x.direction));
  std::vector<LimbIk::Target> free_target;
  for (const Axis& x : *free) free_target.push_back(ik.target(x.column, x.direction));

  ik.out.name = limb_group_name(c, lc, circuit);
  const std::string& p = ik.prefix;
  // The limb's motion is the inverse of the rest's; the free rotations fix the target point P
  // (a point of the limb's end body), so the limb takes P to T P.
  const geometry::Pose<ex> T = geometry::inverse(rest_motion(c, lc, ik.prefix));
  const V P = (*free)[0].r;
  const V x = named_vector(c, p + "target", geometry::apply(T, P));

  // Swing: y = E2 E3 P lies in the plane n.y = n.P (n the parallel axes); rotating about the
  // first axis keeps the component along it (axial) and the distance from it (radial), so
  // y - r1 = axial w1 + u with u normal to w1, |u| = radial, n.u = offset: u = mu e + nu m with
  // e = n - k w1, m = w1 x n, k = w1.n.
  const V& w1 = a[0].w;
  const V& n = a[1].w;
  const ex k = geometry::dot(w1, n);
  const ex kk = c.named(p + "swing_sin_sq", 1 - k * k);
  const V v = named_vector(c, p + "swing_arm", x - a[0].r);
  const ex axial = c.named(p + "swing_axial", geometry::dot(w1, v));
  const ex radial2 = c.named(p + "swing_radial_sq", geometry::dot(v, v) - axial * axial);
  const ex offset = c.named(p + "swing_offset", geometry::dot(n, P - a[0].r) - axial * k);
  const ex reach1 = c.named(p + "swing_reach", radial2 * kk - offset * offset);
  ik.out.reach.push_back(reach1);
  const ex root1 = c.named(p + "swing_root", GiNaC::sqrt(reach1));
  const V e = n - k * w1, m = geometry::cross(w1, n);
  // The roots differ in u's m component: the warm start's u = Rot(w1, -theta1) v is on one side.
  const ex tau1 = ik.branch(geometry::dot(m, geometry::rodrigues(w1, -target[0].warm) * v));
  const V u = named_vector(c, p + "swing_from", (offset / kk) * e + (tau1 * root1 / kk) * m);
  const ex theta1 = ik.angle("theta1", rotation_taking(w1, u, v), target[0]);

  // The planar 2R about n: |L + Rot(phi) P3| = |d| in the plane normal to n, A cos phi +
  // B sin phi = C, then the first angle takes the elbow's point to d.
  const auto in_plane = [&n](const V& y) { return y - geometry::dot(y, n) * n; };
  const ex sigma3 = geometry::dot(a[2].w, n);  // +-1: the third axis along or against n
  const V P3 = named_vector(c, p + "link2", in_plane(P - a[2].r));
  const V L = named_vector(c, p + "link1", in_plane(a[2].r - a[1].r));
  const V nP3 = named_vector(c, p + "link2_normal", geometry::cross(n, P3));
  const V d = named_vector(c, p + "reach_vector", in_plane(a[0].r + axial * w1 + u - a[1].r));
  const ex A = c.named(p + "A", geometry::dot(L, P3));
  const ex B = c.named(p + "B", geometry::dot(L, nP3));
  const ex C =
      c.named(p + "C", (geometry::dot(d, d) - geometry::dot(L, L) - geometry::dot(P3, P3)) / 2);
  const ex r2 = c.named(p + "r2", A * A + B * B);
  const ex reach2 = c.named(p + "reach", r2 - C * C);
  ik.out.reach.push_back(reach2);
  const ex root2 = c.named(p + "root", GiNaC::sqrt(reach2));
  // phi = psi +- alpha (psi = atan2(B, A)): the warm start's phi = sigma3 theta3 is on the + root's
  // side where sin(phi - psi) > 0, A sin phi - B cos phi > 0.
  const ex phi_warm = sigma3 * target[2].warm;
  const ex tau2 = ik.branch(A * GiNaC::sin(phi_warm) - B * GiNaC::cos(phi_warm));
  const ex cos_phi = c.named(p + "cos", (A * C - tau2 * B * root2) / r2);
  const ex sin_phi = c.named(p + "sin", (B * C + tau2 * A * root2) / r2);
  const V z = named_vector(c, p + "elbow", L + cos_phi * P3 + sin_phi * nP3);
  const ex theta2 = ik.angle("theta2", rotation_taking(n, z, d), target[1]);
  const ex theta3 = ik.angle("theta3", sigma3 * GiNaC::atan2(sin_phi, cos_phi), target[2]);
  const std::vector<ex> theta{theta1, theta2, theta3};

  // The pose's free rotations take the rest of the orientation: F = E_limb^-1 T, so
  // R_F = R_limb^T R_T, about the free axes in the rest's order.
  const M R_limb = geometry::rodrigues(w1, theta1) * geometry::rodrigues(n, theta2) *
                   geometry::rodrigues(a[2].w, theta3);
  M R_free = geometry::transpose(R_limb) * T.R;
  for (size_t i = 0; i < 9; ++i)
    R_free.m[i] =
        c.named(p + "free_R_" + std::to_string(i / 3) + std::to_string(i % 3), R_free.m[i]);
  const std::vector<Axis>& f = *free;
  const std::vector<ex> f12 = ik.two_axes("free12", f[0].w, f[1].w, f[2].w, R_free * f[2].w,
                                          {free_target[0], free_target[1]});
  const M R12 = geometry::rodrigues(f[0].w, f12[0]) * geometry::rodrigues(f[1].w, f12[1]);
  const ex f3 = ik.angle(
      "free3", rotation_taking(f[2].w, f[1].w, geometry::transpose(R12) * (R_free * f[1].w)),
      free_target[2]);
  const std::vector<ex> phi{f12[0], f12[1], f3};

  // Both square roots' branches must give the assembly itself, else leave the circuit to Newton.
  for (size_t i = 0; i < 3; ++i)
    if (std::abs(c.at_assembly(theta[i]) - target[i].assembly) > 1e-6 ||
        std::abs(c.at_assembly(phi[i]) - free_target[i].assembly) > 1e-6)
      return std::nullopt;
  std::string joints;
  for (size_t i = 0; i < 3; ++i) {
    ik.out.coordinates.emplace_back(static_cast<int>(a[i].column), a[i].direction * theta[i]);
    ik.out.coordinates.emplace_back(static_cast<int>(f[i].column), f[i].direction * phi[i]);
    joints += (i ? ", " : "") + c.model.joints[static_cast<size_t>(lc.limb[i].joint)].name;
  }
  ik.out.plan = "pose-driven position target, limb " + joints +
                " in closed form (first axis across the parallel pair: the target's component "
                "along it and distance from it, then the planar 2R by the law of cosines; the "
                "free rotations by Paden-Kahan 2 and 1; each root the one nearer the warm start: " +
                ik.branch_signs() + " at the assembly)";
  return ik.out;
}

}  // namespace mechgen::gen
