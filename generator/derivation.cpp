#include "derivation.hpp"

#include <cmath>
#include <map>
#include <stdexcept>

namespace mechgen::gen {

using GiNaC::ex;

namespace {

struct Vec {
  ex x, y;
};
Vec operator+(const Vec& a, const Vec& b) {
  return {a.x + b.x, a.y + b.y};
}
Vec operator-(const Vec& a, const Vec& b) {
  return {a.x - b.x, a.y - b.y};
}
Vec operator*(const ex& k, const Vec& a) {
  return {k * a.x, k * a.y};
}
ex dot(const Vec& a, const Vec& b) {
  return a.x * b.x + a.y * b.y;
}
ex cross(const Vec& a, const Vec& b) {
  return a.x * b.y - a.y * b.x;
}

// A body frame in the reference frame: origin, rotation (cos, sin) and angular velocity.
struct Frame {
  bool located = false;
  ex x = 0, y = 0, c = 1, s = 0, w = 0;
  Vec rotate(const Vec& v) const { return {c * v.x - s * v.y, s * v.x + c * v.y}; }
  Vec place(const Vec& v) const { return Vec{x, y} + rotate(v); }
};

double wrap(double a) {
  return std::remainder(a, 2 * M_PI);
}

class Deriver {
 public:
  Deriver(const Model& model, const SolvePlan& plan, const std::vector<BodyPose>& pose,
          StagedProgram& program, Derivation& out)
      : model_(model),
        plan_(plan),
        pose_(pose),
        p_(program),
        out_(out),
        frames_(model.bodies.size()),
        world_(model.bodies.size()),
        com_(model.bodies.size()),
        acceleration_(model.bodies.size()),
        angular_acceleration_(model.bodies.size()) {
    if (plan.reference != model.ground)
      ref_prefix_ = model.bodies[static_cast<size_t>(plan.reference)].name + "_";
  }

  void run() {
    for (const Parameter& par : model_.parameters) p_.declare(par.symbol, 0);
    p_.declare(model_.t, 1);
    for (const auto& in : out_.driver_inputs) {
      p_.declare(in.q, in.qd);
      p_.declare(in.qd, in.qdd);
    }
    frames_[static_cast<size_t>(plan_.reference)].located = true;
    for (size_t g = 0; g < plan_.groups.size(); ++g) {
      out_.group_names.push_back(plan_.groups[g].name);
      solve_group(plan_.groups[g], static_cast<int>(g));
    }
    kinematic_outputs();
    out_.kinematics_statements = p_.statements().size();
    newton_euler();
  }

 private:
  const Body& body(int b) const { return model_.bodies[static_cast<size_t>(b)]; }
  const Joint& joint(int j) const { return model_.joints[static_cast<size_t>(j)]; }
  Frame& frame(int b) { return frames_[static_cast<size_t>(b)]; }
  Vec local(int b, const std::string& point) const {
    const BodyPoint* p = body(b).find_point(point);
    if (!p) throw std::logic_error("body '" + body(b).name + "' has no point '" + point + "'");
    return {p->local.x.ex, p->local.y.ex};
  }

  // Names a quantity unless it is trivial (a number or a symbol already).
  ex name(const std::string& n, const ex& value) {
    if (GiNaC::is_a<GiNaC::numeric>(value) || GiNaC::is_a<GiNaC::symbol>(value)) return value;
    return p_.define(n, value);
  }
  Vec name(const std::string& n, const Vec& v) {
    return {name(n + "_x", v.x), name(n + "_y", v.y)};
  }

  // A point's position in the reference frame, from any located body that carries it.
  Vec point(const std::string& point_name) {
    if (auto it = points_.find(point_name); it != points_.end()) return it->second;
    for (size_t b = 0; b < model_.bodies.size(); ++b) {
      if (!frames_[b].located || !model_.bodies[b].find_point(point_name)) continue;
      const Vec v =
          name(ref_prefix_ + point_name, frames_[b].place(local(static_cast<int>(b), point_name)));
      return points_[point_name] = v;
    }
    throw std::logic_error("point '" + point_name + "' is not located yet");
  }

  // A located line of a joint (fixed in its first body): a point on it and its unit direction.
  void line(const Joint& j, Vec& origin, Vec& unit) {
    Frame& f = frame(j.first);
    const Vec dir{j.line.direction.x.ex, j.line.direction.y.ex};
    const ex length = GiNaC::sqrt(dot(dir, dir));
    origin = name(ref_prefix_ + j.name + "_o", f.place({j.line.through.x.ex, j.line.through.y.ex}));
    unit = name(ref_prefix_ + j.name + "_u", f.rotate((1 / length) * dir));
  }

  // Rotation of a body turned by `angle` (with time derivative `rate`) from frame f.
  void turn(Frame& b, const Frame& f, const ex& angle, const ex& rate, const std::string& n) {
    const ex ca = name("c_" + n + "_rel", cos(angle)), sa = name("s_" + n + "_rel", sin(angle));
    if (GiNaC::is_a<GiNaC::symbol>(ca) && p_.is_defined(GiNaC::ex_to<GiNaC::symbol>(ca))) {
      // Through the names: d/dt cos(a) = -sin(a) a_d, written with the name of sin(a).
      p_.set_derivative(GiNaC::ex_to<GiNaC::symbol>(ca), -sa * rate);
      p_.set_derivative(GiNaC::ex_to<GiNaC::symbol>(sa), ca * rate);
    }
    b.c = name("c_" + n, f.c * ca - f.s * sa);
    b.s = name("s_" + n, f.s * ca + f.c * sa);
    b.w = name("w_" + n, f.w + rate);
  }

  // Rotation of body b from the vector between two of its points, given in both frames.
  void orient(int b, const Vec& ref_vector, const Vec& body_vector) {
    Frame& f = frame(b);
    const std::string& n = body(b).name;
    const ex len2 = dot(body_vector, body_vector);
    f.c = name("c_" + n, dot(ref_vector, body_vector) / len2);
    f.s = name("s_" + n, cross(body_vector, ref_vector) / len2);
    f.w = name("w_" + n, f.c * p_.derivative(f.s) - f.s * p_.derivative(f.c));
  }

  // Places body b's origin so that its point `at` (local coordinates) lies at `where`.
  void locate(int b, const std::string& at, const Vec& where) {
    Frame& f = frame(b);
    const Vec origin = where - f.rotate(local(b, at));
    f.x = name("x_" + body(b).name, origin.x);
    f.y = name("y_" + body(b).name, origin.y);
    f.located = true;
  }

