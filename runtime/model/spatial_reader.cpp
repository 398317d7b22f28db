// Reads the spatial elements of a description (docs/model_format.md, "Spatial models"): gravity,
// bodies with full inertia, screw joints, joint drivers and pose drivers, the latter expanded into
// their 3P3R virtual chains. Name, parameters and step are read by the shared reader
// (model_reader.cpp) through DescriptionSyntax, so both dimensions parse them identically.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>

#include "geometry/screw.hpp"
#include "model/description_syntax.hpp"
#include "model/fingerprint.hpp"
#include "model/idle_spin.hpp"
#include "model/spatial_graph.hpp"
#include "model/spatial_model.hpp"
#include "model/spatial_value_checks.hpp"

namespace mechgen {

namespace {

using geometry::Vec3;
using GiNaC::ex;
using geometry::operator+;
using geometry::operator-;
using geometry::operator*;

Vec3<ex> vec(const Vec3Expr& v) {
  return {v.x.ex, v.y.ex, v.z.ex};
}

Vec3Expr expr_vec(const Vec3<ex>& v, const std::string& text, const SourceLoc& at) {
  return {{v[0], text + " x", at}, {v[1], text + " y", at}, {v[2], text + " z", at}};
}

Vec3Expr constant_vec(double x, double y, double z, const SourceLoc& at) {
  return expr_vec({ex(x), ex(y), ex(z)}, "constant", at);
}

class SpatialReader {
 public:
  SpatialReader(const DescriptionSyntax& syntax, Model common) : y_(syntax) {
    m_.common = std::move(common);
    subs_ = m_.common.substitutions(m_.common.default_parameters());
  }
  SpatialModel read(const YAML::Node& root);

 private:
  [[noreturn]] void fail(const YAML::Node& node, const std::string& message) const {
    throw ModelError(y_.loc(node), message);
  }
  Vec3Expr vector3(const YAML::Node& node, const std::string& what, bool time_allowed) const;
  double number(const Expr& e) const { return m_.evaluate(e, subs_); }
  Vec3<double> numbers(const Vec3Expr& v) const { return {number(v.x), number(v.y), number(v.z)}; }
  Vec3Expr unit_axis(const YAML::Node& node, const std::string& what) const;
  int body_ref(const YAML::Node& node, const std::string& what) const;
  void claim(const YAML::Node& node, const std::string& name, const std::string& kind);
  std::optional<std::array<Expr, 2>> range(const YAML::Node& node, const std::string& what) const;
  // A point given as [x, y, z] (ground frame, reference pose) or as a named point of `body`.
  Vec3Expr located(const YAML::Node& node, const std::string& what, int body,
                   std::string& point_name) const;

  void read_body(const YAML::Node& node);
  void check_point_names() const;
  void read_mass(const YAML::Node& node, SpatialBody& body);
  void read_joint(const YAML::Node& node);
  void hold_idle_spins();
  void read_driver(const YAML::Node& node);
  void read_pose_driver(const YAML::Node& node);
  void read_driver_table(const YAML::Node& node, const std::string& what, SpatialDriver& d);
  void default_step(const YAML::Node& root);
  void read_load(const YAML::Node& node);
  void read_kernel_options(const YAML::Node& node);
  // A list element's name (a mapping with `name`), checked and claimed; its location in `at`.
  std::string element_name(const YAML::Node& node, const std::string& kind, SourceLoc& at);

