// Closed-form groups of binary links with universal and spherical ends (spatial_link_loops.hpp).
#include "spatial_link_loops.hpp"

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "branch_sign.hpp"

namespace mechgen::gen {

using GiNaC::ex;
using GiNaC::symbol;
using geometry::operator+;
using geometry::operator-;
using geometry::operator*;

namespace {

using V = geometry::Vec3<ex>;
using M = geometry::Mat3<ex>;
using Pose = geometry::Pose<ex>;
// Substitution maps keyed by symbols alone: a lookup per node instead of GiNaC's pattern match
// against every key (which made evaluating thousands of definitions at the assembly quadratic).
constexpr unsigned kSymbolKeys =
    GiNaC::subs_options::no_pattern | GiNaC::subs_options::pattern_is_not_product;

// What the link solver works from: the derivation's columns and tree poses, the columns known so
// far, and the assembly (default parameters, t0: the numeric solver's pose) to choose branches
// and to check itself; its own definitions' values there in `assembly`.
struct ClosureContext {
  const CircuitSolverContext& circuit;
  const SpatialModel& model;
  const SpatialGraph& graph;
  std::vector<geometry::ScrewAxis<ex>> axes;  // per column
  std::vector<ex> q;                          // per column: its coordinate's symbol
  const std::vector<Pose>& tree_pose;         // per body: displacement along the tree
  const std::vector<bool>& known;             // per column: primary or solved
  const std::vector<double>& assembly_q;      // per column: the coordinate at the assembly
  GiNaC::exmap assembly;                      // the group's own definitions -> their values

  double value(const ex& e) const { return circuit.at_assembly(e.subs(assembly, kSymbolKeys)); }
  // Body b's tree pose is usable: every coordinate on its tree path is known.
  bool pose_known(int body) const {
    const std::vector<int>& path = graph.path_sign[static_cast<size_t>(body)];
    for (size_t c = 0; c < path.size(); ++c)
      if (path[c] != 0 && !known[c]) return false;
    return true;
  }
};

// One link's closed form: the secondary coordinates it defines and how.
struct ClosedFormGroup {
  std::string name, plan;
  std::vector<int> columns;  // secondary columns it defines
  // Program order; the columns' own symbols (ClosureContext::q) are defined among them.
  std::vector<std::pair<symbol, ex>> definitions;
  std::vector<ex> reach;  // each >= 0 where the link closes (its discriminants)
  std::map<int, std::pair<ex, ex>> cos_sin;
  std::map<int, ex> warm;  // per column: its warm start's placeholder
};

// The chain Y -near- L1 [-prismatic- L2] -far- X found around one revolute (or prismatic) K-Y.
struct Link {
  int revolute = -1, K = -1, Y = -1;
  int y_end = -1, x_end = -1;  // the link's joints at Y and at X
  int prismatic = -1;          // the cylinder's, or -1
  int L1 = -1, L2 = -1, X = -1;
};

int other(const SpatialJoint& j, int body) {
  return j.first == body ? j.second : j.first;
}

// Joint j's columns are all unknown secondaries.
bool unknown(const ClosureContext& ctx, int j) {
  const SpatialJoint& joint = ctx.model.joints[static_cast<size_t>(j)];
  const int c0 = ctx.graph.joint_column[static_cast<size_t>(j)];
  for (size_t k = 0; k < joint.columns.size(); ++k)
    if (ctx.known[static_cast<size_t>(c0) + k]) return false;
  return !joint.columns.empty();
}

bool end_joint(const ClosureContext& ctx, int j) {
  const SpatialJointType t = ctx.model.joints[static_cast<size_t>(j)].type;
  return (t == SpatialJointType::universal || t == SpatialJointType::spherical) && unknown(ctx, j);
}

// The joints of body b other than `except`.
std::vector<int> joints_of(const SpatialModel& m, int b, int except) {
  std::vector<int> out;
  for (size_t j = 0; j < m.joints.size(); ++j)
    if (static_cast<int>(j) != except && (m.joints[j].first == b || m.joints[j].second == b))
      out.push_back(static_cast<int>(j));
  return out;
}

// A binary link from Y's joint `near`: the body beyond it has exactly one other joint, an end
// joint (to X) or a known prismatic followed by a body with one other joint, an end joint.
std::optional<Link> find_link(const ClosureContext& ctx, int revolute, int K, int Y, int near) {
  const SpatialModel& m = ctx.model;
  Link l{revolute, K, Y, near, -1, -1, other(m.joints[static_cast<size_t>(near)], Y), -1, -1};
  if (l.L1 == m.ground || l.L1 == K) return std::nullopt;
  const std::vector<int> next = joints_of(m, l.L1, near);
  if (next.size() != 1) return std::nullopt;
  int far = next[0];
  l.L2 = l.L1;
  const SpatialJoint& n = m.joints[static_cast<size_t>(far)];
  if (n.type == SpatialJointType::prismatic) {
    if (!ctx.known[static_cast<size_t>(ctx.graph.joint_column[static_cast<size_t>(far)])])
      return std::nullopt;
    l.prismatic = far;
    l.L2 = other(n, l.L1);
    const std::vector<int> last = joints_of(m, l.L2, far);
    if (l.L2 == m.ground || last.size() != 1) return std::nullopt;
    far = last[0];
  }
  if (!end_joint(ctx, far)) return std::nullopt;
  l.x_end = far;
  l.X = other(m.joints[static_cast<size_t>(far)], l.L2);
  const SpatialJointType a = m.joints[static_cast<size_t>(near)].type;
  const SpatialJointType b = m.joints[static_cast<size_t>(far)].type;
  // One end universal (it fixes the link's spin), the other spherical.
  if (l.X == Y || a == b || !ctx.pose_known(l.X)) return std::nullopt;
  return l;
}

// A cylinder whose prismatic is unknown and whose barrel and rod each have one other joint, an
// end joint to a known body: Y at the barrel's end, X at the rod's (revolute and K unused).
std::optional<Link> find_measured_link(const ClosureContext& ctx, int prismatic) {
  const SpatialModel& m = ctx.model;
  const SpatialJoint& pj = m.joints[static_cast<size_t>(prismatic)];
  Link l;
  l.prismatic = prismatic, l.L1 = pj.first, l.L2 = pj.second;
  const std::vector<int> near = joints_of(m, l.L1, prismatic), far = joints_of(m, l.L2, prismatic);
  if (l.L1 == m.ground || l.L2 == m.ground || near.size() != 1 || far.size() != 1 ||
      !end_joint(ctx, near[0]) || !end_joint(ctx, far[0]))
    return std::nullopt;
  l.y_end = near[0], l.x_end = far[0];
  l.Y = other(m.joints[static_cast<size_t>(l.y_end)], l.L1);
  l.X = other(m.joints[static_cast<size_t>(l.x_end)], l.L2);
  if (l.X == l.Y ||
      m.joints[static_cast<size_t>(l.y_end)].type == m.joints[static_cast<size_t>(l.x_end)].type ||
      !ctx.pose_known(l.X) || !ctx.pose_known(l.Y))
    return std::nullopt;
  return l;
}

class LinkSolver {
 public:
  LinkSolver(ClosureContext& ctx, const Link& l) : ctx_(ctx), m_(ctx.model), l_(l) {}

