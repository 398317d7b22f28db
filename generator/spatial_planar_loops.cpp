// RRR dyads of planar loops inside spatial models (spatial_planar_loops.hpp).
#include "spatial_planar_loops.hpp"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "branch_sign.hpp"
#include "spatial_circuit_loop.hpp"

namespace mechgen::gen {

using GiNaC::ex;
using geometry::operator+;
using geometry::operator-;
using geometry::operator*;

namespace {

using V = geometry::Vec3<ex>;
using Pose = geometry::Pose<ex>;

// Recognition tolerance at the default parameters (axes are unit vectors there).
constexpr double kTolerance = 1e-9;

// The loop read from its first unknown revolute U1: U1, the known segment B1, U2, B2, U3, B3;
// the closure is R1 B1 R2 B2 R3 B3 = I, where Rk turns by theta_k = sigma_k q_k about the axis
// through pivot p_k parallel to n.
struct Dyad {
  V n;
  int column[3] = {-1, -1, -1};
  int joint[3] = {-1, -1, -1};
  int sigma[3] = {1, 1, 1};
  std::vector<CircuitStep> segment[3];  // B1, B2, B3
};

bool small(const CircuitSolverContext& c, const V& v) {
  return std::abs(c.at_assembly(v[0])) < kTolerance && std::abs(c.at_assembly(v[1])) < kTolerance &&
         std::abs(c.at_assembly(v[2])) < kTolerance;
}

// The circuit as a dyad: three unknown revolutes, every column parallel to (rotations) or
// normal to (translations) their axis. Among the loop's three readings, the one whose B1 has no
// joint coordinates: the pivots p1, p2 then stay a constant distance apart (the circle
// intersection's base never shrinks to a point).
std::optional<Dyad> find_dyad(const CircuitSolverContext& c, int circuit) {
  const std::vector<CircuitStep> steps = circuit_loop(c.model, c.graph, circuit);
  std::vector<size_t> unknown;  // steps
  for (size_t k = 0; k < steps.size(); ++k) {
    const SpatialJoint& j = c.model.joints[static_cast<size_t>(steps[k].joint)];
    const auto c0 = static_cast<size_t>(c.graph.joint_column[static_cast<size_t>(steps[k].joint)]);
    for (size_t i = 0; i < j.columns.size(); ++i)
      if (!c.known[c0 + i]) {
        if (j.type != SpatialJointType::revolute) return std::nullopt;
        unknown.push_back(k);
      }
  }
  if (unknown.size() != 3) return std::nullopt;
  Dyad d;
  d.n = c.columns[static_cast<size_t>(
                      c.graph.joint_column[static_cast<size_t>(steps[unknown[0]].joint)])]
            .axis.s;
  for (const CircuitStep& s : steps) {
    const SpatialJoint& j = c.model.joints[static_cast<size_t>(s.joint)];
    const auto c0 = static_cast<size_t>(c.graph.joint_column[static_cast<size_t>(s.joint)]);
    for (size_t i = 0; i < j.columns.size(); ++i) {
      const geometry::ScrewAxis<ex>& a = c.columns[c0 + i].axis;
      if (a.kind == geometry::ScrewKind::helical) return std::nullopt;
      const bool planar = a.kind == geometry::ScrewKind::rotation
                              ? small(c, geometry::cross(a.s, d.n))
                              : std::abs(c.at_assembly(geometry::dot(a.s, d.n))) < kTolerance;
      if (!planar) return std::nullopt;
    }
  }
  const auto columns_between = [&](size_t from, size_t to) {  // steps strictly between, cyclic
    size_t count = 0;
    for (size_t k = (from + 1) % steps.size(); k != to; k = (k + 1) % steps.size())
      count += c.model.joints[static_cast<size_t>(steps[k].joint)].columns.size();
    return count;
  };
  size_t first = 0;
  for (size_t r = 0; r < 3; ++r)
    if (columns_between(unknown[r], unknown[(r + 1) % 3]) == 0) {
      first = r;
      break;
    }
  for (size_t i = 0; i < 3; ++i) {
    const size_t at = unknown[(first + i) % 3], next = unknown[(first + i + 1) % 3];
    const CircuitStep& s = steps[at];
    d.joint[i] = s.joint;
    d.column[i] = c.graph.joint_column[static_cast<size_t>(s.joint)];
    d.sigma[i] =
        s.direction *
        (c.at_assembly(geometry::dot(c.columns[static_cast<size_t>(d.column[i])].axis.s, d.n)) > 0
             ? 1
             : -1);
    for (size_t k = (at + 1) % steps.size(); k != next; k = (k + 1) % steps.size())
      d.segment[i].push_back(steps[k]);
  }
  return d;
}

// The motion of a known segment: its joints' displacements in loop order, inverted where the
// loop runs against the joint.
Pose segment_motion(const CircuitSolverContext& c, const std::vector<CircuitStep>& segment) {
  Pose M;
  for (const CircuitStep& s : segment) {
    const SpatialJoint& j = c.model.joints[static_cast<size_t>(s.joint)];
    const auto c0 = static_cast<size_t>(c.graph.joint_column[static_cast<size_t>(s.joint)]);
    Pose E;
    for (size_t i = 0; i < j.columns.size(); ++i) E = E * c.columns[c0 + i].displacement;
    M = M * (s.direction > 0 ? E : geometry::inverse(E));
  }
  return M;
}

// The dyad's expressions, built once unnamed (to choose the branch at the assembly) and once
// named (the kernel's definitions).
struct DyadSolution {
  ex disc;
  ex cos[3], sin[3];  // of theta_k
};

class DyadSolver {
 public:
  DyadSolver(const CircuitSolverContext& c, const Dyad& d, std::string prefix)
      : c_(c), d_(d), prefix_(std::move(prefix)) {}