  // Chooses the sign of a branch: the one whose body angles (computed numerically at the first
  // sample) are closest to the assembled configuration.
  int choose_branch(const std::vector<int>& bodies, const std::vector<std::pair<ex, ex>>& plus,
                    const std::vector<std::pair<ex, ex>>& minus, const std::string& group) {
    const double ref_th = pose_[static_cast<size_t>(plan_.reference)].th;
    double err_plus = 0, err_minus = 0;
    std::vector<double> ground_plus, ground_minus;
    for (size_t i = 0; i < bodies.size(); ++i) {
      const double target = pose_[static_cast<size_t>(bodies[i])].th - ref_th;
      const double th_p = std::atan2(p_.value(plus[i].second, 0), p_.value(plus[i].first, 0));
      const double th_m = std::atan2(p_.value(minus[i].second, 0), p_.value(minus[i].first, 0));
      err_plus += std::abs(wrap(th_p - target));
      err_minus += std::abs(wrap(th_m - target));
      ground_plus.push_back(wrap(th_p + ref_th));
      ground_minus.push_back(wrap(th_m + ref_th));
    }
    if (!(err_plus < 0.5 || err_minus < 0.5) || std::isnan(err_plus) || std::isnan(err_minus))
      throw std::runtime_error(group + ": neither branch matches the assembled configuration");
    const int sign = err_plus <= err_minus ? 1 : -1;
    out_.notes.push_back(group + ": branch " + (sign > 0 ? "+1" : "-1"));
    out_.branches.push_back({group, sign, bodies, sign > 0 ? ground_plus : ground_minus,
                             sign > 0 ? ground_minus : ground_plus});
    return sign;
  }

  // A square root whose derivative is written with its own name.
  ex root_of(const std::string& n, const ex& disc) {
    const GiNaC::symbol root = p_.define(n, sqrt(disc));
    p_.set_derivative(root, p_.derivative(disc) / (2 * root));
    return root;
  }

  // Intersection of the circle |X - center|^2 = r2 with the line origin + lambda unit: returns
  // w.u and the root of the discriminant, lambda = -w.u +- root.
  ex circle_line(const std::string& g, int gi, const Vec& center, const ex& r2, const Vec& origin,
                 const Vec& unit, ex& root) {
    const Vec w = name(g + "_w", origin - center);
    const ex wu = name(g + "_wu", dot(w, unit));
    const ex disc = name(g + "_disc", wu * wu - dot(w, w) + r2);
    p_.check_positive(GiNaC::ex_to<GiNaC::symbol>(disc), "unreachable", gi);
    root = root_of(g + "_root", disc);
    return wu;
  }

  // Body b turns about its located pin `hinge` so that the located point `target` lies on the
  // line (origin, unit) of b's own frame, at the located distance |target - hinge| from the
  // hinge: circle-line in b's frame, the branch picked from the assembly.
  void turn_about_pin_to_line(const std::string& gn, int gi, int b, const std::string& hinge,
                              const std::string& target, const Vec& origin, const Vec& unit) {
    const Vec pa = point(hinge);
    const Vec ref_vector = name(gn + "_ap", point(target) - pa);
    const Vec center = local(b, hinge);
    ex root;
    const ex wu = circle_line(gn, gi, center, dot(ref_vector, ref_vector), origin, unit, root);
    auto rot = [&](int sign) {
      const Vec v = origin + (-wu + sign * root) * unit - center;
      return std::pair<ex, ex>{dot(ref_vector, v), cross(v, ref_vector)};
    };
    const int sign = choose_branch({b}, {rot(1)}, {rot(-1)}, gn);
    const ex lambda = name(gn + "_lambda", -wu + sign * root);
    orient(b, ref_vector, origin + lambda * unit - center);
    locate(b, hinge, pa);
  }

  // Two bodies turning about located pins p1 (b1's point at1) and p2 (b2's point at2) meet at a
  // common point `meet_name`: v1, v2 are the vectors from each pin to it in each body's frame.
  void circle_circle(const std::string& gn, int gi, int b1, const std::string& at1, const Vec& v1,
                     int b2, const std::string& at2, const Vec& v2, const std::string& meet_name) {
    const Vec p1 = point(at1), p2 = point(at2);
    const Vec d = name(gn + "_d", p2 - p1);
    const ex d2 = name(gn + "_d2", dot(d, d));
    p_.check_positive(GiNaC::ex_to<GiNaC::symbol>(d2), "singular", gi);
    const ex e = name(gn + "_e", (d2 + dot(v1, v1) - dot(v2, v2)) / 2);
    const ex disc = name(gn + "_disc", dot(v1, v1) * d2 - e * e);
    p_.check_positive(GiNaC::ex_to<GiNaC::symbol>(disc), "unreachable", gi);
    const ex root = root_of(gn + "_root", disc);
    auto meet = [&](int sign) {
      return p1 + (1 / d2) * Vec{e * d.x - sign * root * d.y, e * d.y + sign * root * d.x};
    };
    auto rot = [&](const Vec& u, const Vec& v) {
      return std::pair<ex, ex>{dot(u, v), cross(v, u)};
    };
    const Vec qp = meet(1), qm = meet(-1);
    const int sign = choose_branch({b1, b2}, {rot(qp - p1, v1), rot(qp - p2, v2)},
                                   {rot(qm - p1, v1), rot(qm - p2, v2)}, gn);
    const Vec q = name(ref_prefix_ + meet_name, meet(sign));
    points_[meet_name] = q;
    const bool rigid = p_.derivative(v1.x).is_zero() && p_.derivative(v1.y).is_zero() &&
                       p_.derivative(v2.x).is_zero() && p_.derivative(v2.y).is_zero();
    if (!rigid) {  // a pin vector that changes with time (a cylinder's length): differentiate
      orient(b1, q - p1, v1);
      locate(b1, at1, p1);
      orient(b2, q - p2, v2);
      locate(b2, at2, p2);
      return;
    }
    dyad_rates(gn, b1, p1, v1, b2, p2, v2, q);
    locate(b1, at1, p1);
    locate(b2, at2, p2);
  }

