// An assembled import tree as a spatial description of our graph: bodies joined by fixed joints
// or welded by a closure merged into one, connects (3d closures) as spherical joints, revolutes
// meeting at a point (through massless links) as spherical or universal joints, idle spins
// removed so that the model is exactly determined by its drivers.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>

#include "import/import_tree.hpp"
#include "model/description_syntax.hpp"
#include "model/idle_spin.hpp"

namespace mechgen::import {

namespace {

constexpr double kTiny = 1e-9;  // m, rad: points and axes that coincide after assembly

std::string fmt(double v) {
  std::ostringstream o;
  o.precision(6);
  o << v;
  return o.str();
}

// Distance between two lines (point, unit direction); parallel lines: their separation.
double line_distance(const Vec3& p1, const Vec3& d1, const Vec3& p2, const Vec3& d2) {
  const Vec3 n = d1.cross(d2);
  if (n.norm() < 1e-12) return (p2 - p1 - d1 * d1.dot(p2 - p1)).norm();
  return std::abs((p2 - p1).dot(n.normalized()));
}

// The point of line 1 closest to line 2.
Vec3 closest_point(const Vec3& p1, const Vec3& d1, const Vec3& p2, const Vec3& d2) {
  const Vec3 w = p1 - p2;
  const double b = d1.dot(d2), d = d1.dot(w), e = d2.dot(w);
  const double den = 1 - b * b;
  if (den < 1e-12) return p1;
  return p1 + d1 * ((b * e - d) / den);
}

class Builder {
 public:
  Builder(const Tree& tree, const TreePose& pose, bool floating)
      : tree_(tree), pose_(pose), floating_(floating) {}

  Description run() {
    d_.name = tree_.name;
    d_.source = tree_.source;
    d_.gravity = tree_.gravity;
    d_.step = tree_.step;
    d_.notes = tree_.notes;
    make_bodies();
    make_joints();
    bool changed = true;
    while (changed) {
      changed = false;
      changed = changed || revolute_chains();
      changed = changed || coaxial_spins();
      changed = changed || spherical_spins();
    }
    massless_points();
    for (const Actuator& a : tree_.actuators) {
      const std::string& jn = tree_.joints[static_cast<size_t>(a.joint)].name;
      int k = -1;
      for (size_t i = 0; i < d_.joints.size(); ++i)
        if (d_.joints[i].name == jn) k = static_cast<int>(i);
      if (k < 0)
        throw ImportError(tree_.source, a.line,
                          "actuated joint '" + jn + "' was merged away (it lies inside a weld)");
      d_.drivers.push_back({a.name, k, a.value, a.passive, a.stiffness, a.damping});
    }
    unique_names();
    return d_;
  }

 private:
  int find(int x) {
    return parent_[static_cast<size_t>(x)] == x
               ? x
               : parent_[static_cast<size_t>(x)] = find(parent_[static_cast<size_t>(x)]);
  }