  // The group, or nothing when the geometry does not fit (checked at the assembly).
  std::optional<ClosedFormGroup> solve() {
    // Both ends known and nothing slides: a rod between a known body and a placed platform.
    const bool rigid = l_.revolute < 0 && l_.prismatic < 0;
    const bool measured = l_.revolute < 0;  // both ends known: the cylinder's length measured
    const std::string& rname =
        rigid ? body(l_.L1) : joint(measured ? l_.prismatic : l_.revolute).name;
    if (g_.name.empty())
      g_.name = rigid ? rname + " (both ends known)" : rname + " (link " + body(l_.L1) + ")";
    if (prefix_.empty()) prefix_ = "cf_" + rname + "_";
    const bool slider = !measured && joint(l_.revolute).type == SpatialJointType::prismatic;
    if (rigid) {
      if (!between_known()) return std::nullopt;
    } else if (measured) {
      if (!measured_length()) return std::nullopt;
    } else {
      const std::optional<ex> length2 = link_length2();
      if (!length2 || !(slider ? slide(*length2) : revolute(*length2))) return std::nullopt;
    }
    if (!ends()) return std::nullopt;
    // The group must reproduce the numeric solver's assembly (mod 2 pi).
    for (const int c : g_.columns) {
      const double d =
          ctx_.value(ctx_.q[static_cast<size_t>(c)]) - ctx_.assembly_q[static_cast<size_t>(c)];
      if (!(std::abs(std::remainder(d, 2 * M_PI)) < 1e-8)) return std::nullopt;
    }
    const SpatialJoint& u = joint(universal_end());
    const SpatialJoint& s = joint(spherical_end());
    const std::string from =
        rigid ? " between '" + body(l_.Y) + "' and '" + body(l_.X) + "'"
        : measured
            ? " between known '" + body(l_.Y) + "' and '" + body(l_.X) +
                  "': its coordinate from the distance of the end centres"
            : " from '" + body(l_.X) +
                  "': " + (slider ? "a quadratic in the slider's q" : "A cos q + B sin q = C") +
                  " (the root nearer the warm start)";
    g_.plan += "closed form, link '" + body(l_.L1) +
               (l_.prismatic >= 0
                    ? "' + '" + body(l_.L2) + "' (length " + (measured ? "of '" : "driven by '") +
                          joint(l_.prismatic).name + "')"
                    : "'") +
               from + ", then '" + u.name + "' (universal) from the link's direction, '" + s.name +
               "' (spherical) from the relative rotation";
    return g_;
  }