  // Angular velocities and accelerations of an RRR dyad from its differentiated loop closure
  // instead of differentiating the closed form (its square root) twice: fewer operations and
  // shorter dependency chains. Both bodies turn about their pins P1, P2 and share Q, so with
  // r_i = Q - P_i and k x r = (-r_y, r_x):  P1' + w1 k x r1 = P2' + w2 k x r2.  Dotting with r2
  // and with r1 gives w1 = u.r2 / (r1 x r2), w2 = u.r1 / (r1 x r2), u = P2' - P1'; the
  // accelerations have the same matrix, with u'' = P2'' - P1'' + w1^2 r1 - w2^2 r2.
  // Assumption: v1, v2 are fixed in their bodies; r1 x r2 = 0 only where the dyad folds flat,
  // i.e. where its discriminant is 0, which the group's check excludes.
  void dyad_rates(const std::string& gn, int b1, const Vec& p1, const Vec& v1, int b2,
                  const Vec& p2, const Vec& v2, const Vec& q) {
    const Vec r1 = q - p1, r2 = q - p2;
    const Vec u{p_.derivative(p2.x - p1.x), p_.derivative(p2.y - p1.y)};
    const Vec a12{p_.derivative(u.x), p_.derivative(u.y)};
    const ex inv = name(gn + "_inv", 1 / cross(r1, r2));
    Frame &f1 = frame(b1), &f2 = frame(b2);
    const std::string &n1 = body(b1).name, &n2 = body(b2).name;
    const GiNaC::symbol w1 = p_.define("w_" + n1, dot(u, r2) * inv);
    const GiNaC::symbol w2 = p_.define("w_" + n2, dot(u, r1) * inv);
    const Vec acc = name(gn + "_acc", a12 + (w1 * w1) * r1 - (w2 * w2) * r2);
    p_.set_derivative(w1, dot(acc, r2) * inv);
    p_.set_derivative(w2, dot(acc, r1) * inv);
    // Q moves with body 1 about P1.
    p_.set_derivative(GiNaC::ex_to<GiNaC::symbol>(q.x), p_.derivative(p1.x) - w1 * r1.y);
    p_.set_derivative(GiNaC::ex_to<GiNaC::symbol>(q.y), p_.derivative(p1.y) + w1 * r1.x);
    auto rotation = [&](Frame& f, const std::string& n, const GiNaC::symbol& w, const Vec& r,
                        const Vec& v) {
      const ex len2 = dot(v, v);
      const GiNaC::symbol c = p_.define("c_" + n, dot(r, v) / len2);
      const GiNaC::symbol s = p_.define("s_" + n, cross(v, r) / len2);
      p_.set_derivative(c, -s * w);
      p_.set_derivative(s, c * w);
      f.c = c;
      f.s = s;
      f.w = w;
    };
    rotation(f1, n1, w1, r1, v1);
    rotation(f2, n2, w2, r2, v2);
  }

  void solve_group(const SolveGroup& g, int gi) {
    const std::string& gn = g.name;
    switch (g.kind) {
      case GroupKind::driven_revolute: {
        const Joint& j = joint(g.joints[0]);
        const int b = g.bodies[0];
        const int k = j.first == b ? j.second : j.first;
        const auto& in = out_.driver_inputs[static_cast<size_t>(g.driver)];
        const ex sign = j.second == b ? 1 : -1;
        const Vec at = point(j.point);
        turn(frame(b), frame(k), sign * in.q, sign * in.qd, body(b).name);
        locate(b, j.point, at);
        break;
      }
      case GroupKind::driven_prismatic: {
        const Joint& j = joint(g.joints[0]);
        const int b = g.bodies[0];
        const auto& in = out_.driver_inputs[static_cast<size_t>(g.driver)];
        Vec origin, unit;
        line(j, origin, unit);
        turn(frame(b), frame(j.first), j.angle.ex, 0, body(b).name);
        locate(b, j.point, origin + in.q * unit);
        break;
      }
      case GroupKind::rrr: {
        const int b1 = g.bodies[0], b2 = g.bodies[1];
        const Joint &j1 = joint(g.joints[0]), &j12 = joint(g.joints[1]), &j2 = joint(g.joints[2]);
        const Vec v1 = local(b1, j12.point) - local(b1, j1.point);
        const Vec v2 = local(b2, j12.point) - local(b2, j2.point);
        circle_circle(gn, gi, b1, j1.point, v1, b2, j2.point, v2, j12.point);
        break;
      }
      case GroupKind::rpr: {
        // The cylinder's pin distance from its located pin B (on c1) to the link's pin C (on c2)
        // is a function of the driven length: a triangle with the link's A-C.
        const int link = g.bodies[0], c1 = g.bodies[1], c2 = g.bodies[2];
        const Joint &hinge = joint(g.joints[0]), &base = joint(g.joints[1]);
        const Joint &jp = joint(g.joints[2]), &tip = joint(g.joints[3]);
        const ex q = out_.driver_inputs[static_cast<size_t>(g.driver)].q;
        const Vec dir{jp.line.direction.x.ex, jp.line.direction.y.ex};
        const Vec along =
            Vec{jp.line.through.x.ex, jp.line.through.y.ex} + (q / sqrt(dot(dir, dir))) * dir;
        Frame relative;  // the slider's frame (jp.second) in the carrier's frame (jp.first)
        relative.c = cos(jp.angle.ex);
        relative.s = sin(jp.angle.ex);
        Vec pin_vector;  // from B to C, in c1's frame
        if (c1 == jp.first) {
          pin_vector = along + relative.rotate(local(c2, tip.point) - local(c2, jp.point)) -
                       local(c1, base.point);
        } else {
          const Vec in_c2 = local(c2, tip.point) - along -
                            relative.rotate(local(c1, base.point) - local(c1, jp.point));
          pin_vector = {relative.c * in_c2.x + relative.s * in_c2.y,
                        -relative.s * in_c2.x + relative.c * in_c2.y};
        }
        const Vec v1 = local(link, tip.point) - local(link, hinge.point);
        const Vec v2 = name(gn + "_v", pin_vector);
        circle_circle(gn, gi, link, hinge.point, v1, c1, base.point, v2, tip.point);
        const ex sign = c1 == jp.first ? 1 : -1;
        turn(frame(c2), frame(c1), sign * jp.angle.ex, 0, body(c2).name);
        locate(c2, tip.point, point(tip.point));
        break;
      }
      case GroupKind::slot_on_body: {
        // In the body's own frame: its pin A is fixed and the located pin P lies on its line at
        // the located distance |P - A| from A (circle-line in the body frame).
        const int b = g.bodies[0];
        const Joint &pin = joint(g.joints[0]), &slot = joint(g.joints[1]);
        const Vec dir{slot.line.direction.x.ex, slot.line.direction.y.ex};
        turn_about_pin_to_line(gn, gi, b, pin.point, slot.point,
                               {slot.line.through.x.ex, slot.line.through.y.ex},
                               (1 / sqrt(dot(dir, dir))) * dir);
        break;
      }
      case GroupKind::passive_rpr: {
        // In the link's frame (the link carries the slide's line) the block's pin P runs on a
        // line, the slide shifted by P's offset from the slider point, and the link's hinge A is
        // fixed: circle-line at the located distance |P - A|, as for a slot on the body. The
        // block keeps the joint's angle to the link.
        const int link = g.bodies[0], block = g.bodies[1];
        const Joint &hinge = joint(g.joints[0]), &jp = joint(g.joints[1]),
                    &pin = joint(g.joints[2]);
        const Vec dir{jp.line.direction.x.ex, jp.line.direction.y.ex};
        Frame relative;  // the block's frame in the link's frame
        relative.c = cos(jp.angle.ex);
        relative.s = sin(jp.angle.ex);
        const Vec origin = Vec{jp.line.through.x.ex, jp.line.through.y.ex} +
                           relative.rotate(local(block, pin.point) - local(block, jp.point));
        turn_about_pin_to_line(gn, gi, link, hinge.point, pin.point, origin,
                               (1 / sqrt(dot(dir, dir))) * dir);
        turn(frame(block), frame(link), jp.angle.ex, 0, body(block).name);
        locate(block, pin.point, point(pin.point));
        break;
      }
      case GroupKind::prp: {
        // Both bodies keep their lines' orientations: their common pin C runs on two located
        // lines (each shifted by C's offset from the slider point), and meets at their crossing.
        const int b1 = g.bodies[0], b2 = g.bodies[1];
        const Joint &s1 = joint(g.joints[0]), &mid = joint(g.joints[1]), &s2 = joint(g.joints[2]);
        Vec o1, u1, o2, u2;
        line(s1, o1, u1);
        line(s2, o2, u2);
        turn(frame(b1), frame(s1.first), s1.angle.ex, 0, body(b1).name);
        turn(frame(b2), frame(s2.first), s2.angle.ex, 0, body(b2).name);
        o1 = o1 + frame(b1).rotate(local(b1, mid.point) - local(b1, s1.point));
        o2 = o2 + frame(b2).rotate(local(b2, mid.point) - local(b2, s2.point));
        const ex crossing = name(gn + "_cross", cross(u1, u2));
        p_.check_nonzero(GiNaC::ex_to<GiNaC::symbol>(crossing), "singular", gi);
        const ex lambda = name(gn + "_lambda", cross(o2 - o1, u2) / crossing);
        const Vec c = name(ref_prefix_ + mid.point, o1 + lambda * u1);
        points_[mid.point] = c;
        locate(b1, mid.point, c);
        locate(b2, mid.point, c);
        break;
      }
      case GroupKind::r_slot:
      case GroupKind::rrp: {
        // One body (b1) turns about a located pin p1; a point of it (q) runs on a located line.
        const bool dyad = g.kind == GroupKind::rrp;
        const int b1 = g.bodies[0];
        const Joint& j1 = joint(g.joints[0]);
        const Joint& slide = joint(g.joints[dyad ? 2 : 1]);
        const std::string q_name = dyad ? joint(g.joints[1]).point : slide.point;
        const Vec p1 = point(j1.point);
        const Vec v1 = local(b1, q_name) - local(b1, j1.point);
        Vec origin, unit;
        line(slide, origin, unit);
        int b2 = -1;
        if (dyad) {  // the slider's orientation is fixed: q runs on a parallel line
          b2 = g.bodies[1];
          turn(frame(b2), frame(slide.first), slide.angle.ex, 0, body(b2).name);
          origin = origin + frame(b2).rotate(local(b2, q_name) - local(b2, slide.point));
        }
        ex root;
        const ex wu = circle_line(gn, gi, p1, dot(v1, v1), origin, unit, root);
        auto meet = [&](int sign) { return origin + (-wu + sign * root) * unit; };
        auto rot = [&](const Vec& u) { return std::pair<ex, ex>{dot(u, v1), cross(v1, u)}; };
        const int sign = choose_branch({b1}, {rot(meet(1) - p1)}, {rot(meet(-1) - p1)}, gn);
        const ex lambda = name(gn + "_lambda", -wu + sign * root);
        const Vec q = name(ref_prefix_ + q_name, origin + lambda * unit);
        points_[q_name] = q;
        orient(b1, q - p1, v1);
        locate(b1, j1.point, p1);
        if (dyad) locate(b2, q_name, q);
        break;
      }
      case GroupKind::iterative:
        solve_iterative(g, gi);
        break;
    }
  }