  void make_bodies() {
    const size_t n = tree_.links.size();
    parent_.resize(n);
    std::iota(parent_.begin(), parent_.end(), 0);
    auto unite = [&](int a, int b) {
      a = find(a), b = find(b);
      if (a == b) return;
      if (b < a) std::swap(a, b);
      parent_[static_cast<size_t>(b)] = a;  // the link nearer the root names the body
    };
    int fixed = 0;
    for (const TreeJoint& j : tree_.joints) {
      if (j.floating)
        d_.notes.push_back("free joint " + j.name + " of " +
                           tree_.links[static_cast<size_t>(j.child)].name +
                           (floating_ ? ": a pose driver holds the base at its source pose"
                                      : ": the base is the ground, at its source pose "
                                        "(--floating: a pose driver)"));
      if (j.type == JointType::fixed && !(j.floating && floating_))
        unite(j.parent, j.child), ++fixed;
    }
    for (const Closure& c : tree_.closures)
      if (c.weld) {
        if (find(c.link_a) == find(c.link_b))
          throw ImportError(c.file.empty() ? tree_.source : c.file, c.line,
                            "closure " + c.a + " - " + c.b + " welds two frames of one rigid body");
        d_.notes.push_back("6d closure " + c.a + " - " + c.b + ": bodies " +
                           tree_.links[static_cast<size_t>(find(c.link_a))].name + " and " +
                           tree_.links[static_cast<size_t>(find(c.link_b))].name +
                           " merged (welded)");
        unite(c.link_a, c.link_b);
      }
    if (fixed)
      d_.notes.push_back(std::to_string(fixed) +
                         " fixed joints: their child links merged into their parents (kept as "
                         "named points)");
    body_of_.assign(n, -1);
    // A body is named and framed after its first link with a mass (not a frame-only link of
    // 1e-9 kg or a cut), the ground after the root.
    std::vector<int> rep(n, -1);
    for (size_t l = 0; l < n; ++l) {
      int& r = rep[static_cast<size_t>(find(static_cast<int>(l)))];
      if (r < 0 || (find(static_cast<int>(l)) != find(0) &&
                    tree_.links[static_cast<size_t>(r)].mass <= 1e-9 && tree_.links[l].mass > 1e-9))
        r = static_cast<int>(l);
    }
    for (size_t l = 0; l < n; ++l) {
      const int root = rep[static_cast<size_t>(find(static_cast<int>(l)))];
      if (body_of_[static_cast<size_t>(root)] < 0) {
        body_of_[static_cast<size_t>(root)] = static_cast<int>(d_.bodies.size());
        Body b;
        b.name = b.link = tree_.links[static_cast<size_t>(root)].name;
        b.frame = pose_.link[static_cast<size_t>(root)];
        b.ground = find(root) == find(0);
        d_.bodies.push_back(b);
      }
      body_of_[l] = body_of_[static_cast<size_t>(root)];
      Body& b = d_.bodies[static_cast<size_t>(body_of_[l])];
      const Link& link = tree_.links[l];
      Body part;
      part.frame = pose_.link[l];
      part.mass = link.mass;
      part.com = link.com;
      part.inertia = link.inertia;
      part.points = link.points;
      if (static_cast<int>(l) != root) {
        part.points.push_back({link.name, Vec3::Zero()});
        part.merged.push_back(link.name);
      }
      absorb(b, part);
    }
  }

  // Adds `part`'s mass, points and merged names to `into` (parallel-axis theorem, into's frame).
  static void absorb(Body& into, const Body& part) {
    const Frame rel = into.frame.inverse() * part.frame;
    const Mat3 R = rel.linear();
    const Vec3 c2 = rel * part.com;
    const Mat3 I2 = R * part.inertia * R.transpose();
    const double m = into.mass + part.mass;
    const Vec3 c = m > 0 ? Vec3((into.mass * into.com + part.mass * c2) / m) : into.com;
    auto shift = [](double mass, const Vec3& d) {
      return Mat3(mass * (d.squaredNorm() * Mat3::Identity() - d * d.transpose()));
    };
    into.inertia = into.inertia + shift(into.mass, into.com - c) + I2 + shift(part.mass, c2 - c);
    into.com = c;
    into.mass = m;
    for (const auto& [name, x] : part.points) into.points.push_back({name, rel * x});
    into.merged.insert(into.merged.end(), part.merged.begin(), part.merged.end());
  }