  // Y is a platform that keeps its reference orientation (Clavel's parallelograms) at known
  // distances r_i from known points: its displacement is the translation t that puts each of
  // three of its end centres w_i on its sphere, |w_i + t - e_i| = r_i, that is |t - c_i| = r_i
  // for c_i = e_i - w_i. The two differences of the spheres are planes, a . x = alpha and
  // b . x = beta for x = t - c_1; their line x0 + lambda n (n = a x b) meets the first sphere at
  // lambda = +-sqrt((r_1^2 - |x0|^2) / |n|^2): the root on the assembly's side (the plate below
  // the motors, not above). Then solve() places the link on Y's tree path from Y's pose.
  bool platform(const std::array<int, 3>& known_body, const std::array<V, 3>& known_centre,
                const std::array<V, 3>& platform_centre, const std::string& name,
                const std::string& plan) {
    g_.name = name;
    prefix_ = "cf_" + m_.bodies[static_cast<size_t>(l_.Y)].name + "_";
    std::array<V, 3> c;
    std::array<ex, 3> r2;
    for (size_t i = 0; i < 3; ++i) {
      const V d = known_centre[i] - platform_centre[i];
      c[i] =
          def("c" + std::to_string(i + 1),
              geometry::apply(ctx_.tree_pose[static_cast<size_t>(known_body[i])], known_centre[i]) -
                  platform_centre[i]);
      r2[i] = def("r" + std::to_string(i + 1) + "_sq", geometry::dot(d, d));
    }
    const V a = def("a", c[1] - c[0]), b = def("b", c[2] - c[0]);
    const V n = def("n", geometry::cross(a, b));
    const ex nn = def("nn", geometry::dot(n, n));
    const ex alpha = def("plane_a", (geometry::dot(a, a) + r2[0] - r2[1]) / 2);
    const ex beta = def("plane_b", (geometry::dot(b, b) + r2[0] - r2[2]) / 2);
    const V x0 =
        def("x0", (1 / nn) * (alpha * geometry::cross(b, n) + beta * geometry::cross(n, a)));
    const ex disc = def("disc", r2[0] - geometry::dot(x0, x0));
    g_.reach.push_back(disc);
    // The assembly's translation and orientation: the root's side, and the orientation kept.
    const Pose& DP = ctx_.tree_pose[static_cast<size_t>(l_.Y)];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (!(std::abs(ctx_.value(DP.R(i, j)) - (i == j ? 1.0 : 0.0)) < 1e-9)) return false;
    const V off = DP.p - c[0] - x0;
    const double side = ctx_.value(geometry::dot(off, n));
    if (!(ctx_.value(disc) > 0) || side == 0) return false;
    const ex lambda = def("lambda", (side > 0 ? 1 : -1) * root(disc) / GiNaC::sqrt(nn));
    const V t = def("t", c[0] + x0 + lambda * n);
    const V miss = t - DP.p;
    if (!(std::sqrt(ctx_.value(geometry::dot(miss, miss))) < 1e-9)) return false;
    placed_ = Pose{M::identity(), t};
    g_.plan = plan;
    return true;
  }

 private:
  const SpatialJoint& joint(int j) const { return m_.joints[static_cast<size_t>(j)]; }
  const std::string& body(int b) const { return m_.bodies[static_cast<size_t>(b)].name; }
  size_t column(int j) const {
    return static_cast<size_t>(ctx_.graph.joint_column[static_cast<size_t>(j)]);
  }
  const V& centre(int j) const { return ctx_.axes[column(j)].s0; }
  int universal_end() const {
    return joint(l_.y_end).type == SpatialJointType::universal ? l_.y_end : l_.x_end;
  }
  int spherical_end() const { return universal_end() == l_.y_end ? l_.x_end : l_.y_end; }

  ex def(const std::string& name, const ex& e) {
    const ex x = e.expand();
    if (GiNaC::is_a<GiNaC::numeric>(x) || GiNaC::is_a<symbol>(x)) return x;
    const symbol s(prefix_ + name);
    g_.definitions.emplace_back(s, x);
    ctx_.assembly[s] = ctx_.value(x);
    return s;
  }
  V def(const std::string& name, const V& v) {
    return {def(name + "_x", v[0]), def(name + "_y", v[1]), def(name + "_z", v[2])};
  }
  M def(const std::string& name, const M& R) {
    M out;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        out(i, j) = def(name + "_" + std::to_string(i) + std::to_string(j), R(i, j));
    return out;
  }
  // Column c's warm start: the previous call's value of its coordinate (the assembly at first).
  ex warm(size_t c) {
    const auto it = g_.warm.find(static_cast<int>(c));
    if (it != g_.warm.end()) return it->second;
    const symbol w("warm_" + std::to_string(c));
    ctx_.assembly[w] = ctx_.assembly_q[c];
    g_.warm[static_cast<int>(c)] = w;
    return w;
  }
  // Column c's coordinate from the sine-like y and cosine-like x of its angle, unwound to the
  // warm start w (the previous call's value): w + atan2(sin(angle - w), cos(angle - w))
  // (continuous along a sweep, as the numeric solver's Newton-Raphson from the previous sample).
  void define_angle(size_t c, const ex& y, const ex& x) {
    const ex w = warm(c);
    const ex cw = GiNaC::cos(w), sw = GiNaC::sin(w);
    const symbol q = GiNaC::ex_to<symbol>(ctx_.q[c]);
    const ex value = w + GiNaC::atan2((y * cw - x * sw).expand(), (x * cw + y * sw).expand());
    g_.definitions.emplace_back(q, value);
    ctx_.assembly[q] = ctx_.value(value);
    g_.columns.push_back(static_cast<int>(c));
  }
  // max(x, 0) without a branch: a discriminant below zero (unreachable, reported through
  // ClosedFormGroup::reach) gives a root of zero instead of NaN.
  static ex root(const ex& x) { return GiNaC::sqrt((x + GiNaC::abs(x)) / 2); }

  // The squared distance of the end centres (the cylinder's: its reference length plus the
  // prismatic's coordinate along the link).
  std::optional<ex> link_length2() {
    d0_ = def("d0", centre(l_.x_end) - centre(l_.y_end));  // from the Y end to the X end
    const ex n2 = def("len0_sq", geometry::dot(d0_, d0_));
    if (l_.prismatic < 0) return n2;
    const size_t c = column(l_.prismatic);
    const V& s = ctx_.axes[c].s;
    // The prismatic must slide along the line of the centres (checked at default parameters).
    const V sx = geometry::cross(s, d0_);
    if (!(std::sqrt(ctx_.value(geometry::dot(sx, sx))) <= 1e-9 * std::sqrt(ctx_.value(n2))))
      return std::nullopt;
    const ex n = def("len0", GiNaC::sqrt(n2));
    const ex sign = joint(l_.prismatic).first == l_.L1 ? 1 : -1;
    length_ = def("len", n + sign * ctx_.q[c] * geometry::dot(s, d0_) / n);
    scale_ = def("len_ratio", length_ / n);
    return length_ * length_;
  }