  // No closed form: Newton-Raphson on the group's body angles in the reference frame, unrolled
  // for a fixed number of iterations (straight-line code, nothing that can hang) from the warm
  // start kept in the kernel's state (the assembly by default). The positions follow from the
  // angles along a tree of revolute joints; the other joints give as many equations as angles.
  // Velocities and accelerations by implicit differentiation: J phi_d = -dF/dt at fixed angles,
  // solved with Cramer's rule (the groups are small), then differentiated again by the staged
  // chain rule.
  static constexpr int kNewtonIterations = 10;  // assumption: quadratic convergence from a start
                                                // within ~0.5 rad needs fewer

  // Cramer's rule for a small dense system: the numerators of x = J^-1 r, and det J.
  static std::vector<ex> cramer(const std::vector<std::vector<ex>>& jac, const std::vector<ex>& r,
                                ex& det) {
    const size_t k = r.size();
    GiNaC::matrix m(static_cast<unsigned>(k), static_cast<unsigned>(k));
    for (size_t i = 0; i < k; ++i)
      for (size_t j = 0; j < k; ++j)
        m(static_cast<unsigned>(i), static_cast<unsigned>(j)) = jac[i][j];
    det = m.determinant();
    std::vector<ex> numerators;
    for (size_t c = 0; c < k; ++c) {
      GiNaC::matrix mc = m;
      for (size_t i = 0; i < k; ++i) mc(static_cast<unsigned>(i), static_cast<unsigned>(c)) = r[i];
      numerators.push_back(mc.determinant());
    }
    return numerators;
  }