  void make_joints() {
    for (size_t i = 0; i < tree_.joints.size(); ++i) {
      const TreeJoint& tj = tree_.joints[i];
      if (tj.floating && floating_)
        d_.pose_drivers.push_back({tree_.links[static_cast<size_t>(tj.child)].name + "_pose",
                                   body_of_[static_cast<size_t>(tj.parent)],
                                   body_of_[static_cast<size_t>(tj.child)],
                                   pose_.link[static_cast<size_t>(tj.child)].translation()});
      if (tj.type == JointType::fixed) continue;
      Joint j;
      j.name = tj.name;
      j.type = tj.type;
      j.first = body_of_[static_cast<size_t>(tj.parent)];
      j.second = body_of_[static_cast<size_t>(tj.child)];
      const Frame f = pose_.link[static_cast<size_t>(tj.parent)] * tj.origin;
      j.s0 = f.translation();
      if (tj.type == JointType::universal) {
        j.s = f.linear() * Vec3::UnitX();
        j.s2 = f.linear() * Eigen::AngleAxisd(pose_.q[i][0], Vec3::UnitX()) * Vec3::UnitY();
      } else {
        j.s = f.linear() * tj.axis;
      }
      if (tj.dofs() == 1) {
        j.source_value = pose_.q[i][0];
        j.lower = tj.lower, j.upper = tj.upper;
      }
      if (j.first == j.second) {
        d_.notes.push_back("joint " + j.name + " dropped: a weld locks it");
        continue;
      }
      d_.joints.push_back(j);
    }
    for (const Closure& c : tree_.closures) {
      if (c.weld) continue;
      Joint j;
      j.name = c.name;
      j.type = JointType::spherical;
      j.first = body_of_[static_cast<size_t>(c.link_a)];
      j.second = body_of_[static_cast<size_t>(c.link_b)];
      j.s0 = (pose_.link[static_cast<size_t>(c.link_a)] * c.in_a).translation();
      j.comment = "3d closure " + c.a + " - " + c.b;
      if (j.first == j.second)
        throw ImportError(c.file.empty() ? tree_.source : c.file, c.line,
                          "closure " + c.a + " - " + c.b + " joins a body to itself");
      d_.notes.push_back("3d closure " + c.a + " - " + c.b + ": spherical joint " + j.name +
                         " between " + d_.bodies[static_cast<size_t>(j.first)].name + " and " +
                         d_.bodies[static_cast<size_t>(j.second)].name);
      d_.joints.push_back(j);
    }
  }

  bool actuated(const std::string& joint) const {
    for (const Actuator& a : tree_.actuators)
      if (tree_.joints[static_cast<size_t>(a.joint)].name == joint) return true;
    return false;
  }

  std::vector<int> joints_of(int body) const {
    std::vector<int> out;
    for (size_t i = 0; i < d_.joints.size(); ++i)
      if (d_.joints[i].first == body || d_.joints[i].second == body)
        out.push_back(static_cast<int>(i));
    return out;
  }

  // Removes body `b` (its joints must have been removed or redirected) and renumbers.
  void erase_body(int b) {
    d_.bodies.erase(d_.bodies.begin() + b);
    for (Joint& j : d_.joints) {
      if (j.first > b) --j.first;
      if (j.second > b) --j.second;
    }
  }
  void erase_joints(std::vector<int> ids) {
    std::sort(ids.rbegin(), ids.rend());
    for (int i : ids) d_.joints.erase(d_.joints.begin() + i);
  }

  // A link of no mass, or of the 1e-9 kg URDF exporters give frame links (dropped with it).
  bool massless(const Body& b) const { return !b.ground && b.mass <= 1e-9 && b.points.empty(); }