  // Both ends' bodies placed (Y by a platform's closed form, or by its tree path) and nothing
  // slides: the ends' angles from the end centres; the link's length must be the distance there.
  bool between_known() {
    d0_ = def("d0", centre(l_.x_end) - centre(l_.y_end));
    DY_ = placed_ ? *placed_ : ctx_.tree_pose[static_cast<size_t>(l_.Y)];
    cX_ = def("cX", geometry::apply(ctx_.tree_pose[static_cast<size_t>(l_.X)], centre(l_.x_end)));
    cY_ = def("cY", geometry::apply(DY_, centre(l_.y_end)));
    const V span = cX_ - cY_;
    const double now = std::sqrt(ctx_.value(geometry::dot(span, span)));
    const double length = std::sqrt(ctx_.value(geometry::dot(d0_, d0_)));
    return std::abs(now - length) < 1e-9 * (1 + length);
  }

  // Both end bodies known, the prismatic unknown (a cylinder following a pose-driven leg): the
  // end centres' distance is the length, the coordinate its excess over the reference length
  // along the prismatic's axis.
  bool measured_length() {
    d0_ = def("d0", centre(l_.x_end) - centre(l_.y_end));
    const ex n2 = def("len0_sq", geometry::dot(d0_, d0_));
    const size_t c = column(l_.prismatic);
    const V& s = ctx_.axes[c].s;
    const V sx = geometry::cross(s, d0_);
    if (!(std::sqrt(ctx_.value(geometry::dot(sx, sx))) <= 1e-9 * std::sqrt(ctx_.value(n2))))
      return false;
    const ex n = def("len0", GiNaC::sqrt(n2));
    DY_ = ctx_.tree_pose[static_cast<size_t>(l_.Y)];
    cX_ = def("cX", geometry::apply(ctx_.tree_pose[static_cast<size_t>(l_.X)], centre(l_.x_end)));
    cY_ = def("cY", geometry::apply(DY_, centre(l_.y_end)));
    const V span = cX_ - cY_;
    length_ = def("len", GiNaC::sqrt(geometry::dot(span, span)));
    scale_ = def("len_ratio", length_ / n);
    const ex sign = joint(l_.prismatic).first == l_.L1 ? 1 : -1;
    const symbol q = GiNaC::ex_to<symbol>(ctx_.q[c]);
    const ex value = (sign * (length_ - n) * n / geometry::dot(s, d0_)).expand();
    g_.definitions.emplace_back(q, value);
    ctx_.assembly[q] = ctx_.value(value);
    g_.columns.push_back(static_cast<int>(c));
    return std::abs(ctx_.value(q) - ctx_.assembly_q[c]) < 1e-8;
  }

  // The revolute K-Y: |c_Y(q) - c_X|^2 = L^2 in K's frame is A cos q + B sin q = C.
  bool revolute(const ex& length2) {
    const size_t c = column(l_.revolute);
    const geometry::ScrewAxis<ex>& a = ctx_.axes[c];
    const ex sigma = joint(l_.revolute).first == l_.K ? 1 : -1;
    const Pose& DK = ctx_.tree_pose[static_cast<size_t>(l_.K)];
    const Pose& DX = ctx_.tree_pose[static_cast<size_t>(l_.X)];
    cX_ = def("cX", geometry::apply(DX, centre(l_.x_end)));
    const V v = def("v", centre(l_.y_end) - a.s0);
    const V vpar = geometry::dot(a.s, v) * a.s;
    const V vperp = def("vperp", v - vpar);
    const V sxv = def("sxv", geometry::cross(a.s, v));
    const V f = def("f", geometry::transpose(DK.R) * (cX_ - DK.p));
    const V e = def("e", a.s0 + vpar - f);
    const ex A = def("A", 2 * geometry::dot(e, vperp));
    const ex B = def("B", 2 * sigma * geometry::dot(e, sxv));
    const ex C = def("C", length2 - geometry::dot(e, e) - geometry::dot(vperp, vperp));
    const ex r2 = def("r2", A * A + B * B);
    const ex disc = def("disc", r2 - C * C);
    g_.reach.push_back(disc);
    const ex rt = def("root", root(disc));
    // The roots are q = phi +- alpha (phi = atan2(B, A), cos alpha = C / r): the + root is the
    // nearer to the warm start w exactly where sin(w - phi) > 0, that is A sin w - B cos w > 0.
    const ex w = warm(c);
    const ex nearer = A * GiNaC::sin(w) - B * GiNaC::cos(w);
    const ex tau = def("branch", followed_branch(nearer, ctx_.value(nearer)));
    // At the assembly the chosen root must be the assembly's angle, away from a dead point.
    const double cq_a = ctx_.value((A * C - tau * B * rt) / r2);
    const double sq_a = ctx_.value((B * C + tau * A * rt) / r2);
    if (!(std::abs(std::remainder(std::atan2(sq_a, cq_a) - ctx_.assembly_q[c], 2 * M_PI)) < 1e-8) ||
        !(ctx_.value(disc) > 0))
      return false;
    const ex cq = def("cos", (A * C - tau * B * rt) / r2);
    const ex sq = def("sin", (B * C + tau * A * rt) / r2);
    define_angle(c, sq, cq);
    g_.cos_sin[static_cast<int>(c)] = {cq, sq};
    // Y's displacement: K's, then the rotation about the axis (against it when K is second).
    M R;
    const ex s1 = sigma * sq, v1 = 1 - cq;
    const V& s = a.s;
    R(0, 0) = s[0] * s[0] * v1 + cq, R(0, 1) = s[0] * s[1] * v1 - s[2] * s1;
    R(0, 2) = s[0] * s[2] * v1 + s[1] * s1, R(1, 0) = s[0] * s[1] * v1 + s[2] * s1;
    R(1, 1) = s[1] * s[1] * v1 + cq, R(1, 2) = s[1] * s[2] * v1 - s[0] * s1;
    R(2, 0) = s[0] * s[2] * v1 - s[1] * s1, R(2, 1) = s[1] * s[2] * v1 + s[0] * s1;
    R(2, 2) = s[2] * s[2] * v1 + cq;
    const Pose E{R, a.s0 - R * a.s0};
    const Pose DY = DK * E;
    DY_ = {def("RY", DY.R), def("pY", DY.p)};
    cY_ = def("cY", geometry::apply(DY_, centre(l_.y_end)));
    return true;
  }

