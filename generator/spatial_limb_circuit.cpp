// What the pose-driven limb solvers share (spatial_limb_circuit.hpp).
#include "spatial_limb_circuit.hpp"

#include <algorithm>
#include <cmath>

#include "branch_sign.hpp"

namespace mechgen::gen {

using GiNaC::ex;
using geometry::operator+;
using geometry::operator-;
using geometry::operator*;

namespace {

using V = geometry::Vec3<ex>;
using Pose = geometry::Pose<ex>;

}  // namespace

std::optional<LimbCircuit> limb_circuit(const CircuitSolverContext& c, int circuit) {
  const SpatialModel& m = c.model;
  const SpatialGraph& g = c.graph;
  const std::vector<LimbStep> steps = circuit_loop(m, g, circuit);
  const size_t n = steps.size();
  enum Kind { limb, fixed, other };
  std::vector<Kind> kind(n, other);
  for (size_t k = 0; k < n; ++k) {
    const SpatialJoint& j = m.joints[static_cast<size_t>(steps[k].joint)];
    const int c0 = g.joint_column[static_cast<size_t>(steps[k].joint)];
    if (j.columns.empty()) kind[k] = fixed;
    if (!j.is_virtual && !j.columns.empty() && !g.columns[static_cast<size_t>(c0)].primary) {
      if (j.type != SpatialJointType::revolute) return std::nullopt;
      kind[k] = limb;
    }
  }
  // The limb starts at a limb joint whose previous non-fixed step is not a limb joint.
  const auto previous = [&](size_t k) {
    for (size_t i = 1; i < n; ++i)
      if (kind[(k + n - i) % n] != fixed) return kind[(k + n - i) % n];
    return fixed;
  };
  size_t start = n;
  for (size_t k = 0; k < n; ++k)
    if (kind[k] == limb && previous(k) != limb) {
      if (start != n) return std::nullopt;  // two separate runs of real joints
      start = k;
    }
  if (start == n) return std::nullopt;
  size_t end = start;  // one past the limb's last joint
  for (size_t k = start; k < start + n && kind[k % n] != other; ++k)
    if (kind[k % n] == limb) end = k + 1;
  LimbCircuit out;
  for (size_t k = start; k < end; ++k)
    if (kind[k % n] == limb) out.limb.push_back(steps[k % n]);
  for (size_t k = end; k < start + n; ++k) {
    const LimbStep& s = steps[k % n];
    if (kind[k % n] == limb) return std::nullopt;
    out.rest.push_back(s);
    const SpatialJoint& j = m.joints[static_cast<size_t>(s.joint)];
    if (j.is_virtual) {
      if (out.pose_driver >= 0 && out.pose_driver != j.pose_driver) {
        // A second pose driver in the rest must be fully prescribed (checked below).
      } else {
        out.pose_driver = j.pose_driver;
      }
    }
    const auto c0 = static_cast<size_t>(g.joint_column[static_cast<size_t>(s.joint)]);
    for (size_t i = 0; i < j.columns.size(); ++i)
      if (!g.columns[c0 + i].primary) out.free.push_back(static_cast<int>(c0 + i));
  }
  for (const int col : out.free)
    if (g.columns[static_cast<size_t>(col)].pose_driver < 0) return std::nullopt;
  if (!out.free.empty()) out.pose_driver = g.columns[static_cast<size_t>(out.free[0])].pose_driver;
  for (const int col : out.free)
    if (g.columns[static_cast<size_t>(col)].pose_driver != out.pose_driver) return std::nullopt;
  return out;
}

// Named joint by joint (`<prefix>rest<k>_R_ij`, `_p_x`): expanded whole, the product of a
// virtual chain's six displacements and the body path's grows to thousands of terms per entry
// (bioloid's arms: 22k of the kernel's 28k operations, most of the generation time).
Pose rest_motion(const CircuitSolverContext& c, const LimbCircuit& lc, const std::string& prefix) {
  Pose M;
  int step = 0;
  for (const LimbStep& s : lc.rest) {
    const SpatialJoint& j = c.model.joints[static_cast<size_t>(s.joint)];
    const auto c0 = static_cast<size_t>(c.graph.joint_column[static_cast<size_t>(s.joint)]);
    Pose E;
    for (size_t i = 0; i < j.columns.size(); ++i)
      if (c.graph.columns[c0 + i].primary) E = E * c.columns[c0 + i].displacement;
    M = M * (s.direction > 0 ? E : geometry::inverse(E));
    const std::string name = prefix + "rest" + std::to_string(step++);
    for (size_t k = 0; k < 9; ++k)
      M.R.m[k] = c.named(name + "_R_" + std::to_string(k / 3) + std::to_string(k % 3), M.R.m[k]);
    for (size_t k = 0; k < 3; ++k) M.p[k] = c.named(name + "_p_" + "xyz"[k], M.p[k]);
  }
  return {M.R, M.p};
}

std::string limb_group_name(const CircuitSolverContext& c, const LimbCircuit& lc, int circuit) {
  return lc.pose_driver >= 0
             ? "ik_" + c.model.pose_drivers[static_cast<size_t>(lc.pose_driver)].name
             : "ik_circuit" + std::to_string(circuit);
}

V named_vector(const CircuitSolverContext& c, const std::string& name, const V& v) {
  return {c.named(name + "_x", v[0]), c.named(name + "_y", v[1]), c.named(name + "_z", v[2])};
}

ex rotation_taking(const V& w, const V& x, const V& y) {
  return GiNaC::atan2(geometry::dot(w, geometry::cross(x, y)),
                      geometry::dot(x, y) - geometry::dot(w, x) * geometry::dot(w, y));
}

LimbIk::Target LimbIk::target(size_t column, const ex& direction) const {
  return {direction * c.warm_start(static_cast<int>(column)),
          c.at_assembly(direction) * c.assembly_q[column]};
}
ex LimbIk::branch(const ex& indicator) {
  const ex sign = c.named(prefix + "branch" + std::to_string(branches.size() + 1),
                          followed_branch(indicator, c.at_assembly(indicator)));
  branches.push_back(c.at_assembly(sign) > 0 ? 1 : -1);
  return sign;
}
ex LimbIk::angle(const std::string& name, const ex& value, const Target& target) const {
  const ex& w = target.warm;
  return c.named(prefix + name, w + GiNaC::atan2(GiNaC::sin(value - w), GiNaC::cos(value - w)));
}
std::vector<ex> LimbIk::two_axes(const std::string& name, const V& w1, const V& w2, const V& u,
                                 const V& v, const std::vector<Target>& targets) {
  const ex k = geometry::dot(w1, w2);
  const ex den = c.named(prefix + name + "_den", k * k - 1);
  const ex alpha =
      c.named(prefix + name + "_alpha", (k * geometry::dot(w2, u) - geometry::dot(w1, v)) / den);
  const ex beta =
      c.named(prefix + name + "_beta", (k * geometry::dot(w1, v) - geometry::dot(w2, u)) / den);
  const V n = geometry::cross(w1, w2);
  const ex gamma2 = c.named(prefix + name + "_reach", (geometry::dot(u, u) - alpha * alpha -
                                                       beta * beta - 2 * alpha * beta * k) /
                                                          geometry::dot(n, n));
  out.reach.push_back(gamma2);
  const ex root = c.named(prefix + name + "_root", GiNaC::sqrt(gamma2));
  // The roots differ in z's n component (+-root): the warm start's z = R2(a2) u is on one side.
  const ex sign = branch(geometry::dot(n, geometry::rodrigues(w2, targets[1].warm) * u));
  const V z = alpha * w1 + beta * w2 + (sign * root) * n;
  return {angle(name + "_a1", rotation_taking(w1, z, v), targets[0]),
          angle(name + "_a2", rotation_taking(w2, u, z), targets[1])};
}

std::string LimbIk::branch_signs() const {
  std::string signs;
  for (const int b : branches) signs += b > 0 ? "+" : "-";
  return signs;
}

}  // namespace mechgen::gen
