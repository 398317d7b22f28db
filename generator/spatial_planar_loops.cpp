// RRR dyads of planar loops inside spatial models (spatial_planar_loops.hpp).
#include "spatial_planar_loops.hpp"

#include <algorithm>
#include <array>
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
      : c_(c), n_(d.n), prefix_(std::move(prefix)) {
    for (int k = 0; k < 3; ++k) {
      segment_[k] = segment_motion(c, d.segment[k]);
      pivot_[k] = c.columns[static_cast<size_t>(d.column[k])].axis.s0;
    }
  }
  // A loop R1 B1 R2 B2 R3 B3 = I given by its segments' motions and its pivots.
  DyadSolver(const CircuitSolverContext& c, const V& n, const Pose (&segment)[3],
             const V (&pivot)[3], std::string prefix)
      : c_(c), n_(n), prefix_(std::move(prefix)) {
    for (int k = 0; k < 3; ++k) {
      segment_[k] = segment[k];
      pivot_[k] = pivot[k];
    }
  }

  // Side lengths from the known segments; with `naming`, each intermediate a definition.
  // tau: which of the circles' two intersections (+1 or -1), or with `theta1_warm` (the warm
  // start of theta1) the one nearer it, chosen at run time.
  DyadSolution solve(int tau, bool naming, const ex* theta1_warm = nullptr) {
    naming_ = naming;
    const V& n = n_;
    const auto in_plane = [&n](const V& x) { return x - geometry::dot(x, n) * n; };
    const Pose &B1 = segment_[0], &B2 = segment_[1], &B3 = segment_[2];
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
    const V& n = n_;
    const auto in_plane = [&n](const V& x) { return x - geometry::dot(x, n) * n; };
    const V r = in_plane(geometry::apply(geometry::inverse(segment_[2]), pivot(2)) - pivot(0));
    const V d = in_plane(geometry::apply(segment_[0], pivot(1)) - pivot(0));
    return c_.at_assembly(nearer_plus(n, d, r, theta1)) >= 0 ? 1 : -1;
  }

 private:
  const V& pivot(int k) const { return pivot_[k]; }
  ex name(const std::string& n, const ex& e) const {
    return naming_ ? c_.named(prefix_ + n, e) : e;
  }
  V name(const std::string& n, const V& v) const {
    return {name(n + "_x", v[0]), name(n + "_y", v[1]), name(n + "_z", v[2])};
  }

  const CircuitSolverContext& c_;
  V n_;
  Pose segment_[3];
  V pivot_[3];
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