  // Side lengths from the known segments; with `naming`, each intermediate a definition.
  // tau: which of the circles' two intersections (+1 or -1), or with `theta1_warm` (the warm
  // start of theta1) the one nearer it, chosen at run time.
  DyadSolution solve(int tau, bool naming, const ex* theta1_warm = nullptr) {
    naming_ = naming;
    const V& n = d_.n;
    const auto in_plane = [&n](const V& x) { return x - geometry::dot(x, n) * n; };
    const Pose B1 = segment_motion(c_, d_.segment[0]), B2 = segment_motion(c_, d_.segment[1]),
               B3 = segment_motion(c_, d_.segment[2]);
    const V& p1 = pivot(0);
    const V& p2 = pivot(1);
    const V& p3 = pivot(2);
    // R3 fixes p3: R1 B1 R2 (B2 p3) = B3^-1 p3 = x. With y = R1^-1 x: |y - p1| = |x - p1| and
    // |y - B1 p2| = |B2 p3 - p2| (B1 and R2 rigid): y on two circles in the plane.
    const V r = name("r", in_plane(geometry::apply(geometry::inverse(B3), p3) - p1));
    const V d = name("d", in_plane(geometry::apply(B1, p2) - p1));
    const V u = name("u", in_plane(geometry::apply(B2, p3) - p2));
    const ex rr = name("rr", geometry::dot(r, r)), dd = name("dd", geometry::dot(d, d));
    const ex uu = name("uu", geometry::dot(u, u));
    const ex e = name("e", (rr + dd - uu) / 2);
    DyadSolution s;
    s.disc = name("reach", rr * dd - e * e);
    // max(disc, 0) without a branch: where the circles miss (reported through reach) a root of
    // zero, never NaN.
    const ex root = name("root", GiNaC::sqrt((s.disc + GiNaC::abs(s.disc)) / 2));
    const V nd = geometry::cross(n, d);
    // The two intersections differ in z's n x d component (+-root): the nearer to the warm
    // start's z = Rot(n, -theta1) r has the sign of that z's n x d component.
    ex branch = tau;
    if (theta1_warm) {
      const ex nearer = nearer_plus(n, d, r, *theta1_warm);
      branch = name("branch", followed_branch(nearer, c_.at_assembly(nearer)));
    }
    const V z = name("z", (1 / dd) * (e * d + (branch * root) * nd));  // y - p1, in the plane
    // theta1 takes z to r; theta2 takes u to B1^-1 (y - B1 p2) = R_B1^T (z - d).
    s.cos[0] = name("cos1", geometry::dot(z, r) / rr);
    s.sin[0] = name("sin1", geometry::dot(n, geometry::cross(z, r)) / rr);
    const V v = name("v", geometry::transpose(B1.R) * (z - d));
    s.cos[1] = name("cos2", geometry::dot(u, v) / uu);
    s.sin[1] = name("sin2", geometry::dot(n, geometry::cross(u, v)) / uu);
    // R3 B3 R1 B1 R2 B2 = I on g = B2^-1 p2: R3 takes B3 R1 (B1 p2) - p3 to g - p3 (both of
    // length |u|), with R1 (B1 p2) = p1 + cos1 d + sin1 n x d in the plane.
    const V w = name("w", in_plane(geometry::apply(B3, p1 + s.cos[0] * d + s.sin[0] * nd) - p3));
    const V g = name("g", in_plane(geometry::apply(geometry::inverse(B2), p2) - p3));
    s.cos[2] = name("cos3", geometry::dot(w, g) / uu);
    s.sin[2] = name("sin3", geometry::dot(n, geometry::cross(w, g)) / uu);
    return s;
  }