  void solve_iterative(const SolveGroup& g, int gi) {
    const std::string& gn = g.name;
    const size_t k = g.bodies.size();
    std::vector<GiNaC::symbol> psi;  // placeholders for the unknown angles
    for (size_t i = 0; i < k; ++i) {
      psi.emplace_back(gn + "_psi" + std::to_string(i));
      p_.declare(psi.back(), 0);
    }
    // The group's bodies as functions of the placeholders, along the tree.
    std::map<int, Frame> trial;
    auto frame_of = [&](int b) -> const Frame& {
      auto it = trial.find(b);
      return it != trial.end() ? it->second : frame(b);
    };
    auto at = [&](int b, const std::string& pt) {
      return trial.count(b) ? frame_of(b).place(local(b, pt)) : point(pt);
    };
    ex scale2 = 0;  // a squared length of the group, for the convergence test
    for (size_t i = 0; i < k; ++i) {
      const int b = g.bodies[i];
      const Joint& j = joint(g.joints[i]);
      const Vec pin = at(j.first == b ? j.second : j.first, j.point);
      Frame f;
      f.c = cos(psi[i]);
      f.s = sin(psi[i]);
      const Vec origin = pin - f.rotate(local(b, j.point));
      f.x = origin.x;
      f.y = origin.y;
      trial[b] = f;
      scale2 += dot(local(b, j.point), local(b, j.point));
    }
    std::vector<ex> residual;
    for (size_t n = k; n < g.joints.size(); ++n) {
      const Joint& j = joint(g.joints[n]);
      const Vec p2 = at(j.second, j.point);
      scale2 += dot(local(j.second, j.point), local(j.second, j.point));
      if (j.type == JointType::revolute) {
        const Vec gap = at(j.first, j.point) - p2;
        residual.push_back(gap.x);
        residual.push_back(gap.y);
        continue;
      }
      const Frame& f1 = frame_of(j.first);
      const Vec dir{j.line.direction.x.ex, j.line.direction.y.ex};
      const Vec unit = f1.rotate((1 / sqrt(dot(dir, dir))) * dir);
      residual.push_back(cross(unit, p2 - f1.place({j.line.through.x.ex, j.line.through.y.ex})));
      if (j.type == JointType::prismatic) {
        const Frame& f2 = frame_of(j.second);
        const ex sin_rel = f2.s * f1.c - f2.c * f1.s, cos_rel = f2.c * f1.c + f2.s * f1.s;
        residual.push_back(sin_rel * cos(j.angle.ex) - cos_rel * sin(j.angle.ex));
      }
    }
    if (residual.size() != k)
      throw std::runtime_error(gn + ": " + std::to_string(residual.size()) + " equations for " +
                               std::to_string(k) + " angles");
    std::vector<std::vector<ex>> jac(k, std::vector<ex>(k));
    for (size_t r = 0; r < k; ++r)
      for (size_t c = 0; c < k; ++c) jac[r][c] = residual[r].diff(psi[c]);

    // Newton-Raphson, unrolled.
    std::vector<ex> current;
    const double ref_th = pose_[static_cast<size_t>(plan_.reference)].th;
    for (size_t i = 0; i < k; ++i) {
      const int b = g.bodies[i];
      const std::string field = gn + "_" + body(b).name;
      const double hint = wrap(pose_[static_cast<size_t>(b)].th - ref_th);
      const GiNaC::symbol start("s.warm." + field);
      p_.declare(start, 0, hint);
      current.push_back(start);
      out_.warm_start.push_back({field, hint});
    }
    auto at_current = [&](const ex& e) {
      GiNaC::exmap values;
      for (size_t i = 0; i < k; ++i) values[psi[i]] = current[i];
      return e.subs(values);
    };
    for (int it = 1; it <= kNewtonIterations; ++it) {
      const std::string tag = gn + "_n" + std::to_string(it);
      std::vector<ex> f(k);
      std::vector<std::vector<ex>> jn(k, std::vector<ex>(k));
      for (size_t r = 0; r < k; ++r) {
        f[r] = name(tag + "_F" + std::to_string(r), at_current(residual[r]));
        for (size_t c = 0; c < k; ++c)
          jn[r][c] =
              name(tag + "_J" + std::to_string(r) + std::to_string(c), at_current(jac[r][c]));
      }
      ex det;
      const std::vector<ex> numerators = cramer(jn, f, det);
      det = name(tag + "_det", det);
      if (GiNaC::is_a<GiNaC::symbol>(det) && p_.is_defined(GiNaC::ex_to<GiNaC::symbol>(det)))
        p_.check_nonzero(GiNaC::ex_to<GiNaC::symbol>(det), "singular", gi);
      for (size_t i = 0; i < k; ++i)
        current[i] = name(gn + "_" + body(g.bodies[i]).name + "_n" + std::to_string(it),
                          current[i] - numerators[i] / det);
    }
    // Converged: |F|^2 below (1e-5 of the group's size)^2, loose enough for float kernels.
    ex residual2 = 0;
    for (const ex& r : residual) residual2 += pow(at_current(r), 2);
    const ex margin = name(gn + "_converged", 1e-10 * scale2 - residual2);
    p_.check_positive_kept(GiNaC::ex_to<GiNaC::symbol>(margin), "unreachable", gi);

    // Implicit derivatives: J phi_d = -dF/dt with the angles held.
    std::vector<ex> rate_rhs(k);
    std::vector<std::vector<ex>> jf(k, std::vector<ex>(k));
    for (size_t r = 0; r < k; ++r) {
      rate_rhs[r] = name(gn + "_Ft" + std::to_string(r), -at_current(p_.derivative(residual[r])));
      for (size_t c = 0; c < k; ++c)
        jf[r][c] = name(gn + "_J" + std::to_string(r) + std::to_string(c), at_current(jac[r][c]));
    }
    ex det;
    const std::vector<ex> numerators = cramer(jf, rate_rhs, det);
    det = name(gn + "_det", det);
    if (GiNaC::is_a<GiNaC::symbol>(det) && p_.is_defined(GiNaC::ex_to<GiNaC::symbol>(det)))
      p_.check_nonzero(GiNaC::ex_to<GiNaC::symbol>(det), "singular", gi);  // a locked triad
    for (size_t i = 0; i < k; ++i) {
      const int b = g.bodies[i];
      const std::string& bn = body(b).name;
      const ex rate = name(gn + "_" + bn + "_rate", numerators[i] / det);
      const GiNaC::symbol angle = GiNaC::ex_to<GiNaC::symbol>(current[i]);
      p_.set_derivative(angle, rate);
      out_.kinematics.push_back({"s.warm." + gn + "_" + bn, angle});
      Frame& f = frame(b);
      f.c = name("c_" + bn, cos(angle));
      f.s = name("s_" + bn, sin(angle));
      p_.set_derivative(GiNaC::ex_to<GiNaC::symbol>(f.c), -f.s * rate);
      p_.set_derivative(GiNaC::ex_to<GiNaC::symbol>(f.s), f.c * rate);
      f.w = rate;
      const Joint& j = joint(g.joints[i]);
      locate(b, j.point, point(j.point));
    }
    out_.notes.push_back(gn + ": iterative, " + std::to_string(kNewtonIterations) +
                         " Newton-Raphson steps on " + std::to_string(k) +
                         " angles from the previous state (assembly by default)");
  }

  // ---- placement on the ground body (the seed's eq. 11 when the reference is not the ground)
  bool moved() const { return plan_.reference != model_.ground; }

  Vec world_point(const std::string& n) {
    if (!moved()) return point(n);
    if (auto it = world_points_.find(n); it != world_points_.end()) return it->second;
    return world_points_[n] = placed(n, point(n));
  }