namespace {

// The loop at the coordinate level: each column of the circuit's joints in loop order (a joint's
// columns reversed where the loop runs against it: (E1 E2)^-1 = E2^-1 E1^-1).
struct LoopColumn {
  int column = -1;
  int direction = 1;
};

std::vector<LoopColumn> column_loop(const CircuitSolverContext& c, int circuit) {
  std::vector<LoopColumn> out;
  for (const CircuitStep& s : circuit_loop(c.model, c.graph, circuit)) {
    const auto n = static_cast<int>(c.model.joints[static_cast<size_t>(s.joint)].columns.size());
    const int c0 = c.graph.joint_column[static_cast<size_t>(s.joint)];
    for (int i = 0; i < n; ++i)
      out.push_back({s.direction > 0 ? c0 + i : c0 + n - 1 - i, s.direction});
  }
  return out;
}

Pose column_motion(const CircuitSolverContext& c, const LoopColumn& l) {
  const Pose& E = c.columns[static_cast<size_t>(l.column)].displacement;
  return l.direction > 0 ? E : geometry::inverse(E);
}

std::string column_name(const CircuitSolverContext& c, int column) {
  const SpatialColumn& sc = c.graph.columns[static_cast<size_t>(column)];
  const std::string& joint = c.model.joints[static_cast<size_t>(sc.joint)].name;
  return sc.index == 0 ? joint : joint + "_" + std::to_string(sc.index + 1);
}

// q = w + atan2(sin(q - w), cos(q - w)): the angle of cosine cq and sine sq nearest the warm
// start w (continuous along a sweep).
ex unwound(const ex& cq, const ex& sq, const ex& w) {
  const ex cw = GiNaC::cos(w), sw = GiNaC::sin(w);
  return w + GiNaC::atan2((sq * cw - cq * sw).expand(), (cq * cw + sq * sw).expand());
}

// A planar loop read at the coordinate level: positions (indices in `loop`) of the unknown
// revolutes parallel to n grouped by pivot (loop order, first group's first position the
// reading's start), the other unknown positions held at 0.
struct HeldLoop {
  V n;
  std::vector<LoopColumn> loop;
  std::vector<bool> held;
  std::vector<int> sigma;                   // per position: theta = sigma q about n
  std::vector<std::vector<size_t>> pivots;  // unknown in-plane revolutes, by pivot
};

bool parallel(const CircuitSolverContext& c, const V& a, const V& n) {
  return small(c, geometry::cross(a, n));
}

// Whether the held columns' screws, at the reference pose, move out of the plane independently:
// their out-of-plane parts (w x n, v . n) have a Gram determinant away from 0.
bool held_independent(const CircuitSolverContext& c, const HeldLoop& h) {
  std::vector<std::array<double, 4>> a;
  for (size_t k = 0; k < h.loop.size(); ++k) {
    if (!h.held[k]) continue;
    const geometry::Twist<ex> t =
        geometry::unit_twist(c.columns[static_cast<size_t>(h.loop[k].column)].axis);
    const V wn = geometry::cross(t.w, h.n);
    a.push_back({c.at_assembly(wn[0]), c.at_assembly(wn[1]), c.at_assembly(wn[2]),
                 c.at_assembly(geometry::dot(t.v, h.n))});
  }
  if (a.size() > 3) return false;
  // Gram-Schmidt: each residual against the ones before must keep a fair part of its norm
  // (lengths are scaled by the largest lever arm, so the test is on directions).
  std::vector<std::array<double, 4>> basis;
  for (std::array<double, 4> v : a) {
    double norm0 = 0;
    for (const double x : v) norm0 += x * x;
    for (const auto& b : basis) {
      double p = 0;
      for (size_t i = 0; i < 4; ++i) p += v[i] * b[i];
      for (size_t i = 0; i < 4; ++i) v[i] -= p * b[i];
    }
    double norm = 0;
    for (const double x : v) norm += x * x;
    if (!(norm0 > 0) || !(norm > 1e-6 * norm0)) return false;
    for (double& x : v) x /= std::sqrt(norm);
    basis.push_back(v);
  }
  return true;
}

std::optional<HeldLoop> find_held_loop(const CircuitSolverContext& c, int circuit) {
  HeldLoop h;
  h.loop = column_loop(c, circuit);
  const size_t size = h.loop.size();
  const auto axis = [&](size_t k) -> const geometry::ScrewAxis<ex>& {
    return c.columns[static_cast<size_t>(h.loop[k].column)].axis;
  };
  const auto known = [&](size_t k) { return c.known[static_cast<size_t>(h.loop[k].column)]; };
  const auto planar = [&](size_t k, const V& n) {
    const geometry::ScrewAxis<ex>& a = axis(k);
    return a.kind == geometry::ScrewKind::rotation
               ? parallel(c, a.s, n)
               : std::abs(c.at_assembly(geometry::dot(a.s, n))) < kTolerance;
  };
  // n: the rotation axis most columns are planar to (the first such on ties).
  size_t best = 0;
  for (size_t k = 0; k < size; ++k) {
    if (axis(k).kind == geometry::ScrewKind::helical) return std::nullopt;
    if (axis(k).kind != geometry::ScrewKind::rotation) continue;
    size_t count = 0;
    for (size_t i = 0; i < size; ++i) count += planar(i, axis(k).s) ? 1 : 0;
    if (count > best) {
      best = count;
      h.n = axis(k).s;
    }
  }
  if (best == 0) return std::nullopt;
  h.held.assign(size, false);
  h.sigma.assign(size, 1);
  std::vector<size_t> unknown;
  for (size_t k = 0; k < size; ++k) {
    if (!planar(k, h.n)) {
      // A known out-of-plane motion (a driver) tilts the plane: not this loop.
      if (known(k) || !(std::abs(c.assembly_q[static_cast<size_t>(h.loop[k].column)]) < kTolerance))
        return std::nullopt;
      h.held[k] = true;
      continue;
    }
    if (known(k)) continue;
    if (axis(k).kind != geometry::ScrewKind::rotation) return std::nullopt;
    h.sigma[k] = h.loop[k].direction * (c.at_assembly(geometry::dot(axis(k).s, h.n)) > 0 ? 1 : -1);
    unknown.push_back(k);
  }
  if (unknown.size() < 3 || !held_independent(c, h)) return std::nullopt;
  // Two unknown revolutes share a pivot when only held columns lie between them and their axes
  // meet the plane at one point.
  const auto shared = [&](size_t a, size_t b) {
    for (size_t k = (a + 1) % size; k != b; k = (k + 1) % size)
      if (!h.held[k]) return false;
    const V d = axis(b).s0 - axis(a).s0;
    return small(c, d - geometry::dot(d, h.n) * h.n);
  };
  size_t start = unknown.size();
  for (size_t i = 0; i < unknown.size() && start == unknown.size(); ++i)
    if (!shared(unknown[(i + unknown.size() - 1) % unknown.size()], unknown[i])) start = i;
  if (start == unknown.size()) return std::nullopt;
  for (size_t i = 0; i < unknown.size(); ++i) {
    const size_t k = unknown[(start + i) % unknown.size()];
    if (i > 0 && shared(h.pivots.back().back(), k))
      h.pivots.back().push_back(k);
    else
      h.pivots.push_back({k});
  }
  if (h.pivots.size() != 3) return std::nullopt;
  // The reading: a pivot with one revolute first (its angle takes the branch), preferably with
  // nothing moving between it and the next (the circle intersection's base then never shrinks).
  const auto moving_between = [&](size_t a, size_t b) {
    for (size_t k = (a + 1) % size; k != b; k = (k + 1) % size)
      if (!h.held[k]) return true;
    return false;
  };
  int first = -1;
  for (int r = 0; r < 3; ++r) {
    const auto& p = h.pivots[static_cast<size_t>(r)];
    if (p.size() != 1) continue;
    if (first < 0) first = r;
    if (!moving_between(p.back(), h.pivots[static_cast<size_t>((r + 1) % 3)].front())) {
      first = r;
      break;
    }
  }
  if (first < 0) return std::nullopt;
  std::rotate(h.pivots.begin(), h.pivots.begin() + first, h.pivots.end());
  return h;
}

}  // namespace