  // The prismatic K-Y (a slider): |c_Y(q) - c_X|^2 = L^2 in K's frame is a quadratic in q.
  bool slide(const ex& length2) {
    const size_t c = column(l_.revolute);
    const V& s = ctx_.axes[c].s;
    const ex sigma = joint(l_.revolute).first == l_.K ? 1 : -1;
    const Pose& DK = ctx_.tree_pose[static_cast<size_t>(l_.K)];
    const Pose& DX = ctx_.tree_pose[static_cast<size_t>(l_.X)];
    cX_ = def("cX", geometry::apply(DX, centre(l_.x_end)));
    const V e = def("e", centre(l_.y_end) - geometry::transpose(DK.R) * (cX_ - DK.p));
    // (s.s) u^2 + 2 (s.e) u + e.e - L^2 = 0 for the displacement u = sigma q along s.
    const ex ss = def("ss", geometry::dot(s, s));
    const ex se = def("se", geometry::dot(s, e));
    const ex disc = def("disc", se * se - ss * (geometry::dot(e, e) - length2));
    g_.reach.push_back(disc);
    const ex rt = def("root", root(disc));
    // The roots u = (-se +- root) / ss: the + root is the nearer to the warm start's displacement
    // sigma w exactly where se + sigma ss w > 0.
    const ex nearer = se + sigma * ss * warm(c);
    const ex tau = def("branch", followed_branch(nearer, ctx_.value(nearer)));
    const double qa = ctx_.assembly_q[c];
    if (!(std::abs(ctx_.value(sigma * (-se + tau * rt) / ss) - qa) < 1e-8 * (1 + std::abs(qa))) ||
        !(ctx_.value(disc) > 0))
      return false;  // not the assembly, or at a dead point
    const symbol q = GiNaC::ex_to<symbol>(ctx_.q[c]);
    const ex value = (sigma * (-se + tau * rt) / ss).expand();
    g_.definitions.emplace_back(q, value);
    ctx_.assembly[q] = ctx_.value(value);
    g_.columns.push_back(static_cast<int>(c));
    // Y's displacement: K's, then the translation along the axis (against it when K is second).
    const Pose DY = DK * Pose{M::identity(), (sigma * q) * s};
    DY_ = {def("RY", DY.R), def("pY", DY.p)};
    cY_ = def("cY", geometry::apply(DY_, centre(l_.y_end)));
    return true;
  }

  const Pose& pose(int b) const { return b == l_.Y ? DY_ : ctx_.tree_pose[static_cast<size_t>(b)]; }