  // A reference-frame point r placed on the ground body G and named n: X = G^T (r - o_G). Its
  // derivatives reuse X instead of differentiating the product: d/dt G^T = w_G J G^T with
  // J (x, y) = (y, -x), so X' = Y + w_G J X with Y = G^T (r - o_G)', and Y' = G^T (r - o_G)'' +
  // w_G J Y (fewer operations than the product rule through G's cos and sin twice).
  Vec placed(const std::string& n, const Vec& r) {
    if (!moved()) return name(n, r);
    const Frame& g = frame(model_.ground);
    auto rotate_back = [&](const Vec& v) {
      return Vec{g.c * v.x + g.s * v.y, g.c * v.y - g.s * v.x};
    };
    const Vec d{r.x - g.x, r.y - g.y};
    const Vec d1{p_.derivative(d.x), p_.derivative(d.y)};
    const Vec d2{p_.derivative(d1.x), p_.derivative(d1.y)};
    const Vec x = rotate_back(d), y = rotate_back(d1), y1 = rotate_back(d2);
    const GiNaC::symbol xx = p_.define(n + "_x", x.x), xy = p_.define(n + "_y", x.y);
    const GiNaC::symbol yx = p_.define(n + "_vr_x", y.x), yy = p_.define(n + "_vr_y", y.y);
    p_.set_derivative(yx, y1.x + g.w * yy);
    p_.set_derivative(yy, y1.y - g.w * yx);
    p_.set_derivative(xx, yx + g.w * xy);
    p_.set_derivative(xy, yy - g.w * xx);
    return {xx, xy};
  }

  // A body's rotation and angular velocity in the ground frame.
  const Frame& world_frame(int b) {
    if (!moved() || b == model_.ground) return b == model_.ground ? ground_frame_ : frame(b);
    Frame& w = world_[static_cast<size_t>(b)];
    if (w.located) return w;
    const Frame &f = frame(b), &g = frame(model_.ground);
    const std::string& n = body(b).name;
    w.c = name("cw_" + n, f.c * g.c + f.s * g.s);
    w.s = name("sw_" + n, f.s * g.c - f.c * g.s);
    w.w = name("ww_" + n, f.w - g.w);
    w.located = true;
    return w;
  }

  // ---- outputs named as in the CSV contract
  void emit(std::vector<Output>& to, const std::string& target, const ex& value) {
    to.push_back({target, value});
  }

  void kinematic_outputs() {
    for (size_t d = 0; d < model_.drivers.size(); ++d) {
      const auto& in = out_.driver_inputs[d];
      const std::string t = "s.drivers." + model_.drivers[d].name + ".";
      emit(out_.kinematics, t + "q", in.q);
      emit(out_.kinematics, t + "qd", in.qd);
      emit(out_.kinematics, t + "qdd", in.qdd);
    }
    for (size_t b = 0; b < model_.bodies.size(); ++b) {
      if (static_cast<int>(b) == model_.ground) continue;
      const Body& B = model_.bodies[b];
      const Frame& w = world_frame(static_cast<int>(b));
      const Vec com = placed("com_" + B.name,
                             frame(static_cast<int>(b)).place({B.mass.com.x.ex, B.mass.com.y.ex}));
      const Vec v{p_.derivative(com.x), p_.derivative(com.y)};
      const Vec a{p_.derivative(v.x), p_.derivative(v.y)};
      const ex alpha = p_.derivative(w.w);
      com_[b] = com;
      acceleration_[b] = a;
      angular_acceleration_[b] = alpha;
      const std::string t = "s.bodies." + B.name + ".";
      emit(out_.kinematics, t + "x", com.x);
      emit(out_.kinematics, t + "y", com.y);
      emit(out_.kinematics, t + "cos_th", w.c);
      emit(out_.kinematics, t + "sin_th", w.s);
      emit(out_.kinematics, t + "vx", v.x);
      emit(out_.kinematics, t + "vy", v.y);
      emit(out_.kinematics, t + "w", w.w);
      emit(out_.kinematics, t + "ax", a.x);
      emit(out_.kinematics, t + "ay", a.y);
      emit(out_.kinematics, t + "al", alpha);
    }
    for (const auto& [point_name, locator] : model_.named_points()) {
      const Vec r = world_point(point_name);
      const std::string t = "s.points." + point_name + ".";
      const Vec v{p_.derivative(r.x), p_.derivative(r.y)};
      emit(out_.kinematics, t + "x", r.x);
      emit(out_.kinematics, t + "y", r.y);
      emit(out_.kinematics, t + "vx", v.x);
      emit(out_.kinematics, t + "vy", v.y);
      emit(out_.kinematics, t + "ax", p_.derivative(v.x));
      emit(out_.kinematics, t + "ay", p_.derivative(v.y));
    }
  }

  // ---- Newton-Euler: A x = b, every joint reaction and driver effort unknown
  struct Load {  // one unknown's (or a known load's) force and moment on a body
    Vec force;
    Vec at;
    ex moment;
  };

  void add_load(std::vector<std::map<int, ex>>& rows, std::vector<ex>& rhs, int b, int col,
                const Load& load, int sign) {
    const int base = row_of_[static_cast<size_t>(b)];
    if (base < 0) return;  // the ground's equations are not part of the system
    const Vec& g = moment_point_[static_cast<size_t>(b)];
    const ex mz = cross(load.at - g, load.force) + load.moment;
    const ex comps[3] = {load.force.x, load.force.y, mz};
    for (int k = 0; k < 3; ++k) {
      if (comps[k].is_zero()) continue;
      if (col >= 0) {
        rows[static_cast<size_t>(base + k)][col] += sign * comps[k];
      } else {
        rhs[static_cast<size_t>(base + k)] -= sign * comps[k];  // a known load moves to b
      }
    }
  }

  Vec world_direction(const Joint& j, bool normal) {
    const Vec dir{j.line.direction.x.ex, j.line.direction.y.ex};
    const ex length = GiNaC::sqrt(dot(dir, dir));
    const Vec unit = normal ? Vec{-dir.y / length, dir.x / length} : (1 / length) * dir;
    return name(j.name + (normal ? "_normal" : "_axis"), world_frame(j.first).rotate(unit));
  }