  // (n x d) . Rot(n, -theta) r for d and r in the plane normal to n: positive where the + root is
  // the nearer to theta1 = theta.
  static ex nearer_plus(const V& n, const V& d, const V& r, const ex& theta) {
    return GiNaC::cos(theta) * geometry::dot(n, geometry::cross(d, r)) -
           GiNaC::sin(theta) * geometry::dot(d, r);
  }
  // Which root the rule takes at the assembly (theta1 there).
  int assembly_branch(double theta1) {
    naming_ = false;
    const V& n = d_.n;
    const auto in_plane = [&n](const V& x) { return x - geometry::dot(x, n) * n; };
    const V r = in_plane(
        geometry::apply(geometry::inverse(segment_motion(c_, d_.segment[2])), pivot(2)) - pivot(0));
    const V d = in_plane(geometry::apply(segment_motion(c_, d_.segment[0]), pivot(1)) - pivot(0));
    return c_.at_assembly(nearer_plus(n, d, r, theta1)) >= 0 ? 1 : -1;
  }

 private:
  const V& pivot(int k) const { return c_.columns[static_cast<size_t>(d_.column[k])].axis.s0; }
  ex name(const std::string& n, const ex& e) const {
    return naming_ ? c_.named(prefix_ + n, e) : e;
  }
  V name(const std::string& n, const V& v) const {
    return {name(n + "_x", v[0]), name(n + "_y", v[1]), name(n + "_z", v[2])};
  }

  const CircuitSolverContext& c_;
  const Dyad& d_;
  std::string prefix_;
  bool naming_ = false;
};

// Whether the solution's angles at the assembly are the numeric solver's (mod 2 pi).
bool matches_assembly(const CircuitSolverContext& c, const Dyad& d, const DyadSolution& s) {
  for (int k = 0; k < 3; ++k) {
    const double theta = std::atan2(c.at_assembly(s.sin[k]), c.at_assembly(s.cos[k]));
    const double q = d.sigma[k] * theta;
    if (!(std::abs(std::remainder(q - c.assembly_q[static_cast<size_t>(d.column[k])], 2 * M_PI)) <
          1e-8))
      return false;
  }
  return true;
}

}  // namespace

std::optional<CircuitClosedForm> planar_loop_closed_form(const CircuitSolverContext& c,
                                                         int circuit) {
  const std::optional<Dyad> found = find_dyad(c, circuit);
  if (!found) return std::nullopt;
  const Dyad& d = *found;
  const std::string chord =
      c.model.joints[static_cast<size_t>(c.graph.chords[static_cast<size_t>(circuit)])].name;
  DyadSolver solver(c, d, "pl_" + chord + "_");
  // The branch: the intersection nearer the warm start, at run time; at the assembly it must be
  // the assembly's, away from a dead point where the circles touch (else left to Newton).
  const double theta1 = d.sigma[0] * c.assembly_q[static_cast<size_t>(d.column[0])];
  const DyadSolution at_assembly = solver.solve(solver.assembly_branch(theta1), false);
  if (!(c.at_assembly(at_assembly.disc) > 0) || !matches_assembly(c, d, at_assembly))
    return std::nullopt;
  const ex warm0 = c.warm_start(d.column[0]);
  const ex theta1_warm = d.sigma[0] * warm0;
  const DyadSolution s = solver.solve(0, true, &theta1_warm);
  CircuitClosedForm out;
  out.name = "planar_loop_" + chord;
  out.reach.push_back(s.disc);
  std::string joints;
  for (int k = 0; k < 3; ++k) {
    // q = sigma theta, unwound to the warm start w: w + atan2(sin(q - w), cos(q - w)).
    const auto col = d.column[k];
    const ex cq = s.cos[k], sq = d.sigma[k] * s.sin[k];
    const ex w = k == 0 ? warm0 : c.warm_start(col);
    const ex cw = GiNaC::cos(w), sw = GiNaC::sin(w);
    out.coordinates.emplace_back(
        col, w + GiNaC::atan2((sq * cw - cq * sw).expand(), (cq * cw + sq * sw).expand()));
    out.cos_sin[col] = {cq, c.named("pl_" + chord + "_sin_q" + std::to_string(k + 1), sq)};
    joints += (k ? ", " : "") + c.model.joints[static_cast<size_t>(d.joint[k])].name;
  }
  out.plan = "planar loop " + joints +
             " (parallel revolute axes) in closed form in its plane: circle intersection (the one "
             "nearer the warm start), angles unwound to the warm start";
  return out;
}

}  // namespace mechgen::gen