std::optional<CircuitClosedForm> planar_loop_held_closed_form(const CircuitSolverContext& c,
                                                              int circuit) {
  const std::optional<HeldLoop> found = find_held_loop(c, circuit);
  if (!found) return std::nullopt;
  const HeldLoop& h = *found;
  const size_t size = h.loop.size();
  Pose segment[3];
  V pivot[3];
  for (size_t k = 0; k < 3; ++k) {
    pivot[k] = c.columns[static_cast<size_t>(h.loop[h.pivots[k].front()].column)].axis.s0;
    const size_t end = h.pivots[(k + 1) % 3].front();
    for (size_t i = (h.pivots[k].back() + 1) % size; i != end; i = (i + 1) % size)
      if (!h.held[i]) segment[k] = segment[k] * column_motion(c, h.loop[i]);
  }
  const std::string chord =
      c.model.joints[static_cast<size_t>(c.graph.chords[static_cast<size_t>(circuit)])].name;
  DyadSolver solver(c, h.n, segment, pivot, "ph_" + chord + "_");
  // Each pivot's angle at the assembly: the sum of its revolutes' theta.
  double theta[3] = {0, 0, 0};
  for (size_t k = 0; k < 3; ++k)
    for (const size_t i : h.pivots[k])
      theta[k] += h.sigma[i] * c.assembly_q[static_cast<size_t>(h.loop[i].column)];
  const DyadSolution at_assembly = solver.solve(solver.assembly_branch(theta[0]), false);
  if (!(c.at_assembly(at_assembly.disc) > 0)) return std::nullopt;
  for (size_t k = 0; k < 3; ++k) {
    const double t =
        std::atan2(c.at_assembly(at_assembly.sin[k]), c.at_assembly(at_assembly.cos[k]));
    if (!(std::abs(std::remainder(t - theta[k], 2 * M_PI)) < 1e-8)) return std::nullopt;
  }
  const size_t lead = h.pivots[0].front();
  const int lead_column = h.loop[lead].column;
  const ex warm0 = c.warm_start(lead_column);
  const ex theta1_warm = h.sigma[lead] * warm0;
  const DyadSolution s = solver.solve(0, true, &theta1_warm);
  CircuitClosedForm out;
  out.name = "planar_loop_held_" + chord;
  out.reach.push_back(s.disc);
  std::string joints, pairs, held;
  for (size_t k = 0; k < 3; ++k) {
    if (h.pivots[k].size() != 1) {
      out.closes = false;
      std::string names;
      for (const size_t i : h.pivots[k])
        names += (names.empty() ? "" : " + ") + column_name(c, h.loop[i].column);
      pairs += (pairs.empty() ? "" : ", ") + names;
      continue;
    }
    const size_t i = h.pivots[k].front();
    const int col = h.loop[i].column;
    const ex cq = s.cos[k], sq = h.sigma[i] * s.sin[k];
    out.coordinates.emplace_back(col, unwound(cq, sq, k == 0 ? warm0 : c.warm_start(col)));
    out.cos_sin[col] = {cq, c.named("ph_" + chord + "_sin_q" + std::to_string(k + 1), sq)};
    joints += (joints.empty() ? "" : ", ") + column_name(c, col);
  }
  for (size_t i = 0; i < size; ++i)
    if (h.held[i]) {
      const int col = h.loop[i].column;
      out.coordinates.emplace_back(col, ex(0));
      out.cos_sin[col] = {ex(1), ex(0)};
      held += (held.empty() ? "" : ", ") + column_name(c, col);
    }
  out.plan =
      "planar loop " + joints + " (parallel revolute axes)" +
      (held.empty() ? "" : "; out of its plane " + held + " held at 0") +
      (pairs.empty() ? "" : "; on a shared pivot " + pairs + " (their sum only: the rest later)") +
      "; in closed form in its plane: circle intersection (the one nearer the warm start), "
      "angles unwound to the warm start";
  return out;
}