  void newton_euler() {
    row_of_.assign(model_.bodies.size(), -1);
    int equations = 0;
    for (size_t b = 0; b < model_.bodies.size(); ++b)
      if (static_cast<int>(b) != model_.ground) row_of_[b] = 3 * equations++;
    const int n = 3 * equations;
    std::vector<std::map<int, ex>> rows(static_cast<size_t>(n));
    std::vector<ex> rhs(static_cast<size_t>(n), 0);
    std::vector<std::pair<std::string, std::vector<std::pair<int, Vec>>>> reactions;

    // Each body's moment equation is taken about the pin of its first revolute joint (the COM
    // when it has none): that joint's two reactions drop out of the row, so the elimination
    // couples fewer unknowns; the inertial forces' moment about the pin moves to the rhs.
    moment_point_ = com_;
    for (size_t b = 0; b < model_.bodies.size(); ++b)
      for (const Joint& j : model_.joints)
        if (j.type == JointType::revolute &&
            (j.first == static_cast<int>(b) || j.second == static_cast<int>(b))) {
          moment_point_[b] = world_point(j.point);
          break;
        }

    const Vec gravity{model_.gravity.x.ex, model_.gravity.y.ex};
    for (size_t b = 0; b < model_.bodies.size(); ++b) {
      if (row_of_[b] < 0) continue;
      // Mass and inertia named once: as products of parameters (a bar's density, width,
      // thickness, length) they were repeated in every term that carries them.
      const MassProperties& m = model_.bodies[b].mass;
      const std::string& body_name = model_.bodies[b].name;
      const ex mass = name(body_name + "_mass", m.mass.ex);
      const ex inertia = name(body_name + "_inertia", m.inertia.ex);
      const Vec inertial = name(body_name + "_inertial", mass * (acceleration_[b] - gravity));
      rhs[static_cast<size_t>(row_of_[b])] += inertial.x;
      rhs[static_cast<size_t>(row_of_[b] + 1)] += inertial.y;
      rhs[static_cast<size_t>(row_of_[b] + 2)] +=
          inertia * angular_acceleration_[b] + cross(com_[b] - moment_point_[b], inertial);
    }

    int col = 0;
    for (const Joint& j : model_.joints) {
      const Vec at = world_point(j.point);
      std::vector<std::pair<int, Vec>> components;  // unknown column and its force direction
      if (j.type == JointType::revolute) {
        out_.ne_unknowns.push_back(j.name + ".fx");
        out_.ne_unknowns.push_back(j.name + ".fy");
        components = {{col, {1, 0}}, {col + 1, {0, 1}}};
      } else {
        out_.ne_unknowns.push_back(j.name + ".n");
        components = {{col, world_direction(j, true)}};
      }
      for (const auto& [c, dir] : components) {
        add_load(rows, rhs, j.second, c, {dir, at, 0}, 1);
        add_load(rows, rhs, j.first, c, {dir, at, 0}, -1);
      }
      col += static_cast<int>(components.size());
      if (j.type == JointType::prismatic) {
        out_.ne_unknowns.push_back(j.name + ".m");
        add_load(rows, rhs, j.second, col, {{0, 0}, at, 1}, 1);
        add_load(rows, rhs, j.first, col, {{0, 0}, at, 1}, -1);
        ++col;
      }
      reactions.emplace_back(j.name, components);
    }
    for (const Driver& d : model_.drivers) {
      const Joint& j = joint(d.joint);
      out_.ne_unknowns.push_back(d.name + ".effort");
      const Load load = d.kind == DriverKind::angle
                            ? Load{{0, 0}, {0, 0}, 1}
                            : Load{world_direction(j, false), world_point(j.point), 0};
      add_load(rows, rhs, j.second, col, load, 1);
      add_load(rows, rhs, j.first, col, load, -1);
      ++col;
    }
    if (col != n)
      throw std::runtime_error("Newton-Euler system is not square: " + std::to_string(n) +
                               " equations, " + std::to_string(col) + " unknowns");
    applied_loads(rows, rhs);

    out_.ne_matrix.assign(static_cast<size_t>(n) * static_cast<size_t>(n), 0);
    for (int r = 0; r < n; ++r)
      for (const auto& [c, v] : rows[static_cast<size_t>(r)])
        out_.ne_matrix[static_cast<size_t>(r * n + c)] = v;
    out_.ne_rhs = rhs;

    const std::vector<ex> x = solve_sparse(rows, rhs);
    col = 0;
    for (const auto& [joint_name, components] : reactions) {
      const std::string t = "s.joints." + joint_name + ".";
      if (components.size() == 2) {
        emit(out_.dynamics, t + "fx", x[static_cast<size_t>(col)]);
        emit(out_.dynamics, t + "fy", x[static_cast<size_t>(col + 1)]);
      } else {
        const Vec& dir = components[0].second;
        emit(out_.dynamics, t + "fx", x[static_cast<size_t>(col)] * dir.x);
        emit(out_.dynamics, t + "fy", x[static_cast<size_t>(col)] * dir.y);
      }
      col += static_cast<int>(components.size());
      const Joint& j = model_.joints[static_cast<size_t>(model_joint(joint_name))];
      if (j.type == JointType::prismatic)
        emit(out_.dynamics, t + "m", x[static_cast<size_t>(col++)]);
    }
    for (const Driver& d : model_.drivers)
      emit(out_.dynamics, "s.drivers." + d.name + ".effort", x[static_cast<size_t>(col++)]);
  }