  // The universal end's angles from the link's direction, the spherical end's from the rest.
  bool ends() {
    const int uj = universal_end(), sj = spherical_end();
    const SpatialJoint& u = joint(uj);
    const bool u_at_y = uj == l_.y_end;
    const int anchor = u_at_y ? l_.Y : l_.X;
    // The link's direction now (from the universal's centre to the spherical's) in the anchor's
    // displaced frame, w, and at the reference, p (scaled to the current length).
    const V d = u_at_y ? cX_ - cY_ : cY_ - cX_;
    const V w = def("w", geometry::transpose(pose(anchor).R) * d);
    const V p0 = u_at_y ? d0_ : -d0_;
    const V p = l_.prismatic < 0 ? p0 : def("p", scale_ * p0);
    // Rot(k1, a1) Rot(k2, a2) p = w: the universal's axes in product order when the anchor is its
    // first body; else the anchor's pose is the link's times the universal's motion, inverted.
    const size_t cu = column(uj);
    const bool anchor_first = u.first == anchor;
    const V& k1 = anchor_first ? ctx_.axes[cu].s : ctx_.axes[cu + 1].s;
    const V& k2 = anchor_first ? ctx_.axes[cu + 1].s : ctx_.axes[cu].s;
    const ex al = def("alpha", geometry::dot(k1, w));  // k1 . z (k1 is perpendicular to k2)
    const ex be = def("beta", geometry::dot(k2, p));   // k2 . z
    const ex disc = def("u_disc", geometry::dot(p, p) - al * al - be * be);
    g_.reach.push_back(disc);
    const ex rt = def("u_root", root(disc));
    const V k3 = geometry::cross(k1, k2);
    // The two roots differ in z's k3 component (+-root): the nearer to the warm start's
    // z = Rot(k2, a2) p has the sign of that z's k3 component (a2 the angle about k2: column
    // cu + 1's when the anchor is first, minus column cu's otherwise).
    const ex a2_warm = anchor_first ? warm(cu + 1) : -warm(cu);
    const ex side = geometry::dot(k3, geometry::rodrigues(k2, a2_warm) * p);
    const ex gamma = def("branch_u", followed_branch(side, ctx_.value(side)));
    const V z = def("z", al * k1 + be * k2 + (gamma * rt) * k3);
    if (!angles_match(cu, anchor_first, k1, k2, p, w, z)) return false;
    const ex y2 = geometry::dot(k2, geometry::cross(p, z)), x2 = geometry::dot(p, z) - be * be;
    const ex y1 = geometry::dot(k1, geometry::cross(z, w)), x1 = geometry::dot(z, w) - al * al;
    if (anchor_first) {
      define_angle(cu, y1, x1);
      define_angle(cu + 1, y2, x2);
    } else {
      define_angle(cu, -y2, x2);
      define_angle(cu + 1, -y1, x1);
    }
    // The link's rotation, then the spherical end's relative rotation Rx Ry Rz.
    const M Ru = geometry::rodrigues(ctx_.axes[cu].s, ctx_.q[cu]) *
                 geometry::rodrigues(ctx_.axes[cu + 1].s, ctx_.q[cu + 1]);
    const M RL =
        def("RL", anchor_first ? pose(anchor).R * Ru : pose(anchor).R * geometry::transpose(Ru));
    const SpatialJoint& s = joint(sj);
    const int s_anchor = u_at_y ? l_.X : l_.Y;
    const M& Ra = pose(s_anchor).R;
    const M& R1 = s.first == s_anchor ? Ra : RL;
    const M& R2 = s.first == s_anchor ? RL : Ra;
    auto rel = [&](int i, int j) {
      return def("m" + std::to_string(i) + std::to_string(j),
                 R1(0, i) * R2(0, j) + R1(1, i) * R2(1, j) + R1(2, i) * R2(2, j));
    };
    const ex m00 = rel(0, 0), m01 = rel(0, 1), m02 = rel(0, 2), m12 = rel(1, 2), m22 = rel(2, 2);
    // Of the two equivalent angle sets, the one whose middle angle's cosine has the sign of the
    // warm start's (a spherical joint is singular where it is zero, docs/spatial.md).
    const size_t cs = column(sj);
    const ex middle = GiNaC::cos(warm(cs + 1));
    const ex kappa = def("branch_s", followed_branch(middle, ctx_.value(middle)));
    define_angle(cs, -kappa * m12, kappa * m22);
    define_angle(cs + 1, m02, kappa * GiNaC::sqrt(m12 * m12 + m22 * m22));
    define_angle(cs + 2, -kappa * m01, kappa * m00);
    return true;
  }

  // Whether the candidate z gives the universal's assembly angles.
  bool angles_match(size_t cu, bool anchor_first, const V& k1, const V& k2, const V& p, const V& w,
                    const V& z) const {
    const double a2 =
        std::atan2(ctx_.value(geometry::dot(k2, geometry::cross(p, z))),
                   ctx_.value(geometry::dot(p, z) - geometry::dot(k2, p) * geometry::dot(k2, z)));
    const double a1 =
        std::atan2(ctx_.value(geometry::dot(k1, geometry::cross(z, w))),
                   ctx_.value(geometry::dot(z, w) - geometry::dot(k1, z) * geometry::dot(k1, w)));
    const double qa = anchor_first ? a1 : -a2, qb = anchor_first ? a2 : -a1;
    return std::abs(std::remainder(qa - ctx_.assembly_q[cu], 2 * M_PI)) < 1e-8 &&
           std::abs(std::remainder(qb - ctx_.assembly_q[cu + 1], 2 * M_PI)) < 1e-8;
  }

