// The welded single-support model (support_model.hpp).
#include "model/support_model.hpp"

#include <sstream>
#include <utility>

#include "model/fingerprint.hpp"

namespace mechgen {

namespace {

using GiNaC::ex;

// Part of the welded model's fingerprint: bump it when the transformation changes what a kernel
// of the same description computes.
constexpr int kSupportTransformVersion = 2;  // 2: the description's `kernel: {jacobians}` kept

Expr expr(const ex& e, const SourceLoc& loc) {
  std::ostringstream text;
  text << e;
  return {e, text.str(), loc};
}

// The placement: rotation Rz(heading) and translation, applied to ground-frame vectors of the
// reference pose.
struct Placement {
  ex c, s;  // cos and sin of the heading
  ex p[3];  // translation: (x, y, z) - Rz at
  ex turn;  // the heading

  Vec3Expr direction(const Vec3Expr& d) const {
    return {expr(c * d.x.ex - s * d.y.ex, d.x.loc), expr(s * d.x.ex + c * d.y.ex, d.y.loc),
            expr(d.z.ex, d.z.loc)};
  }
  Vec3Expr point(const Vec3Expr& v) const {
    const Vec3Expr r = direction(v);
    return {expr(r.x.ex + p[0], v.x.loc), expr(r.y.ex + p[1], v.y.loc),
            expr(r.z.ex + p[2], v.z.loc)};
  }
};

bool is_zero(const Expr& e) {
  return e.ex.expand().is_zero();
}

}  // namespace

std::string support_model_name(const std::string& model, const std::string& support) {
  return model + "_support_" + support;
}

std::optional<std::pair<std::string, std::string>> split_support_model_name(
    const std::string& name) {
  const std::string mark = "_support_";
  const auto at = name.rfind(mark);
  if (at == std::string::npos || at == 0 || at + mark.size() == name.size()) return std::nullopt;
  return std::make_pair(name.substr(0, at), name.substr(at + mark.size()));
}

std::string support_driver_name(const SpatialJoint& joint, size_t k) {
  return joint.columns.size() == 1 ? joint.name + "_drive"
                                   : joint.name + "_" + std::to_string(k + 1) + "_drive";
}

std::string support_weld_name(const std::string& support) {
  return support + "_weld";
}

SpatialModel weld_support(const SpatialModel& model, const std::string& support) {
  const SourceLoc file{model.common.file, 0, 0};
  const int foot = model.body_index(support);
  if (foot < 0 || foot == model.ground || model.bodies[static_cast<size_t>(foot)].is_virtual) {
    std::string known;
    for (const SpatialBody& b : model.bodies)
      if (!b.is_virtual && !b.ground) known += (known.empty() ? "" : ", ") + b.name;
    throw ModelError(file, "support '" + support + "' is not a moving body of '" +
                               model.common.name + "' (bodies: " + known + ")");
  }
  const PoseDriver* placed = nullptr;
  for (const PoseDriver& pd : model.pose_drivers)
    if (pd.second == foot && pd.first == model.ground) placed = &pd;
  if (!placed)
    throw ModelError(file, "support '" + support +
                               "': no pose driver places it from the ground (its `at` point is "
                               "what the support's placement places)");

  SpatialModel out;
  out.common = model.common;
  // The Jacobians the description asks its kernels for (`kernel: {jacobians: [...]}`), not every
  // body's: the support foot is the ground here and has none.
  out.kernel_jacobians = model.kernel_jacobians;
  Model& common = out.common;
  common.name = support_model_name(model.common.name, support);
  common.description = model.common.description + "; single support on " + support +
                       ", welded to the floor at its placement";
  Fnv1a64 hash;
  hash.add_field("single support");
  hash.add_field(std::to_string(kSupportTransformVersion));
  hash.add_field(hex64(model.common.description_hash));
  hash.add_field(support);
  common.description_hash = hash.value();

  // The placement parameters, defaults: the `at` point where the description puts it, no turn.
  const std::vector<double> defaults = model.common.default_parameters();
  const GiNaC::exmap values = model.common.substitutions(defaults);
  const double at_default[3] = {model.evaluate(placed->at.x, values),
                                model.evaluate(placed->at.y, values),
                                model.evaluate(placed->at.z, values)};
  ex placement[4];
  for (int i = 0; i < 4; ++i) {
    const std::string name = kSupportPlacement[i];
    if (common.parameter_index(name) >= 0 || common.derived_index(name) >= 0)
      throw ModelError(file, "parameter '" + name +
                                 "' is the support's placement in a single-support kernel: "
                                 "rename the description's own");
    Parameter p;
    p.name = name;
    p.value = i < 3 ? at_default[i] : 0.0;
    p.unit = i < 3 ? "m" : "rad";
    p.doc = i < 3 ? std::string("support placement: ground ") + "xyz"[i] + " of its point " +
                        (placed->at_point.empty() ? "`at`" : placed->at_point)
                  : "support placement: turn about the ground z axis";
    p.symbol = GiNaC::symbol(name);
    p.loc = placed->loc;
    placement[i] = p.symbol;
    common.parameters.push_back(p);
  }
  Placement P;
  P.turn = placement[3];
  P.c = GiNaC::cos(P.turn);
  P.s = GiNaC::sin(P.turn);
  const Vec3Expr at_turned = P.direction(placed->at);
  P.p[0] = placement[0] - at_turned.x.ex;
  P.p[1] = placement[1] - at_turned.y.ex;
  P.p[2] = placement[2] - at_turned.z.ex;

  // Real bodies, frames placed.
  std::vector<int> body_index(model.bodies.size(), -1);
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    const SpatialBody& body = model.bodies[b];
    if (body.is_virtual) continue;
    body_index[b] = static_cast<int>(out.bodies.size());
    SpatialBody placed_body = body;
    if (!body.ground) {
      placed_body.origin = P.point(body.origin);
      const Vec3Expr& a = body.rotation_axis;
      ex angle;
      if (is_zero(body.rotation_angle)) {
        angle = P.turn;
      } else if (is_zero(a.x) && is_zero(a.y) && (a.z.ex - 1).expand().is_zero()) {
        angle = body.rotation_angle.ex + P.turn;
      } else if (is_zero(a.x) && is_zero(a.y) && (a.z.ex + 1).expand().is_zero()) {
        angle = P.turn - body.rotation_angle.ex;
      } else {
        throw ModelError(body.rotation_angle.loc,
                         "body '" + body.name +
                             "': a single-support kernel places body frames by a turn about z; "
                             "this one is rotated about another axis at the reference pose");
      }
      placed_body.rotation_axis = {expr(0, body.loc), expr(0, body.loc), expr(1, body.loc)};
      placed_body.rotation_angle = expr(angle, body.rotation_angle.loc);
    }
    out.bodies.push_back(std::move(placed_body));
  }
  out.ground = body_index[static_cast<size_t>(model.ground)];