  // P -R- X1 -R- X2 -R- C with X massless binary links: three axes through one point make a
  // spherical joint, two perpendicular ones a universal joint.
  bool revolute_chains() {
    for (size_t x = 0; x < d_.bodies.size(); ++x) {
      if (!massless(d_.bodies[x])) continue;
      std::vector<int> js = joints_of(static_cast<int>(x));
      if (js.size() != 2) continue;
      // Walk outwards both ways through massless binary revolute links.
      std::vector<int> chain_bodies{static_cast<int>(x)};
      std::vector<int> chain{js[0], js[1]};  // joints, in order
      auto other = [&](int joint, int body) {
        const Joint& j = d_.joints[static_cast<size_t>(joint)];
        return j.first == body ? j.second : j.first;
      };
      int left = other(js[0], static_cast<int>(x)), right = other(js[1], static_cast<int>(x));
      auto extend = [&](int& end, bool at_front) {
        while (massless(d_.bodies[static_cast<size_t>(end)])) {
          std::vector<int> ej = joints_of(end);
          if (ej.size() != 2) break;
          const int came = at_front ? chain.front() : chain.back();
          const int next = ej[0] == came ? ej[1] : ej[0];
          if (at_front) {
            chain.insert(chain.begin(), next);
            chain_bodies.insert(chain_bodies.begin(), end);
          } else {
            chain.push_back(next);
            chain_bodies.push_back(end);
          }
          end = other(next, end);
        }
      };
      extend(left, true);
      extend(right, false);
      if (chain.size() != 2 && chain.size() != 3) continue;
      bool ok = left != right;
      for (int j : chain)
        ok = ok && d_.joints[static_cast<size_t>(j)].type == JointType::revolute &&
             !actuated(d_.joints[static_cast<size_t>(j)].name);
      if (!ok) continue;
      const Joint& a = d_.joints[static_cast<size_t>(chain[0])];
      const Joint& b = d_.joints[static_cast<size_t>(chain[1])];
      const Vec3 c = closest_point(a.s0, a.s, b.s0, b.s);
      bool meet = true;
      for (int j : chain) {
        const Joint& jj = d_.joints[static_cast<size_t>(j)];
        meet = meet && (c - jj.s0 - jj.s * jj.s.dot(c - jj.s0)).norm() < kTiny;
      }
      if (!meet) continue;
      Joint made;
      if (chain.size() == 3) {
        const Joint& e = d_.joints[static_cast<size_t>(chain[2])];
        if (std::abs(a.s.cross(b.s).dot(e.s)) < 1e-6) continue;
        made.type = JointType::spherical;
      } else {
        if (std::abs(a.s.dot(b.s)) > 1e-9) continue;
        made.type = JointType::universal;
        made.s = a.s, made.s2 = b.s;
      }
      // The chain runs from `left` to `right`: orient the first axis accordingly.
      made.first = left, made.second = right;
      made.s0 = c;
      std::string prefix = a.name;
      for (int j : chain) {
        const std::string& nm = d_.joints[static_cast<size_t>(j)].name;
        size_t k = 0;
        while (k < prefix.size() && k < nm.size() && prefix[k] == nm[k]) ++k;
        prefix.resize(k);
      }
      while (!prefix.empty() &&
             (prefix.back() == '_' || std::isdigit(static_cast<unsigned char>(prefix.back()))))
        prefix.pop_back();
      if (prefix.size() > 4 && prefix.substr(prefix.size() - 4) == "_rev")
        prefix.resize(prefix.size() - 4);
      made.name = prefix.empty() ? a.name : prefix;
      std::string names;
      for (int j : chain)
        names += (names.empty() ? "" : ", ") + d_.joints[static_cast<size_t>(j)].name;
      made.comment = "replaces revolutes " + names;
      d_.notes.push_back("revolutes " + names + " (axes meeting at one point, massless links " +
                         "between) replaced by the " +
                         (made.type == JointType::spherical ? "spherical" : "universal") +
                         " joint " + made.name);
      erase_joints(chain);
      d_.joints.push_back(made);
      std::sort(chain_bodies.rbegin(), chain_bodies.rend());
      for (int bb : chain_bodies) erase_body(bb);
      return true;
    }
    return false;
  }

