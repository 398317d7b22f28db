// A description built by the import, written as a readable spatial model: the source's names,
// numbers in their shortest exact form, and a header saying where it came from and what was
// converted.
#include <charconv>
#include <cmath>
#include <sstream>

#include "import/import_tree.hpp"

namespace mechgen::import {

std::string shortest(double v, double dust) {
  if (std::abs(v) < dust) v = 0;
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, result.ptr);
}

namespace {

std::string num(double v) {
  return shortest(v, 1e-14);
}

std::string vec(const Vec3& v) {
  return "[" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + "]";
}

const char* type_name(JointType t) {
  switch (t) {
    case JointType::revolute:
      return "revolute";
    case JointType::prismatic:
      return "prismatic";
    case JointType::spherical:
      return "spherical";
    case JointType::universal:
      return "universal";
    case JointType::fixed:
      return "fixed";
  }
  return "fixed";
}

}  // namespace

std::string write_model(const Description& d) {
  std::ostringstream o;
  o << "# Imported by `mechgen import` from " << d.source << ".\n";
  o << "# Reference pose (every joint coordinate 0): the source's loops closed by Newton-Raphson\n"
       "# with the actuated joints at their source values; axes, points and frames are given "
       "there\n"
       "# (ground frame = the source's root link frame). A joint's source coordinate at that pose\n"
       "# is in its comment. Conversions:\n";
  for (const std::string& note : d.notes) o << "#  - " << note << "\n";
  o << "name: " << identifier(d.name) << "\n";
  o << "description: \"" << d.name << ", imported from " << d.source << "\"\n";
  o << "dimension: spatial\n";
  o << "gravity: " << vec(d.gravity) << "\n\n";
  o << "parameters:\n";
  o << "  amplitude: {value: 0.05, unit: rad, doc: \"drivers' motion about the assembled pose\"}\n";
  o << "  w: {value: 6.283185307179586, unit: rad/s, doc: \"drivers' angular frequency\"}\n";
  for (const Driver& dr : d.drivers) {
    if (!dr.passive) continue;
    const bool linear = d.joints[static_cast<size_t>(dr.joint)].type == JointType::prismatic;
    o << "  k_" << identifier(dr.name) << ": {value: " << num(dr.stiffness)
      << ", unit: " << (linear ? "N/m" : "N m/rad") << ", doc: \"" << dr.name
      << "'s spring stiffness\"}\n";
    o << "  c_" << identifier(dr.name) << ": {value: " << num(dr.damping)
      << ", unit: " << (linear ? "N s/m" : "N m s/rad") << ", doc: \"" << dr.name
      << "'s damping\"}\n";
  }
  o << "\n";
  o << "bodies:\n";
  for (const Body& b : d.bodies) {
    o << "  - name: " << identifier(b.name) << "\n";
    if (b.ground) o << "    ground: true\n";
    if (!b.ground) {
      const Vec3 t = b.frame.translation();
      if (t.norm() > 1e-14) o << "    origin: " << vec(t) << "\n";
      const Eigen::AngleAxisd aa(b.frame.linear());
      if (std::abs(aa.angle()) > 1e-15)
        o << "    rotation: {axis: " << vec(aa.axis().normalized())
          << ", angle: " << num(aa.angle()) << "}\n";
    }
    if (!b.points.empty()) {
      o << "    points:\n";
      for (const auto& [name, x] : b.points)
        o << "      " << identifier(name) << ": " << vec(x) << "\n";
    }
    if (!b.ground) {
      const Mat3 I = (b.inertia + b.inertia.transpose()) / 2;
      o << "    mass: {mass: " << num(b.mass) << ", com: " << vec(b.com) << ",\n"
        << "           inertia: [" << vec(I.row(0)) << ", " << vec(I.row(1)) << ", "
        << vec(I.row(2)) << "]}\n";
    }
    if (!b.merged.empty()) {
      o << "    # merged source links:";
      for (const std::string& m : b.merged) o << " " << m;
      o << "\n";
    }
  }
  o << (d.joints.empty() ? "\njoints: []\n" : "\njoints:\n");  // a floating body alone
  for (const Joint& j : d.joints) {
    o << "  - {name: " << identifier(j.name) << ", type: " << type_name(j.type)
      << ", first: " << identifier(d.bodies[static_cast<size_t>(j.first)].name)
      << ", second: " << identifier(d.bodies[static_cast<size_t>(j.second)].name) << ",\n     ";
    if (j.type == JointType::revolute || j.type == JointType::prismatic ||
        j.type == JointType::universal)
      o << "s: " << vec(j.s) << ", ";
    if (j.type == JointType::universal) o << "s2: " << vec(j.s2) << ", ";
    o << "s0: " << vec(j.s0) << "}";
    std::string comment = j.comment;
    if (j.type == JointType::revolute || j.type == JointType::prismatic)
      comment +=
          (comment.empty() ? "" : "; ") + std::string("source coordinate here: ") +
          num(j.source_value) +
          (j.lower < j.upper ? ", source limits [" + num(j.lower) + ", " + num(j.upper) + "]" : "");
    if (!comment.empty()) o << "  # " << comment;
    o << "\n";
  }
  o << "\ndrivers:   # the actuated joints (coordinates from the assembled pose): the law the "
       "source\n           # carries (mechgen export), else a small motion about that pose; "
       "sprung joints\n           # (--springs): passive, held at their rest, their spring "
       "the effort under simulate\n";
  for (const Driver& dr : d.drivers) {
    const Joint& j = d.joints[static_cast<size_t>(dr.joint)];
    o << "  - {name: " << identifier(dr.name) << ", joint: " << identifier(j.name)
      << ", kind: " << (j.type == JointType::prismatic ? "length" : "angle");
    const std::string id = identifier(dr.name);
    if (dr.passive)
      o << ", value: 0, passive: true,\n     effort: -k_" << id << "*q - c_" << id << "*qd}\n";
    else
      o << ", value: " << (dr.value.empty() ? "amplitude*sin(w*t)" : "\"" + dr.value + "\"")
        << "}\n";
  }
  for (const PoseDriver& pd : d.pose_drivers)
    o << "  - {name: " << pd.name
      << ", type: pose, first: " << identifier(d.bodies[static_cast<size_t>(pd.first)].name)
      << ", second: " << identifier(d.bodies[static_cast<size_t>(pd.second)].name)
      << ", at: " << vec(pd.at) << ",\n     x: " << num(pd.at.x()) << ", y: " << num(pd.at.y())
      << ", z: " << num(pd.at.z())
      << ", rotations: [{axis: z, value: 0}, {axis: y, value: 0}, {axis: x, value: 0}]}"
      << "  # the floating base at its source pose\n";
  if (d.step)
    o << "\nstep: {t0: " << num(d.step->t0) << ", t1: " << num(d.step->t1)
      << ", samples: " << d.step->samples << "}\n";
  else
    o << "\nstep: {t0: 0, t1: 2*pi/w, samples: 101}\n";
  return o.str();
}

}  // namespace mechgen::import