  ClosureContext& ctx_;
  const SpatialModel& m_;
  Link l_;
  ClosedFormGroup g_;
  std::string prefix_;
  V d0_, cX_, cY_;
  ex length_, scale_;
  Pose DY_;
  std::optional<Pose> placed_;  // Y's displacement, given (a platform)
};

// The first link (over the unknown revolutes in joint order) that `accept` takes.
std::optional<ClosedFormGroup> link_group(
    ClosureContext& ctx, const std::function<bool(const ClosedFormGroup&)>& accept) {
  const SpatialModel& m = ctx.model;
  for (size_t j = 0; j < m.joints.size(); ++j) {
    const SpatialJoint& r = m.joints[j];
    const bool one_axis =
        r.type == SpatialJointType::revolute || r.type == SpatialJointType::prismatic;
    if (!one_axis || !unknown(ctx, static_cast<int>(j))) continue;
    for (const auto& [K, Y] : {std::pair{r.first, r.second}, std::pair{r.second, r.first}}) {
      if (Y == m.ground || !ctx.pose_known(K)) continue;
      for (const int near : joints_of(m, Y, static_cast<int>(j))) {
        if (!end_joint(ctx, near)) continue;
        const std::optional<Link> link = find_link(ctx, static_cast<int>(j), K, Y, near);
        if (!link) continue;
        ctx.assembly.clear();
        std::optional<ClosedFormGroup> group = LinkSolver(ctx, *link).solve();
        if (group && accept(*group)) return group;
      }
    }
  }
  for (size_t j = 0; j < m.joints.size(); ++j) {
    if (m.joints[j].type != SpatialJointType::prismatic || !unknown(ctx, static_cast<int>(j)))
      continue;
    const std::optional<Link> link = find_measured_link(ctx, static_cast<int>(j));
    if (!link) continue;
    ctx.assembly.clear();
    std::optional<ClosedFormGroup> group = LinkSolver(ctx, *link).solve();
    if (group && accept(*group)) return group;
  }
  // A rod between two known bodies (a platform's, once the platform is placed): nothing unknown
  // but its ends' angles.
  for (size_t b = 0; b < m.bodies.size(); ++b) {
    const int L = static_cast<int>(b);
    const std::vector<int> ends = joints_of(m, L, -1);
    if (L == m.ground || ends.size() != 2 || !end_joint(ctx, ends[0]) || !end_joint(ctx, ends[1]))
      continue;
    Link l;
    l.L1 = l.L2 = L, l.y_end = ends[0], l.x_end = ends[1];
    l.Y = other(m.joints[static_cast<size_t>(ends[0])], L);
    l.X = other(m.joints[static_cast<size_t>(ends[1])], L);
    if (l.X == l.Y ||
        m.joints[static_cast<size_t>(ends[0])].type ==
            m.joints[static_cast<size_t>(ends[1])].type ||
        !ctx.pose_known(l.X) || !ctx.pose_known(l.Y))
      continue;
    ctx.assembly.clear();
    std::optional<ClosedFormGroup> group = LinkSolver(ctx, l).solve();
    if (group && accept(*group)) return group;
  }
  return std::nullopt;
}

// A platform P held only by rods from known bodies, two per body as a parallelogram whose side
// on that body keeps its direction (it lies along every revolute axis of the body's tree path:
// a Delta's arm), from three or more bodies whose sides are not all parallel: P keeps its
// reference orientation (Clavel's argument) and its position is the intersection of three
// spheres. Then the rod on P's tree path is placed between its known body and P; the other rods
// are then links between known bodies (link_group). The layout is recognised at the default
// parameters; P's translation must give the assembly.
std::optional<ClosedFormGroup> platform_group(ClosureContext& ctx,
                                              const std::vector<bool>& in_circuit) {
  const SpatialModel& m = ctx.model;
  struct Rod {
    int L = -1, at_platform = -1, at_known = -1, known = -1;
  };
  const auto small = [&](const V& v) { return std::sqrt(ctx.value(geometry::dot(v, v))) < 1e-9; };
  for (size_t pb = 0; pb < m.bodies.size(); ++pb) {
    const int P = static_cast<int>(pb);
    if (P == m.ground || ctx.pose_known(P)) continue;
    std::map<int, std::vector<Rod>> by_known;  // the rods, by their known body
    bool rods_only = true;
    for (const int j : joints_of(m, P, -1)) {
      Rod r{other(m.joints[static_cast<size_t>(j)], P), j, -1, -1};
      const std::vector<int> next = joints_of(m, r.L, j);
      rods_only =
          rods_only && r.L != m.ground && end_joint(ctx, j) && next.size() == 1 &&
          end_joint(ctx, next[0]) &&
          m.joints[static_cast<size_t>(j)].type != m.joints[static_cast<size_t>(next[0])].type;
      if (!rods_only) break;
      r.at_known = next[0];
      r.known = other(m.joints[static_cast<size_t>(next[0])], r.L);
      rods_only = r.known != P && ctx.pose_known(r.known);
      if (!rods_only) break;
      by_known[r.known].push_back(r);
    }
    if (!rods_only || by_known.size() < 3) continue;
    const auto centre = [&](int j) -> const V& {
      return ctx.axes[static_cast<size_t>(ctx.graph.joint_column[static_cast<size_t>(j)])].s0;
    };
    // Each known body's pair: a parallelogram at the reference, its side along the body's axes.
    std::vector<V> sides;
    bool parallelograms = true;
    for (const auto& [known, rods] : by_known) {
      if (rods.size() != 2) {
        parallelograms = false;
        break;
      }
      const V side = centre(rods[1].at_known) - centre(rods[0].at_known);
      const V l0 = centre(rods[0].at_known) - centre(rods[0].at_platform);
      const V l1 = centre(rods[1].at_known) - centre(rods[1].at_platform);
      parallelograms = !small(side) &&
                       small(side - (centre(rods[1].at_platform) - centre(rods[0].at_platform))) &&
                       small(l0 - l1);
      const std::vector<int>& path = ctx.graph.path_sign[static_cast<size_t>(known)];
      for (size_t c = 0; parallelograms && c < path.size(); ++c)
        if (path[c] != 0 && ctx.axes[c].kind == geometry::ScrewKind::rotation)
          parallelograms = small(geometry::cross(ctx.axes[c].s, side));
      if (!parallelograms) break;
      sides.push_back(side);
    }
    if (!parallelograms) continue;
    bool crossing = false;  // two sides not parallel: together they fix the orientation
    for (size_t i = 1; i < sides.size(); ++i)
      crossing = crossing || !small(geometry::cross(sides[0], sides[i]));
    if (!crossing) continue;
    // P's tree path: its unknown columns are exactly one rod's.
    const std::vector<int>& path = ctx.graph.path_sign[pb];
    std::optional<Rod> tree_rod;
    for (const auto& [known, rods] : by_known)
      for (const Rod& r : rods)
        if (ctx.graph.parent_joint[pb] == r.at_platform) tree_rod = r;
    if (!tree_rod) continue;
    std::vector<bool> rod_column(path.size(), false);
    for (const int j : {tree_rod->at_platform, tree_rod->at_known}) {
      const int c0 = ctx.graph.joint_column[static_cast<size_t>(j)];
      for (size_t k = 0; k < m.joints[static_cast<size_t>(j)].columns.size(); ++k)
        rod_column[static_cast<size_t>(c0) + k] = true;
    }
    bool only_the_rod = true;
    for (size_t c = 0; c < path.size(); ++c)
      if (path[c] != 0 && !ctx.known[c])
        only_the_rod = only_the_rod && rod_column[c] && in_circuit[c];
    if (!only_the_rod) continue;
    std::array<V, 3> known_centre, platform_centre;
    std::array<int, 3> arms{};
    std::string names;
    size_t i = 0;
    for (const auto& [known, rods] : by_known) {
      if (i == 3) break;
      known_centre[i] = centre(rods[0].at_known);
      platform_centre[i] = centre(rods[0].at_platform);
      arms[i++] = known;
      names += (names.empty() ? "'" : ", '") + m.bodies[static_cast<size_t>(known)].name + "'";
    }
    Link l;
    l.L1 = l.L2 = tree_rod->L, l.Y = P, l.X = tree_rod->known;
    l.y_end = tree_rod->at_platform, l.x_end = tree_rod->at_known;
    ctx.assembly.clear();
    LinkSolver solver(ctx, l);
    const std::string& name = m.bodies[pb].name;
    if (!solver.platform(arms, known_centre, platform_centre, name + " (three spheres)",
                         "platform '" + name + "' keeps its orientation (parallelogram rods from " +
                             names + "): its position from the intersection of three spheres; "))
      continue;
    return solver.solve();
  }
  return std::nullopt;
}

// Which columns take part in `circuit`'s closure (coefficient not zero).
std::vector<bool> circuit_columns(const CircuitSolverContext& context, int circuit) {
  const SpatialGraph& g = context.graph;
  const int chord = g.chords[static_cast<size_t>(circuit)];
  const SpatialJoint& cj = context.model.joints[static_cast<size_t>(chord)];
  std::vector<bool> in_circuit(g.columns.size());
  for (size_t c = 0; c < g.columns.size(); ++c)
    in_circuit[c] = g.path_sign[static_cast<size_t>(cj.first)][c] -
                        g.path_sign[static_cast<size_t>(cj.second)][c] +
                        (g.columns[c].joint == chord ? 1 : 0) !=
                    0;
  return in_circuit;
}

ClosureContext closure_context(const CircuitSolverContext& context) {
  ClosureContext ctx{context,           context.model, context.graph,      {}, {},
                     context.tree_pose, context.known, context.assembly_q, {}};
  for (const CircuitColumn& c : context.columns) {
    ctx.axes.push_back(c.axis);
    ctx.q.push_back(c.q);
  }
  return ctx;
}

// The group's definitions under the derivation's names (the columns' own symbols are its
// coordinates).
CircuitClosedForm circuit_form(const CircuitSolverContext& context, const ClosureContext& ctx,
                               const ClosedFormGroup& group, bool closes) {
  CircuitClosedForm out{group.name, group.plan, {}, {}, {}};
  out.closes = closes;
  std::map<ex, int, GiNaC::ex_is_less> column_of;
  for (const int c : group.columns) column_of[ctx.q[static_cast<size_t>(c)]] = c;
  GiNaC::exmap renamed;
  for (const auto& [c, w] : group.warm) renamed[w] = context.warm_start(c);
  for (const auto& [name, value] : group.definitions) {
    const ex v = value.subs(renamed);
    const auto it = column_of.find(name);
    if (it != column_of.end())
      out.coordinates.emplace_back(it->second, v);
    else
      renamed[name] = context.named(name.get_name(), v);
  }
  for (const ex& r : group.reach) out.reach.push_back(r.subs(renamed));
  for (const auto& [c, cs] : group.cos_sin)
    out.cos_sin[c] = {cs.first.subs(renamed), cs.second.subs(renamed)};
  return out;
}

}  // namespace

std::optional<CircuitClosedForm> platform_closed_form(const CircuitSolverContext& context,
                                                      int circuit) {
  ClosureContext ctx = closure_context(context);
  const std::vector<bool> in_circuit = circuit_columns(context, circuit);
  const std::optional<ClosedFormGroup> group = platform_group(ctx, in_circuit);
  if (!group) return std::nullopt;
  // Closed when the rod on the platform's path was the circuit's last unknown.
  bool closes = true;
  std::vector<bool> known = context.known;
  for (const int c : group->columns) known[static_cast<size_t>(c)] = true;
  for (size_t c = 0; c < known.size(); ++c) closes = closes && (!in_circuit[c] || known[c]);
  return circuit_form(context, ctx, *group, closes);
}

std::optional<CircuitClosedForm> link_loop_closed_form(const CircuitSolverContext& context,
                                                       int circuit) {
  ClosureContext ctx = closure_context(context);
  const std::vector<bool> in_circuit = circuit_columns(context, circuit);
  const auto accept = [&](const ClosedFormGroup& group) {
    std::vector<bool> known = context.known;
    for (const int c : group.columns) {
      if (!in_circuit[static_cast<size_t>(c)]) return false;
      known[static_cast<size_t>(c)] = true;
    }
    for (size_t c = 0; c < known.size(); ++c)
      if (in_circuit[c] && !known[c]) return false;
    return true;
  };
  const std::optional<ClosedFormGroup> group = link_group(ctx, accept);
  if (!group) return std::nullopt;
  return circuit_form(context, ctx, *group, true);
}

}  // namespace mechgen::gen