  // A link between two coaxial revolutes spins idly: welded to its neighbour across the first.
  bool coaxial_spins() {
    for (size_t x = 0; x < d_.bodies.size(); ++x) {
      if (d_.bodies[x].ground) continue;
      std::vector<int> js = joints_of(static_cast<int>(x));
      if (js.size() != 2) continue;
      const Joint& a = d_.joints[static_cast<size_t>(js[0])];
      const Joint& b = d_.joints[static_cast<size_t>(js[1])];
      if (a.type != JointType::revolute || b.type != JointType::revolute) continue;
      if (std::abs(std::abs(a.s.dot(b.s)) - 1) > 1e-9 ||
          line_distance(a.s0, a.s, b.s0, b.s) > kTiny)
        continue;
      const Joint* keep = &b;
      const Joint* drop = &a;
      if (actuated(a.name)) std::swap(keep, drop);
      if (actuated(drop->name)) continue;
      const int into = drop->first == static_cast<int>(x) ? drop->second : drop->first;
      d_.notes.push_back("body " + d_.bodies[x].name + " between coaxial revolutes " + a.name +
                         " and " + b.name + " would spin idly: welded to " +
                         d_.bodies[static_cast<size_t>(into)].name + " (" + drop->name +
                         " removed; exact for a body symmetric about the axis)");
      merge(into, static_cast<int>(x), drop == &a ? js[0] : js[1]);
      return true;
    }
    return false;
  }

  // Links between two spherical joints, binary (a rod) or a chain joined by prismatics along the
  // line through the two centres and revolutes about it (a cylinder and its piston), spin idly
  // about that line: the second spherical joint becomes universal, its axes normal to the line
  // (model/idle_spin.hpp, shared with the spatial reader).
  bool spherical_spins() {
    std::vector<SpinJoint> joints;
    for (const Joint& j : d_.joints)
      joints.push_back({j.type == JointType::spherical   ? SpinJointKind::spherical
                        : j.type == JointType::prismatic ? SpinJointKind::prismatic
                        : j.type == JointType::revolute  ? SpinJointKind::revolute
                                                         : SpinJointKind::other,
                        j.first,
                        j.second,
                        {j.s0[0], j.s0[1], j.s0[2]},
                        {j.s[0], j.s[1], j.s[2]}});
    std::vector<bool> ground;
    for (const Body& b : d_.bodies) ground.push_back(b.ground);
    const std::optional<IdleSpin> spin = find_idle_spin(joints, ground, kTiny);
    if (!spin) return false;
    Joint& b = d_.joints[static_cast<size_t>(spin->b)];
    const Vec3 u(spin->u[0], spin->u[1], spin->u[2]);
    b.type = JointType::universal;
    b.s = u.cross(Vec3::Unit(spin->normal)).normalized();
    b.s2 = u.cross(b.s).normalized();
    std::string names;
    for (const int k : spin->bodies) {
      d_.bodies[static_cast<size_t>(k)].spin_fixed = true;
      names += (names.empty() ? "" : ", ") + d_.bodies[static_cast<size_t>(k)].name;
    }
    const std::string& an = d_.joints[static_cast<size_t>(spin->a)].name;
    b.comment = "spherical in the source; universal: " + names + " would spin idly about " + an +
                " - " + b.name;
    d_.notes.push_back((spin->bodies.size() == 1 ? "link " : "links ") + names +
                       " between spherical joints " + an + " and " + b.name +
                       ": their spin about the line through them is idle; " + b.name +
                       " made universal (axes normal to that line)");
    return true;
  }

  // Body `from` into body `into`; joint `removed` (between them) goes.
  void merge(int into, int from, int removed) {
    absorb(d_.bodies[static_cast<size_t>(into)], [&] {
      Body part = d_.bodies[static_cast<size_t>(from)];
      part.points.insert(part.points.begin(), {part.name, Vec3::Zero()});
      part.merged.insert(part.merged.begin(), part.link);
      return part;
    }());
    Body& b = d_.bodies[static_cast<size_t>(into)];
    const Body& gone = d_.bodies[static_cast<size_t>(from)];
    b.idle_links.push_back(gone.link);
    b.idle_links.insert(b.idle_links.end(), gone.merged.begin(), gone.merged.end());
    erase_joints({removed});
    for (Joint& j : d_.joints) {
      if (j.first == from) j.first = into;
      if (j.second == from) j.second = into;
    }
    erase_body(from);
  }