  auto taken = [&](const std::string& name) {
    if (out.body_index(name) >= 0 || out.joint_index(name) >= 0 ||
        common.parameter_index(name) >= 0)
      throw ModelError(file, "'" + name +
                                 "' is a name the single-support kernel gives its weld or a "
                                 "joint's driver: rename the description's own");
  };
  // Real joints, axes and points placed, each coordinate driven.
  for (const SpatialJoint& joint : model.joints) {
    if (joint.is_virtual) continue;
    if (joint.first == model.ground || joint.second == model.ground)
      throw ModelError(joint.loc, "joint '" + joint.name +
                                      "' attaches the robot to the ground: a single-support "
                                      "kernel takes a robot that touches only the floor");
    SpatialJoint j = joint;
    j.first = body_index[static_cast<size_t>(joint.first)];
    j.second = body_index[static_cast<size_t>(joint.second)];
    j.s = P.direction(joint.s);
    j.s2 = P.direction(joint.s2);
    j.s0 = P.point(joint.s0);
    for (ScrewColumnExpr& c : j.columns) c.s = P.direction(c.s);
    out.joints.push_back(std::move(j));
  }
  for (size_t j = 0; j < out.joints.size(); ++j) {
    const SpatialJoint& joint = out.joints[j];
    for (size_t k = 0; k < joint.columns.size(); ++k) {
      SpatialDriver d;
      d.name = support_driver_name(joint, k);
      taken(d.name);
      d.joint = static_cast<int>(j);
      d.column = static_cast<int>(k);
      d.kind = joint.columns[k].kind == ScrewColumnKind::translation ? DriverKind::length
                                                                     : DriverKind::angle;
      d.value = expr(0, joint.loc);
      d.value_d = 0;
      d.value_dd = 0;
      d.range = joint.range;
      d.loc = joint.loc;
      out.drivers.push_back(std::move(d));
    }
  }
  SpatialJoint weld;
  weld.name = support_weld_name(support);
  taken(weld.name);
  weld.type = SpatialJointType::fixed;
  weld.first = out.ground;
  weld.second = body_index[static_cast<size_t>(foot)];
  weld.s = {expr(0, placed->loc), expr(0, placed->loc), expr(1, placed->loc)};
  weld.s2 = {expr(1, placed->loc), expr(0, placed->loc), expr(0, placed->loc)};
  weld.s0 = {expr(placement[0], placed->loc), expr(placement[1], placed->loc),
             expr(placement[2], placed->loc)};
  weld.point = placed->at_point;
  weld.pitch = expr(0, placed->loc);
  weld.loc = placed->loc;
  out.joints.push_back(std::move(weld));

  // Applied loads: ground-frame components stay the world's; their bodies are real.
  for (const SpatialLoad& load : model.loads) {
    SpatialLoad l = load;
    l.body = body_index[static_cast<size_t>(load.body)];
    if (l.body < 0) throw ModelError(load.loc, "load '" + load.name + "' acts on a virtual body");
    out.loads.push_back(std::move(l));
  }
  out.gravity = model.gravity;
  return out;
}

}  // namespace mechgen