std::optional<CircuitClosedForm> one_angle_closed_form(const CircuitSolverContext& c, int circuit) {
  const std::vector<LoopColumn> loop = column_loop(c, circuit);
  size_t at = loop.size();
  for (size_t k = 0; k < loop.size(); ++k)
    if (!c.known[static_cast<size_t>(loop[k].column)]) {
      if (at != loop.size()) return std::nullopt;
      at = k;
    }
  if (at == loop.size()) return std::nullopt;
  const int col = loop[at].column;
  const geometry::ScrewAxis<ex>& a = c.columns[static_cast<size_t>(col)].axis;
  if (a.kind != geometry::ScrewKind::rotation) return std::nullopt;
  // M_before E^dir M_after = I: E^dir = M_before^-1 M_after^-1; its rotation R about s by q.
  Pose before, after;
  for (size_t k = 0; k < at; ++k) before = before * column_motion(c, loop[k]);
  for (size_t k = at + 1; k < loop.size(); ++k) after = after * column_motion(c, loop[k]);
  geometry::Mat3<ex> R = geometry::transpose(before.R) * geometry::transpose(after.R);
  if (loop[at].direction < 0) R = geometry::transpose(R);
  // u = s x e, e the coordinate axis least along s.
  int e = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(c.at_assembly(a.s[static_cast<size_t>(i)])) <
        std::abs(c.at_assembly(a.s[static_cast<size_t>(e)])))
      e = i;
  V unit{ex(0), ex(0), ex(0)};
  unit[static_cast<size_t>(e)] = 1;
  const std::string chord =
      c.model.joints[static_cast<size_t>(c.graph.chords[static_cast<size_t>(circuit)])].name;
  const std::string prefix = "oa_" + chord + "_";
  const V u = geometry::cross(a.s, unit);
  const ex uu = geometry::dot(u, u);
  const V Ru = geometry::operator*(R, u);
  const ex cq = geometry::dot(u, Ru) / uu, sq = geometry::dot(a.s, geometry::cross(u, Ru)) / uu;
  const double q = std::atan2(c.at_assembly(sq), c.at_assembly(cq));
  if (!(std::abs(std::remainder(q - c.assembly_q[static_cast<size_t>(col)], 2 * M_PI)) < 1e-8))
    return std::nullopt;
  const V Ru_named{c.named(prefix + "Ru_x", Ru[0]), c.named(prefix + "Ru_y", Ru[1]),
                   c.named(prefix + "Ru_z", Ru[2])};
  const ex cos_named = c.named(prefix + "cos", geometry::dot(u, Ru_named) / uu);
  const ex sin_named =
      c.named(prefix + "sin", geometry::dot(a.s, geometry::cross(u, Ru_named)) / uu);
  CircuitClosedForm out;
  out.name = "one_angle_" + chord;
  out.coordinates.emplace_back(col, unwound(cos_named, sin_named, c.warm_start(col)));
  out.cos_sin[col] = {cos_named, sin_named};
  out.plan = "the loop's last unknown " + column_name(c, col) +
             " from the rotation of the rest (cos q = u.R u, sin q = s.(u x R u)), unwound to the "
             "warm start";
  return out;
}

}  // namespace mechgen::gen