  // A body whose mass is negligible and inertia singular (a URDF frame link of 1e-9 kg on a
  // moving joint) is written massless.
  void massless_points() {
    for (Body& b : d_.bodies) {
      if (b.ground || b.mass == 0) continue;
      const Eigen::SelfAdjointEigenSolver<Mat3> eig(b.inertia);
      if (eig.eigenvalues().minCoeff() > 0) continue;
      if (b.mass < 1e-6) {
        d_.notes.push_back("body " + b.name + ": mass " + fmt(b.mass) +
                           " kg without inertia written massless");
        b.mass = 0, b.inertia.setZero();
      }
    }
  }

  // Bodies, points, joints and drivers share one namespace (CSV columns, kernel fields): a name
  // met again gets its kind as a suffix (a URDF driver is named after its joint: `mot1_drive`).
  void unique_names() {
    std::set<std::string> taken;
    auto claim = [&](std::string& name, const std::string& suffix) {
      std::string n = identifier(name);
      if (taken.count(n)) {
        std::string base = n + "_" + suffix;
        n = base;
        for (int k = 2; taken.count(n); ++k) n = base + std::to_string(k);
        d_.notes.push_back("name " + name + " taken: this " + suffix + " is " + n);
      }
      taken.insert(n);
      name = n;
    };
    for (Body& b : d_.bodies) claim(b.name, "body");
    for (Body& b : d_.bodies)
      for (auto& p : b.points) claim(p.first, "point");
    for (Joint& j : d_.joints) claim(j.name, "joint");
    for (PoseDriver& pd : d_.pose_drivers) claim(pd.name, "pose");
    for (Driver& dr : d_.drivers) {
      std::string n = identifier(dr.name);
      if (taken.count(n)) dr.name = n + "_drive";
      claim(dr.name, "drive");
    }
  }

  const Tree& tree_;
  const TreePose& pose_;
  bool floating_ = false;
  Description d_;
  std::vector<int> parent_, body_of_;
};

}  // namespace

Description describe(const Tree& tree, const TreePose& pose, bool floating) {
  Description d = Builder(tree, pose, floating).run();
  // Nothing moves (no link, or every link fixed or welded to the root, and no floating base): no
  // mechanism to describe, said at the root (issue 26 item 5, found by import_fuzzer).
  if (d.joints.empty() && d.pose_drivers.empty())
    throw ImportError(tree.source, tree.links.empty() ? 1 : tree.links[0].line,
                      "nothing moves: every link of '" + tree.name +
                          "' is its root or fixed to it (no joint to describe)");
  return d;
}

void float_base(Tree& tree) {
  for (const TreeJoint& j : tree.joints)
    if (j.floating) return;  // MJCF: the free joint's body floats
  // URDF: a new ground below the root link.
  Link world;
  world.name = "world";
  tree.links.insert(tree.links.begin(), world);
  for (TreeJoint& j : tree.joints) ++j.parent, ++j.child;
  for (Closure& c : tree.closures) ++c.link_a, ++c.link_b;
  for (Actuator& a : tree.actuators) ++a.joint;
  TreeJoint free;
  free.name = tree.links[1].name + "_free";
  free.type = JointType::fixed;
  free.floating = true;
  free.parent = 0;
  free.child = 1;
  tree.joints.insert(tree.joints.begin(), free);
}

std::string identifier(const std::string& name) {
  std::string out;
  for (const char c : name) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  if (out.empty() || std::isdigit(static_cast<unsigned char>(out[0])) || out[0] == '_')
    out = "n" + out;
  while (out.find("__") != std::string::npos) out.replace(out.find("__"), 2, "_");
  if (!reserved_name_reason(out).empty()) out += "_";  // a C++ keyword, a kernel's own name
  return out;
}

}  // namespace mechgen::import