  const DescriptionSyntax& y_;
  SpatialModel m_;
  GiNaC::exmap subs_;
  std::map<std::string, std::string> names_;
};

void SpatialReader::claim(const YAML::Node& node, const std::string& name,
                          const std::string& kind) {
  const auto [at, inserted] = names_.emplace(name, kind);
  if (!inserted)
    fail(node, "duplicate name '" + name + "' (already the name of a " + at->second + ")");
}

Vec3Expr SpatialReader::vector3(const YAML::Node& node, const std::string& what,
                                bool time_allowed) const {
  if (!node.IsSequence() || node.size() != 3)
    fail(node, what + " must be a triple [x, y, z] (got " +
                   (!node.IsSequence() ? std::string("no list")
                                       : std::to_string(node.size()) + " values") +
                   ")");
  return {y_.expression(node[0], what + " x", time_allowed),
          y_.expression(node[1], what + " y", time_allowed),
          y_.expression(node[2], what + " z", time_allowed)};
}

Vec3Expr SpatialReader::unit_axis(const YAML::Node& node, const std::string& what) const {
  const Vec3Expr axis = vector3(node, what, false);
  const Vec3<double> s = numbers(axis);
  const double norm = std::sqrt(geometry::dot(s, s));
  if (norm == 0) fail(node, what + " is zero: give the joint's unit axis, e.g. [0, 0, 1]");
  if (std::abs(norm - 1) > 1e-9) {
    std::ostringstream message;
    message.precision(6);
    message << what << " has length " << norm << " at the default parameters: give a unit vector"
            << " (this one divided by its length is [" << s[0] / norm << ", " << s[1] / norm << ", "
            << s[2] / norm << "])";
    fail(node, message.str());
  }
  return axis;
}

int SpatialReader::body_ref(const YAML::Node& node, const std::string& what) const {
  const std::string name = y_.scalar(node, what);
  const int index = m_.body_index(name);
  if (index < 0 || m_.bodies[static_cast<size_t>(index)].is_virtual) {
    std::string known;
    for (const SpatialBody& b : m_.bodies)
      if (!b.is_virtual) known += (known.empty() ? "" : ", ") + b.name;
    fail(node, what + ": unknown body '" + name + "' (bodies: " + known + ")");
  }
  return index;
}

std::optional<std::array<Expr, 2>> SpatialReader::range(const YAML::Node& node,
                                                        const std::string& what) const {
  if (!node) return std::nullopt;
  if (!node.IsSequence() || node.size() != 2) fail(node, what + " range must be [min, max]");
  std::array<Expr, 2> r{y_.expression(node[0], what + " range min", false),
                        y_.expression(node[1], what + " range max", false)};
  if (!(number(r[0]) < number(r[1]))) fail(node, what + " range: min must be less than max");
  return r;
}

Vec3Expr SpatialReader::located(const YAML::Node& node, const std::string& what, int body,
                                std::string& point_name) const {
  if (!node.IsScalar()) return vector3(node, what, false);
  point_name = y_.identifier(node, what);
  // A named point of `body`, or else of any real body: its reference position, ground frame.
  for (int pass = 0; pass < 2; ++pass)
    for (size_t b = 0; b < m_.bodies.size(); ++b) {
      const SpatialBody& sb = m_.bodies[b];
      if ((pass == 0 && static_cast<int>(b) != body) || sb.is_virtual) continue;
      if (const SpatialPoint* p = sb.find_point(point_name)) {
        const Vec3<ex> axis = vec(sb.rotation_axis);
        const geometry::Pose<ex> g0{geometry::rodrigues(axis, sb.rotation_angle.ex),
                                    vec(sb.origin)};
        return expr_vec(geometry::apply(g0, vec(p->local)), point_name, y_.loc(node));
      }
    }
  fail(node, what + ": no body carries a point '" + point_name + "'");
}

void SpatialReader::read_mass(const YAML::Node& node, SpatialBody& body) {
  const std::string what = "mass of body '" + body.name + "'";
  if (!node.IsMap()) fail(node, what + " must be a mapping");
  SpatialMass& m = body.mass;
  m.loc = y_.loc(node);
  auto sq = [](const ex& e) { return e * e; };
  if (node["bar"]) {
    // A solid round bar between two of the body's points.
    y_.expect_keys(node, what + " (bar)", {"bar", "radius", "density"});
    const YAML::Node bar = node["bar"];
    if (!bar.IsSequence() || bar.size() != 2)
      fail(bar, what + ": bar must name two of the body's points [from, to]");
    const SpatialPoint* a = body.find_point(y_.scalar(bar[0], "bar end"));
    const SpatialPoint* b = body.find_point(y_.scalar(bar[1], "bar end"));
    if (!a) fail(bar[0], what + ": the body has no point '" + bar[0].Scalar() + "'");
    if (!b) fail(bar[1], what + ": the body has no point '" + bar[1].Scalar() + "'");
    const Expr r = y_.expression(y_.required(node, "radius", what), what + " radius", false);
    const Expr rho = y_.expression(y_.required(node, "density", what), what + " density", false);
    const Vec3<ex> d = vec(b->local) - vec(a->local);
    const ex length2 = geometry::dot(d, d);
    if (number({length2, "", m.loc}) <= 0) fail(bar, what + ": the bar's ends coincide");
    const ex mass = rho.ex * GiNaC::Pi * sq(r.ex) * GiNaC::sqrt(length2);
    m.source = SpatialMass::Source::bar;
    m.bar_from = a->name;
    m.bar_to = b->name;
    m.radius = r;
    m.mass = {mass, "density*pi*radius^2*length", m.loc};
    m.com = expr_vec(ex(1) / 2 * (vec(a->local) + vec(b->local)), "bar middle", m.loc);
    // I = It (E - u u^T) + Ia u u^T with u = d / |d|: It = m (3 r^2 + L^2) / 12, Ia = m r^2 / 2.
    const ex it = mass * (3 * sq(r.ex) + length2) / 12, ia = mass * sq(r.ex) / 2;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        m.inertia[static_cast<size_t>(3 * i + j)] =
            (i == j ? it : ex(0)) +
            (ia - it) * d[static_cast<size_t>(i)] * d[static_cast<size_t>(j)] / length2;
  } else if (node["box"]) {
    // A solid box with edges along the body frame's axes, centred at `com`.
    y_.expect_keys(node, what + " (box)", {"box", "density", "com"});
    const Vec3Expr size = vector3(node["box"], what + " box", false);
    const Expr rho = y_.expression(y_.required(node, "density", what), what + " density", false);
    const ex mass = rho.ex * size.x.ex * size.y.ex * size.z.ex;
    m.source = SpatialMass::Source::box;
    m.box_size = size;
    m.mass = {mass, "density*a*b*c", m.loc};
    m.com = vector3(y_.required(node, "com", what), what + " com", false);
    const Vec3<ex> s = vec(size);
    for (ex& e : m.inertia) e = 0;
    m.inertia[0] = mass * (sq(s[1]) + sq(s[2])) / 12;
    m.inertia[4] = mass * (sq(s[0]) + sq(s[2])) / 12;
    m.inertia[8] = mass * (sq(s[0]) + sq(s[1])) / 12;
  } else {
    y_.expect_keys(node, what, {"mass", "com", "inertia"});
    m.source = SpatialMass::Source::explicit_values;
    m.mass = y_.expression(y_.required(node, "mass", what), what, false);
    m.com = vector3(y_.required(node, "com", what), what + " com", false);
    const YAML::Node inertia = y_.required(node, "inertia", what);
    const std::string iw = what + " inertia";
    if (inertia.IsSequence() && inertia.size() == 3 && inertia[0].IsScalar()) {
      for (ex& e : m.inertia) e = 0;
      for (int i = 0; i < 3; ++i)
        m.inertia[static_cast<size_t>(4 * i)] =
            y_.expression(inertia[static_cast<size_t>(i)], iw, false).ex;
    } else if (inertia.IsSequence() && inertia.size() == 3) {
      for (size_t i = 0; i < 3; ++i) {
        if (!inertia[i].IsSequence() || inertia[i].size() != 3)
          fail(inertia[i], iw + ": each row must have 3 values");
        for (size_t j = 0; j < 3; ++j)
          m.inertia[3 * i + j] = y_.expression(inertia[i][j], iw, false).ex;
      }
    } else {
      fail(inertia, iw + " must be [Ixx, Iyy, Izz] or a 3 x 3 matrix [[..], [..], [..]]");
    }
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < i; ++j)
        if (std::abs(number({m.inertia[static_cast<size_t>(3 * i + j)] -
                                 m.inertia[static_cast<size_t>(3 * j + i)],
                             "", m.loc})) > 1e-12)
          fail(inertia, iw + " must be symmetric");
  }
  if (number(m.mass) < 0) fail(node, what + " is negative");
  for (int i = 0; i < 3; ++i)
    if (number({m.inertia[static_cast<size_t>(4 * i)], "", m.loc}) < 0)
      fail(node, what + ": a diagonal inertia term is negative");
}

void SpatialReader::read_body(const YAML::Node& node) {
  if (!node.IsMap()) fail(node, "a body must be a mapping");
  y_.expect_keys(node, "body", {"name", "ground", "points", "mass", "origin", "rotation"});
  SpatialBody body;
  body.name = y_.identifier(y_.required(node, "name", "a body"), "body name");
  body.loc = y_.loc(node["name"]);
  claim(node["name"], body.name, "body");
  if (node["ground"]) body.ground = y_.flag(node["ground"], "ground");
  body.origin =
      node["origin"] ? vector3(node["origin"], "origin", false) : constant_vec(0, 0, 0, body.loc);
  body.rotation_axis = constant_vec(0, 0, 1, body.loc);
  body.rotation_angle = {ex(0), "0", body.loc};
  if (const YAML::Node rot = node["rotation"]) {
    if (!rot.IsMap()) fail(rot, "rotation must be {axis: [x, y, z], angle: A}");
    y_.expect_keys(rot, "rotation", {"axis", "angle"});
    body.rotation_axis = unit_axis(y_.required(rot, "axis", "rotation"), "rotation axis");
    body.rotation_angle =
        y_.expression(y_.required(rot, "angle", "rotation"), "rotation angle", false);
  }
  if (const YAML::Node points = node["points"]) {
    if (!points.IsMap()) fail(points, "points of body '" + body.name + "' must be a mapping");
    for (const auto& item : points) {
      SpatialPoint p;
      p.name = y_.identifier(item.first, "point name");
      if (body.find_point(p.name))
        fail(item.first, "body '" + body.name + "': duplicate point '" + p.name + "'");
      p.local = vector3(item.second, "point '" + p.name + "'", false);
      body.points.push_back(p);
    }
  }
  if (node["mass"]) {
    if (body.ground) fail(node["mass"], "the ground body takes no mass");
    read_mass(node["mass"], body);
  } else if (!body.ground) {
    fail(node["name"],
         "body '" + body.name + "' has no mass (give mass, com, inertia; a bar; or a box)");
  }
  if (body.ground) {
    if (m_.ground >= 0)
      fail(node["name"], "more than one ground body ('" +
                             m_.bodies[static_cast<size_t>(m_.ground)].name + "' and '" +
                             body.name + "')");
    m_.ground = static_cast<int>(m_.bodies.size());
  }
  m_.bodies.push_back(body);
}

SpatialJointType joint_type(const std::string& name, bool& ok) {
  static const std::map<std::string, SpatialJointType> types{
      {"revolute", SpatialJointType::revolute},   {"prismatic", SpatialJointType::prismatic},
      {"helical", SpatialJointType::helical},     {"cylindrical", SpatialJointType::cylindrical},
      {"universal", SpatialJointType::universal}, {"spherical", SpatialJointType::spherical},
      {"fixed", SpatialJointType::fixed}};
  const auto at = types.find(name);
  ok = at != types.end();
  return ok ? at->second : SpatialJointType::fixed;
}

void SpatialReader::read_joint(const YAML::Node& node) {
  SpatialJoint j;
  j.name = element_name(node, "joint", j.loc);
  const std::string what = "joint '" + j.name + "'";
  bool ok = false;
  const YAML::Node type = y_.required(node, "type", what);
  j.type = joint_type(y_.scalar(type, what + " type"), ok);
  if (!ok)
    fail(type, what + ": unknown type '" + type.Scalar() +
                   "' (expected revolute, prismatic, helical, cylindrical, universal, spherical "
                   "or fixed)");
  std::set<std::string> keys{"name", "type", "first", "second", "s0", "assembly", "range"};
  const bool axial = j.type != SpatialJointType::spherical && j.type != SpatialJointType::fixed;
  if (axial) keys.insert("s");
  if (j.type == SpatialJointType::universal) keys.insert("s2");
  if (j.type == SpatialJointType::helical) keys.insert("pitch");
  y_.expect_keys(node, what + " (" + std::string(to_string(j.type)) + ")", keys);
  j.first = body_ref(y_.required(node, "first", what), what + " first");
  j.second = body_ref(y_.required(node, "second", what), what + " second");
  if (j.first == j.second)
    fail(node["second"], what + " joins body '" + node["second"].Scalar() +
                             "' to itself: a circuit with no joint; name two different bodies");
  j.s0 = located(y_.required(node, "s0", what), what + " s0", j.first, j.point);
  j.s = axial ? unit_axis(y_.required(node, "s", what), what + " axis s")
              : constant_vec(0, 0, 1, j.loc);
  j.pitch = {ex(0), "0", j.loc};
  if (j.type == SpatialJointType::helical)
    j.pitch = y_.expression(y_.required(node, "pitch", what), what + " pitch", false);
  using K = ScrewColumnKind;
  switch (j.type) {
    case SpatialJointType::revolute:
      j.columns = {{K::rotation, j.s}};
      break;
    case SpatialJointType::prismatic:
      j.columns = {{K::translation, j.s}};
      break;
    case SpatialJointType::helical:
      j.columns = {{K::helical, j.s}};
      break;
    case SpatialJointType::cylindrical:
      j.columns = {{K::translation, j.s}, {K::rotation, j.s}};
      break;
    case SpatialJointType::universal: {
      j.s2 = unit_axis(y_.required(node, "s2", what), what + " axis s2");
      if (std::abs(geometry::dot(numbers(j.s), numbers(j.s2))) > 1e-9)
        fail(node["s2"], what + ": s2 must be perpendicular to s (a cross of two axes)");
      j.columns = {{K::rotation, j.s}, {K::rotation, j.s2}};
      break;
    }
    case SpatialJointType::spherical:
      j.columns = {{K::rotation, constant_vec(1, 0, 0, j.loc)},
                   {K::rotation, constant_vec(0, 1, 0, j.loc)},
                   {K::rotation, constant_vec(0, 0, 1, j.loc)}};
      break;
    case SpatialJointType::fixed:
      break;
  }
  j.assembly.assign(j.columns.size(), {ex(0), "0", j.loc});
  if (const YAML::Node a = node["assembly"]) {
    if (j.columns.size() == 1 && a.IsScalar()) {
      j.assembly[0] = y_.expression(a, what + " assembly", false);
    } else if (a.IsSequence() && a.size() == j.columns.size()) {
      for (size_t i = 0; i < a.size(); ++i)
        j.assembly[i] = y_.expression(a[i], what + " assembly", false);
    } else {
      fail(a, what + " assembly: give one value per coordinate (" +
                  std::to_string(j.columns.size()) + ")");
    }
  }
  j.range = range(node["range"], what);
  m_.joints.push_back(j);
}

// A link between two spherical joints A and B spins idly about the line through their centres (no
// driver can fix it): B becomes universal with its axes normal to that line (as the importer
// does), which holds the spin at its reference; the universal's couple about the line is the one
// the spin would need, zero for links with no moment of inertia about it (a thin rod, a point
// mass).
void SpatialReader::hold_idle_spins() {
  std::vector<bool> ground;
  for (const SpatialBody& b : m_.bodies) ground.push_back(b.ground);
  for (;;) {
    std::vector<SpinJoint> joints;
    for (const SpatialJoint& j : m_.joints) {
      const Vec3<double> s0 = numbers(j.s0), s = numbers(j.s);
      joints.push_back({j.type == SpatialJointType::spherical   ? SpinJointKind::spherical
                        : j.type == SpatialJointType::prismatic ? SpinJointKind::prismatic
                        : j.type == SpatialJointType::revolute  ? SpinJointKind::revolute
                                                                : SpinJointKind::other,
                        j.first,
                        j.second,
                        {s0[0], s0[1], s0[2]},
                        {s[0], s[1], s[2]}});
    }
    const std::optional<IdleSpin> spin = find_idle_spin(joints, ground, 1e-9);
    if (!spin) return;
    SpatialJoint& a = m_.joints[static_cast<size_t>(spin->a)];
    SpatialJoint& b = m_.joints[static_cast<size_t>(spin->b)];
    // The line's direction as an expression of the parameters (u = B - A, not normalised), e the
    // unit axis least aligned with it: s = u x e / |u x e|, s2 = u x s / |u x s|.
    const GiNaC::ex u[3] = {b.s0.x.ex - a.s0.x.ex, b.s0.y.ex - a.s0.y.ex, b.s0.z.ex - a.s0.z.ex};
    auto cross = [](const GiNaC::ex* p, const GiNaC::ex* q, GiNaC::ex* out) {
      out[0] = p[1] * q[2] - p[2] * q[1];
      out[1] = p[2] * q[0] - p[0] * q[2];
      out[2] = p[0] * q[1] - p[1] * q[0];
    };
    auto unit = [&](GiNaC::ex* v) {
      const GiNaC::ex length = GiNaC::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      Vec3Expr out;
      Expr* parts[3] = {&out.x, &out.y, &out.z};
      for (int i = 0; i < 3; ++i) {
        std::ostringstream text;
        text << v[i] / length;
        *parts[i] = {v[i] / length, text.str(), b.loc};
      }
      return out;
    };
    GiNaC::ex e[3] = {0, 0, 0}, s[3], s2[3];
    e[spin->normal] = 1;
    cross(u, e, s);
    b.s = unit(s);
    const GiNaC::ex sn[3] = {b.s.x.ex, b.s.y.ex, b.s.z.ex};
    cross(u, sn, s2);
    b.s2 = unit(s2);
    b.type = SpatialJointType::universal;
    b.columns = {{ScrewColumnKind::rotation, b.s}, {ScrewColumnKind::rotation, b.s2}};
    b.assembly.assign(2, {GiNaC::ex(0), "0", b.loc});
    std::string names;
    for (const int k : spin->bodies)
      names += (names.empty() ? "'" : ", '") + m_.bodies[static_cast<size_t>(k)].name + "'";
    m_.notes.push_back(std::string(spin->bodies.size() == 1 ? "link " : "links ") + names +
                       " between spherical joints '" + a.name + "' and '" + b.name +
                       "': its spin about the line through them is idle; fixed ('" + b.name +
                       "' taken as universal, axes normal to that line), no reaction about that "
                       "line for links without a moment of inertia about it");
  }
}

void SpatialReader::read_driver(const YAML::Node& node) {
  if (!node.IsMap()) fail(node, "a driver must be a mapping");
  if (node["type"]) {
    if (y_.scalar(node["type"], "driver type") != "pose")
      fail(node["type"], "driver type must be pose (or omitted for a joint driver)");
    read_pose_driver(node);
    return;
  }
  y_.expect_keys(node, "driver", {"name", "joint", "kind", "value", "range", "effort", "passive"});
  SpatialDriver d;
  d.name = y_.identifier(y_.required(node, "name", "a driver"), "driver name");
  d.loc = y_.loc(node["name"]);
  const std::string what = "driver '" + d.name + "'";
  claim(node["name"], d.name, "driver");
  const YAML::Node jn = y_.required(node, "joint", what);
  d.joint = m_.joint_index(y_.scalar(jn, what + " joint"));
  if (d.joint < 0 || m_.joints[static_cast<size_t>(d.joint)].is_virtual)
    fail(jn, what + ": unknown joint '" + jn.Scalar() + "'");
  const SpatialJoint& j = m_.joints[static_cast<size_t>(d.joint)];
  const std::string kind = y_.scalar(y_.required(node, "kind", what), what + " kind");
  if (kind != "angle" && kind != "length")
    fail(node["kind"], what + ": kind must be angle or length");
  d.kind = kind == "angle" ? DriverKind::angle : DriverKind::length;
  const bool angular = j.type == SpatialJointType::revolute || j.type == SpatialJointType::helical;
  if (j.type == SpatialJointType::cylindrical) {
    d.column = d.kind == DriverKind::angle ? 1 : 0;
  } else if (!(angular && d.kind == DriverKind::angle) &&
             !(j.type == SpatialJointType::prismatic && d.kind == DriverKind::length)) {
    fail(node["kind"], what + ": a " + std::string(to_string(j.type)) + " joint cannot take a " +
                           kind +
                           " driver (angle: revolute, helical, cylindrical; length: prismatic, "
                           "cylindrical; use a pose driver for the rest)");
  }
  for (const SpatialDriver& other : m_.drivers)
    if (other.joint == d.joint && other.column == d.column)
      fail(jn, what + " drives the same coordinate as driver '" + other.name +
                   "': the motion is over-determined; remove one");
  const YAML::Node value = y_.required(node, "value", what);
  if (value.IsMap()) {
    read_driver_table(value, what, d);
  } else {
    d.value = y_.expression(value, what + " value", true);
    d.value_d = d.value.ex.diff(m_.common.t);
    d.value_dd = d.value_d.diff(m_.common.t);
  }
  d.range = range(node["range"], what);
  if (node["effort"]) d.effort = y_.effort_law(node["effort"], what + " effort");
  d.passive = passive_driver(node, y_, what);
  m_.drivers.push_back(d);
}

// `value: {table: FILE.csv, column: NAME, time: COLUMN}`: the driver follows the table's column
// (the driver's SI unit) against its time column (s) through a not-a-knot cubic spline.
void SpatialReader::read_driver_table(const YAML::Node& node, const std::string& what,
                                      SpatialDriver& d) {
  y_.expect_keys(node, what + " value table", {"table", "column", "time"});
  const std::string written =
      y_.scalar(y_.required(node, "table", what + " value"), what + " table");
  const std::string column =
      y_.scalar(y_.required(node, "column", what + " value table"), what + " table column");
  const std::string time = node["time"] ? y_.scalar(node["time"], what + " table time") : "t";
  std::filesystem::path file(written);
  if (file.is_relative()) file = std::filesystem::path(m_.common.file).parent_path() / file;
  d.table = mechgen::read_driver_table(file.string(), column, time, y_.loc(node["table"]));
  const double first = d.table->spline->values().front();
  d.value = {GiNaC::numeric(first), "table " + written + " column " + column, y_.loc(node)};
  d.value_d = d.value_dd = 0;
  // The kernel depends on the table (its placeholder law, the default step) and a sweep on all of
  // it: the table's bytes are part of the description's fingerprint.
  Fnv1a64 hash;
  hash.add_field(hex64(m_.common.description_hash));
  hash.add_field("driver table");
  hash.add_field(written);
  hash.add_field(d.table->content);
  m_.common.description_hash = hash.value();
}

// A model whose drivers include tables may omit `step:`: t0 and t1 are then the span common to
// its tables (the latest start, the earliest end), 101 samples.
void SpatialReader::default_step(const YAML::Node& root) {
  if (root["step"]) return;
  double t0 = -INFINITY, t1 = INFINITY;
  std::string names;
  for (const SpatialDriver& d : m_.drivers)
    if (d.table) {
      t0 = std::max(t0, d.table->spline->front());
      t1 = std::min(t1, d.table->spline->back());
      names += (names.empty() ? "'" : ", '") + d.name + "'";
    }
  if (names.empty()) y_.required(root, "step", "the model");  // the usual error
  if (!(t1 > t0))
    fail(root,
         "no step: and the time ranges of the tables of drivers " + names + " do not overlap");
  const SourceLoc at = y_.loc(root);
  m_.common.step.t0 = {GiNaC::numeric(t0), "the tables' first time", at};
  m_.common.step.t1 = {GiNaC::numeric(t1), "the tables' last time", at};
}

void SpatialReader::read_pose_driver(const YAML::Node& node) {
  y_.expect_keys(node, "pose driver",
                 {"name", "type", "first", "second", "at", "x", "y", "z", "rotations"});
  PoseDriver pd;
  pd.name = y_.identifier(y_.required(node, "name", "a pose driver"), "driver name");
  pd.loc = y_.loc(node["name"]);
  const std::string what = "pose driver '" + pd.name + "'";
  claim(node["name"], pd.name, "driver");
  pd.first = body_ref(y_.required(node, "first", what), what + " first");
  pd.second = body_ref(y_.required(node, "second", what), what + " second");
  if (pd.first == pd.second) fail(node["second"], what + ": first and second are the same body");
  pd.at = located(y_.required(node, "at", what), what + " at", pd.second, pd.at_point);
  const SpatialBody& first = m_.bodies[static_cast<size_t>(pd.first)];
  const geometry::Pose<ex> g0{
      geometry::rodrigues(vec(first.rotation_axis), first.rotation_angle.ex), vec(first.origin)};
  const Vec3<ex> at_local = geometry::apply(geometry::inverse(g0), vec(pd.at));
  const char* names[3] = {"x", "y", "z"};
  auto frame_axis = [&](int k) {
    Vec3<ex> e{ex(0), ex(0), ex(0)};
    e[static_cast<size_t>(k)] = 1;
    return expr_vec(g0.R * e, std::string("axis ") + names[k], pd.loc);
  };
  // Translations x, y, z (prescribed or free), then the rotations in the order given, then free
  // rotations about the remaining axes.
  std::vector<std::pair<PoseCoordinate, ScrewColumnExpr>> chain;
  int prescribed = 0;
  for (int k = 0; k < 3; ++k) {
    PoseCoordinate c;
    c.name = names[k];
    c.reference = at_local[static_cast<size_t>(k)];
    if (node[names[k]]) {
      c.value = y_.expression(node[names[k]], what + " " + names[k], true);
      ++prescribed;
    }
    chain.push_back({c, {ScrewColumnKind::translation, frame_axis(k)}});
  }
  bool used[3] = {false, false, false};
  if (const YAML::Node rotations = node["rotations"]) {
    if (!rotations.IsSequence() || rotations.size() > 3)
      fail(rotations, what + ": rotations must be a list of up to three {axis: x|y|z, value: A}");
    for (const auto& r : rotations) {
      if (!r.IsMap()) fail(r, what + ": a rotation must be {axis: x|y|z, value: A}");
      y_.expect_keys(r, what + " rotation", {"axis", "value"});
      const std::string axis = y_.scalar(y_.required(r, "axis", what + " rotation"), "axis");
      const int k = axis == "x" ? 0 : axis == "y" ? 1 : axis == "z" ? 2 : -1;
      if (k < 0) fail(r["axis"], what + ": a rotation axis is x, y or z (of first's frame)");
      if (used[k])
        fail(r["axis"], what + ": two rotations about " + axis +
                            " over-determine the orientation; use three different axes");
      used[k] = true;
      PoseCoordinate c;
      c.name = "r" + axis;
      c.reference = 0;
      c.value =
          y_.expression(y_.required(r, "value", what + " rotation"), what + " r" + axis, true);
      ++prescribed;
      chain.push_back({c, {ScrewColumnKind::rotation, frame_axis(k)}});
    }
  }
  for (int k = 0; k < 3; ++k)
    if (!used[k]) {
      PoseCoordinate c;
      c.name = std::string("r") + names[k];
      c.reference = 0;
      chain.push_back({c, {ScrewColumnKind::rotation, frame_axis(k)}});
    }
  if (prescribed == 0)
    fail(node["name"], what + " prescribes nothing: give some of x, y, z, rotations");
  // The virtual chain first -> b1 -> ... -> b5 -> second, one coordinate per virtual joint.
  const int index = static_cast<int>(m_.pose_drivers.size());
  int previous = pd.first;
  for (size_t k = 0; k < chain.size(); ++k) {
    int next = pd.second;
    if (k + 1 < chain.size()) {
      SpatialBody b;
      b.name = pd.name + "_b" + std::to_string(k + 1);
      b.is_virtual = true;
      b.loc = pd.loc;
      b.origin = constant_vec(0, 0, 0, pd.loc);
      b.rotation_axis = constant_vec(0, 0, 1, pd.loc);
      b.rotation_angle = {ex(0), "0", pd.loc};
      b.mass.mass = {ex(0), "0", pd.loc};
      b.mass.com = constant_vec(0, 0, 0, pd.loc);
      for (ex& e : b.mass.inertia) e = 0;
      claim(node["name"], b.name, "virtual body");
      next = static_cast<int>(m_.bodies.size());
      m_.bodies.push_back(b);
    }
    SpatialJoint j;
    PoseCoordinate& c = chain[k].first;
    j.name = pd.name + "_" + c.name;
    claim(node["name"], j.name, "virtual joint");
    j.type = chain[k].second.kind == ScrewColumnKind::translation ? SpatialJointType::prismatic
                                                                  : SpatialJointType::revolute;
    j.first = previous;
    j.second = next;
    j.s = chain[k].second.s;
    j.s0 = pd.at;
    j.pitch = {ex(0), "0", pd.loc};
    j.columns = {chain[k].second};
    j.is_virtual = true;
    j.pose_driver = index;
    j.loc = pd.loc;
    if (c.value) {
      c.value_d = c.value->ex.diff(m_.common.t);
      c.value_dd = c.value_d.diff(m_.common.t);
    }
    // A prescribed coordinate starts from its driver's value; a free one from the reference.
    j.assembly = {{ex(0), "0", pd.loc}};
    c.joint = static_cast<int>(m_.joints.size());
    m_.joints.push_back(j);
    pd.coordinates.push_back(c);
    previous = next;
  }
  m_.pose_drivers.push_back(pd);
}

std::string SpatialReader::element_name(const YAML::Node& node, const std::string& kind,
                                        SourceLoc& at) {
  if (!node.IsMap()) fail(node, "a " + kind + " must be a mapping");
  const std::string name = y_.identifier(y_.required(node, "name", "a " + kind), kind + " name");
  at = y_.loc(node["name"]);
  claim(node["name"], name, kind);
  return name;
}

void SpatialReader::read_load(const YAML::Node& node) {
  SpatialLoad f;
  f.name = element_name(node, "force", f.loc);
  const std::string what = "force '" + f.name + "'";
  const std::string type = y_.scalar(y_.required(node, "type", what), what + " type");
  if (type != "force" && type != "torque")
    fail(node["type"],
         what + ": spatial models take force or torque elements (got '" + type + "')");
  f.torque = type == "torque";
  y_.expect_keys(node, what,
                 f.torque ? std::set<std::string>{"name", "type", "body", "value"}
                          : std::set<std::string>{"name", "type", "body", "point", "value"});
  f.body = body_ref(y_.required(node, "body", what), what + " body");
  if (!f.torque) {
    f.point = y_.identifier(y_.required(node, "point", what), what + " point");
    if (!m_.bodies[static_cast<size_t>(f.body)].find_point(f.point))
      fail(node["point"], what + ": body '" + m_.bodies[static_cast<size_t>(f.body)].name +
                              "' has no point '" + f.point + "'");
  }
  f.value = vector3(y_.required(node, "value", what), what + " value", true);
  m_.loads.push_back(f);
}

// A point named like a body would give the sweep CSV two `<name>.x` columns (the point and the
// body's centre of mass): a reader of the CSV by column name would silently get one of them.
void SpatialReader::check_point_names() const {
  for (const SpatialBody& body : m_.bodies)
    for (const SpatialPoint& p : body.points)
      if (const auto at = names_.find(p.name); at != names_.end() && at->second == "body")
        throw ModelError(p.local.x.loc, "point '" + p.name + "' of body '" + body.name +
                                            "' has the name of a body: their CSV columns '" +
                                            p.name + ".x', ... would collide; rename one");
}

// `kernel: {jacobians: [name, ...]}`: each name a moving body, a named point of one, or both.
void SpatialReader::read_kernel_options(const YAML::Node& node) {
  if (!node.IsMap()) fail(node, "kernel must be a mapping, e.g. {jacobians: [foot]}");
  y_.expect_keys(node, "kernel", {"jacobians"});
  const YAML::Node list = node["jacobians"];
  if (!list) return;
  if (!list.IsSequence()) fail(list, "kernel jacobians must be a list of body or point names");
  std::vector<std::string> names;
  for (const auto& item : list) {
    const std::string name = y_.identifier(item, "kernel jacobians entry");
    const int b = m_.body_index(name);
    bool known = b >= 0 && !m_.bodies[static_cast<size_t>(b)].ground &&
                 !m_.bodies[static_cast<size_t>(b)].is_virtual;
    for (const auto& [point, body] : m_.named_points())
      known = known || (point == name && !m_.bodies[static_cast<size_t>(body)].ground);
    if (!known)
      fail(item,
           "kernel jacobians: '" + name + "' is neither a moving body nor a named point of one");
    if (std::find(names.begin(), names.end(), name) != names.end())
      fail(item, "kernel jacobians: '" + name + "' is listed twice");
    names.push_back(name);
  }
  m_.kernel_jacobians = names;
}

SpatialModel SpatialReader::read(const YAML::Node& root) {
  m_.gravity = root["gravity"] ? vector3(root["gravity"], "gravity", false)
                               : constant_vec(0, 0, -9.81, y_.loc(root));
  // Each list in order: bodies (required), joints, drivers (pose drivers refer to joints' bodies).
  using Read = void (SpatialReader::*)(const YAML::Node&);
  const std::pair<const char*, Read> lists[] = {{"bodies", &SpatialReader::read_body},
                                                {"joints", &SpatialReader::read_joint},
                                                {"drivers", &SpatialReader::read_driver},
                                                {"forces", &SpatialReader::read_load}};
  for (const auto& [key, read_item] : lists) {
    const YAML::Node list =
        key == std::string("bodies") ? y_.required(root, key, "the model") : root[key];
    if (!list) continue;
    if (!list.IsSequence()) fail(list, std::string(key) + " must be a list");
    for (const auto& item : list) (this->*read_item)(item);
    if (m_.ground < 0) fail(list, "no ground body (mark one body 'ground: true')");
    if (key == std::string("bodies")) check_point_names();
    if (key == std::string("joints")) hold_idle_spins();
  }
  default_step(root);
  build_spatial_graph(m_);  // a body not connected to the ground, a rigid circuit: errors now
  if (root["kernel"]) read_kernel_options(root["kernel"]);
  return m_;
}

}  // namespace

const std::set<std::string>& spatial_description_keys() {
  static const std::set<std::string> keys{"gravity", "bodies", "joints",
                                          "drivers", "forces", "kernel"};
  return keys;
}

SpatialModel read_spatial_elements(const YAML::Node& root, const DescriptionSyntax& syntax,
                                   Model common) {
  SpatialModel model = SpatialReader(syntax, std::move(common)).read(root);
  check_spatial_values(model, model.common.default_parameters());
  return model;
}

}  // namespace mechgen