  // ---- structure-aware solve of A x = b: Markowitz pivot order with a stability threshold,
  // chosen on the numeric sample configurations, then unrolled as straight-line code.
  std::vector<ex> solve_sparse(std::vector<std::map<int, ex>> rows, std::vector<ex> rhs) {
    const size_t n = rows.size(), samples = p_.sample_count();
    using Values = std::vector<double>;
    std::vector<std::map<int, Values>> num(n);
    for (size_t r = 0; r < n; ++r)
      for (const auto& [c, e] : rows[r]) {
        Values v(samples);
        for (size_t s = 0; s < samples; ++s) v[s] = p_.value(e, s);
        num[r][c] = v;
      }
    std::vector<bool> row_done(n, false);
    struct Pivot {
      size_t row;
      int col;
      ex value;
    };
    std::vector<Pivot> order;
    int counter = 0;
    auto entry = [&](const ex& value) { return name("ne" + std::to_string(++counter), value); };
    for (size_t step = 0; step < n; ++step) {
      std::map<int, int> col_count;
      std::map<int, Values> col_max;
      for (size_t r = 0; r < n; ++r) {
        if (row_done[r]) continue;
        for (const auto& [c, v] : num[r]) {
          ++col_count[c];
          Values& m = col_max[c];
          m.resize(samples, 0.0);
          for (size_t s = 0; s < samples; ++s) m[s] = std::max(m[s], std::abs(v[s]));
        }
      }
      // Candidates: stable enough on every sample (|a| >= 0.1 max of its column), then the
      // fewest fill-ins, then exact constants (no division at run time), then the most stable.
      bool found = false;
      size_t best_r = 0;
      int best_c = 0;
      std::tuple<long, int, double> best_key{0, 0, 0.0};
      for (size_t r = 0; r < n; ++r) {
        if (row_done[r]) continue;
        for (const auto& [c, v] : num[r]) {
          double ratio = 1;
          for (size_t s = 0; s < samples; ++s) {
            const double m = col_max[c][s];
            ratio = std::min(ratio, m > 0 ? std::abs(v[s]) / m : 0.0);
          }
          if (!(ratio >= 0.1)) continue;
          const long cost = static_cast<long>(rows[r].size() - 1) * (col_count[c] - 1);
          const int variable = GiNaC::is_a<GiNaC::numeric>(rows[r].at(c)) ? 0 : 1;
          const std::tuple<long, int, double> key{cost, variable, -ratio};
          if (!found || key < best_key) {
            found = true;
            best_key = key;
            best_r = r;
            best_c = c;
          }
        }
      }
      if (!found)
        throw std::runtime_error(
            "the Newton-Euler system is singular at the sample configurations (step " +
            std::to_string(step) + " of " + std::to_string(n) + ")");
      const size_t pr = best_r;
      const int pc = best_c;
      ex pivot = rows[pr].at(pc);
      if (!GiNaC::is_a<GiNaC::numeric>(pivot)) {
        pivot = name("ne_pivot" + std::to_string(step + 1), pivot);
        if (GiNaC::is_a<GiNaC::symbol>(pivot) && p_.is_defined(GiNaC::ex_to<GiNaC::symbol>(pivot)))
          p_.check_nonzero(GiNaC::ex_to<GiNaC::symbol>(pivot), "singular", -1);
      }
      row_done[pr] = true;
      order.push_back({pr, pc, pivot});
      const Values& pivot_values = num[pr].at(pc);
      for (size_t r = 0; r < n; ++r) {
        if (row_done[r] || !rows[r].count(pc)) continue;
        const ex factor = name("ne" + std::to_string(++counter), rows[r].at(pc) / pivot);
        Values factor_values(samples);
        for (size_t s = 0; s < samples; ++s) factor_values[s] = num[r].at(pc)[s] / pivot_values[s];
        rows[r].erase(pc);
        num[r].erase(pc);
        for (const auto& [c, e] : rows[pr]) {
          if (c == pc) continue;
          const ex updated = (rows[r].count(c) ? rows[r].at(c) : ex(0)) - factor * e;
          if (updated.is_zero()) {
            rows[r].erase(c);
            num[r].erase(c);
            continue;
          }
          rows[r][c] = entry(updated);
          Values& v = num[r][c];
          v.resize(samples, 0.0);
          for (size_t s = 0; s < samples; ++s) v[s] -= factor_values[s] * num[pr].at(c)[s];
        }
        if (!rhs[pr].is_zero()) rhs[r] = entry(rhs[r] - factor * rhs[pr]);
      }
    }
    std::vector<ex> x(n);
    for (auto it = order.rbegin(); it != order.rend(); ++it) {
      ex sum = rhs[it->row];
      for (const auto& [c, e] : rows[it->row])
        if (c != it->col) sum -= e * x[static_cast<size_t>(c)];
      std::string unknown = out_.ne_unknowns[static_cast<size_t>(it->col)];
      for (char& ch : unknown)
        if (ch == '.') ch = '_';
      x[static_cast<size_t>(it->col)] = name(unknown, sum / it->value);
    }
    return x;
  }

  int model_joint(const std::string& joint_name) const {
    for (size_t j = 0; j < model_.joints.size(); ++j)
      if (model_.joints[j].name == joint_name) return static_cast<int>(j);
    return -1;
  }

  // Springs, dampers, forces and torques: known loads, moved to the right-hand side.
  void applied_loads(std::vector<std::map<int, ex>>& rows, std::vector<ex>& rhs) {
    for (const ForceElement& f : model_.forces) {
      if (f.type == ForceType::spring_damper) {
        const Vec pa = world_point(f.point_a), pb = world_point(f.point_b);
        const Vec d = name(f.name + "_d", pb - pa);
        const ex length = root_of(f.name + "_length", dot(d, d));
        const ex rate = dot(d, {p_.derivative(d.x), p_.derivative(d.y)}) / length;
        const ex tension = name(f.name + "_tension",
                                f.stiffness.ex * (length - f.free_length.ex) + f.damping.ex * rate);
        const Vec on_b = (-tension / length) * d;
        add_load(rows, rhs, f.body_b, -1, {on_b, pb, 0}, 1);
        add_load(rows, rhs, f.body_a, -1, {on_b, pa, 0}, -1);
      } else if (f.type == ForceType::force) {
        add_load(rows, rhs, f.body_a, -1, {{f.force.x.ex, f.force.y.ex}, world_point(f.point_a), 0},
                 1);
      } else {
        add_load(rows, rhs, f.body_a, -1, {{0, 0}, {0, 0}, f.torque.ex}, 1);
      }
    }
  }

  const Model& model_;
  const SolvePlan& plan_;
  const std::vector<BodyPose>& pose_;
  StagedProgram& p_;
  Derivation& out_;
  std::vector<Frame> frames_;
  std::map<std::string, Vec> points_;
  std::string ref_prefix_;  // names of reference-frame quantities, when it is not the ground frame
  std::map<std::string, Vec> world_points_;
  std::vector<Frame> world_;  // body rotations in the ground frame (when it is not the reference)
  Frame ground_frame_{true, 0, 0, 1, 0, 0};
  std::vector<Vec> com_, acceleration_;
  std::vector<Vec> moment_point_;  // the point each body's moment equation is taken about
  std::vector<ex> angular_acceleration_;
  std::vector<int> row_of_;
};

}  // namespace

std::vector<Derivation::DriverInputs> make_driver_inputs(const Model& model) {
  std::vector<Derivation::DriverInputs> inputs;
  for (const Driver& d : model.drivers)
    inputs.push_back({GiNaC::symbol("in." + d.name), GiNaC::symbol("in." + d.name + "_d"),
                      GiNaC::symbol("in." + d.name + "_dd")});
  return inputs;
}

std::vector<GiNaC::exmap> make_samples(const Model& model,
                                       const std::vector<Derivation::DriverInputs>& inputs,
                                       const std::vector<double>& times) {
  const GiNaC::exmap params = model.substitutions(model.default_parameters());
  std::vector<GiNaC::exmap> samples;
  for (const double t : times) {
    GiNaC::exmap sample = params;
    sample[model.t] = t;
    GiNaC::exmap with_t = params;
    with_t[model.t] = t;
    for (size_t d = 0; d < model.drivers.size(); ++d) {
      const Driver& driver = model.drivers[d];
      sample[inputs[d].q] = model.evaluate(driver.value, with_t);
      sample[inputs[d].qd] =
          model.evaluate({driver.value_d, driver.value.text, driver.loc}, with_t);
      sample[inputs[d].qdd] =
          model.evaluate({driver.value_dd, driver.value.text, driver.loc}, with_t);
    }
    samples.push_back(sample);
  }
  return samples;
}

Derivation derive(const Model& model, const SolvePlan& plan, const std::vector<BodyPose>& pose,
                  const std::vector<Derivation::DriverInputs>& inputs, StagedProgram& program) {
  if (!plan.complete())
    throw std::runtime_error("no closed-form solve plan reaches body '" +
                             model.bodies[static_cast<size_t>(plan.unsolved.front())].name + "'");
  Derivation out;
  out.driver_inputs = inputs;
  Deriver(model, plan, pose, program, out).run();
  return out;
}

}  // namespace mechgen::gen
