// A spatial model as URDF (+ Extended URDF closures) or MJCF (model_export.hpp).
#include "import/model_export.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <sstream>

#include "import/import_tree.hpp"
#include "spatial/spatial_solver.hpp"

namespace mechgen::import {

namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Frame = Eigen::Isometry3d;

std::string num(double v) {
  return shortest(v, 1e-15);
}
std::string triple(const Vec3& v) {
  return num(v.x()) + " " + num(v.y()) + " " + num(v.z());
}
Vec3 vec(const spatial::V3& v) {
  return Vec3(v[0], v[1], v[2]);
}
Frame frame(const spatial::Pose& p) {
  Frame f = Frame::Identity();
  for (int i = 0; i < 3; ++i) {
    f.translation()[i] = p.p[static_cast<size_t>(i)];
    for (int k = 0; k < 3; ++k) f.linear()(i, k) = p.R(i, k);
  }
  return f;
}
Frame at(const Mat3& R, const Vec3& p) {
  Frame f = Frame::Identity();
  f.linear() = R;
  f.translation() = p;
  return f;
}
// URDF's roll-pitch-yaw (R = Rz(yaw) Ry(pitch) Rx(roll)).
Vec3 rpy(const Mat3& R) {
  const double pitch = std::atan2(-R(2, 0), std::hypot(R(0, 0), R(1, 0)));
  if (std::abs(std::cos(pitch)) < 1e-12) return Vec3(std::atan2(-R(1, 2), R(1, 1)), pitch, 0);
  return Vec3(std::atan2(R(2, 1), R(2, 2)), pitch, std::atan2(R(1, 0), R(0, 0)));
}
std::string quat(const Mat3& R) {
  const Eigen::Quaterniond q(R);
  return num(q.w()) + " " + num(q.x()) + " " + num(q.y()) + " " + num(q.z());
}

// One elementary motion of a joint: a rotation or a translation along an axis (ground frame,
// reference pose), in the order the tree runs through it.
struct Step {
  bool rotation = true;
  Vec3 axis;
};

// What both formats need: the model's numbers, the tree, each joint's steps.
struct Layout {
  const SpatialModel& m;
  spatial::SpatialSolver solver;
  std::vector<Frame> body;  // body frames, reference pose
  Layout(const SpatialModel& model) : m(model), solver(model, {}) {
    if (!m.pose_drivers.empty())
      throw ModelError(m.bodies.back().loc,
                       "pose drivers (virtual chains) have no URDF or MJCF form: export a model "
                       "with joint drivers");
    for (const SpatialJoint& j : m.joints)
      if (j.type == SpatialJointType::helical)
        throw ModelError(j.loc, "joint '" + j.name + "': a helical joint has no URDF or MJCF form");
    for (const SpatialDriver& d : m.drivers)
      if (d.table)
        throw ModelError(d.value.loc, "driver '" + d.name +
                                          "': follows a table; the exported driver law is a "
                                          "number or a law of t: export the model with a law");
    for (const SpatialDriver& d : m.drivers)
      if (m.joints[static_cast<size_t>(d.joint)].columns.size() != 1)
        throw ModelError(d.loc, "driver '" + d.name +
                                    "': drives one coordinate of a multi-coordinate joint; "
                                    "URDF and MJCF actuate one-coordinate joints");
    for (const spatial::Pose& p : solver.instance().body_frame) body.push_back(frame(p));
  }
  const SpatialGraph& graph() const { return solver.graph(); }
  Vec3 s0(int j) const { return vec(solver.instance().joint_point[static_cast<size_t>(j)]); }
  // The joint's steps from `from` (its first or second body) to the other.
  std::vector<Step> steps(int j, int from) const {
    const SpatialJoint& joint = m.joints[static_cast<size_t>(j)];
    const int c0 = graph().joint_column[static_cast<size_t>(j)];
    std::vector<Step> out;
    for (size_t k = 0; k < joint.columns.size(); ++k) {
      const auto& axis = solver.instance().axes[static_cast<size_t>(c0) + k];
      out.push_back({axis.kind != geometry::ScrewKind::translation, vec(axis.s)});
    }
    if (from == joint.second) {
      std::reverse(out.begin(), out.end());
      for (Step& s : out) s.axis = -s.axis;
    }
    return out;
  }
  // A driver's law with the default parameters in (numbers: what a URDF or MJCF file holds).
  std::string law(const SpatialDriver& d) const {
    const GiNaC::exmap subs = m.common.substitutions(m.common.default_parameters());
    std::ostringstream o;
    o.precision(17);
    o << d.value.ex.subs(subs).evalf();
    return o.str();
  }
  // A passive driver's law as MJCF's joint spring: -k (q - rest) - c q', numbers at the default
  // parameters. Any other law (of t, or not linear in q and q') has no MJCF form: ModelError.
  struct Spring {
    double stiffness = 0, damping = 0, rest = 0;
  };
  Spring spring(const SpatialDriver& d) const {
    const GiNaC::exmap subs = m.common.substitutions(m.common.default_parameters());
    const GiNaC::ex law = d.effort->ex.subs(subs).expand();
    const GiNaC::symbol &q = m.common.driver_q, &qd = m.common.driver_qd;
    auto number = [](const GiNaC::ex& e) {
      const GiNaC::ex v = e.evalf();
      return GiNaC::is_a<GiNaC::numeric>(v) ? GiNaC::ex_to<GiNaC::numeric>(v).to_double()
                                            : std::nan("");
    };
    const GiNaC::ex dq = law.diff(q), dqd = law.diff(qd);
    Spring out{-number(dq), -number(dqd), 0};
    const double at_rest = number(law.subs(GiNaC::lst{q == 0, qd == 0}));
    if (law.has(m.common.t) || !std::isfinite(out.stiffness) || !std::isfinite(out.damping) ||
        !std::isfinite(at_rest) || out.stiffness < 0 || out.damping < 0 ||
        (out.stiffness == 0 && at_rest != 0))
      throw ModelError(d.effort->loc, "passive driver '" + d.name +
                                          "': MJCF holds a joint spring -k*(q - rest) - c*qd "
                                          "(k, c >= 0, constant), not this law");
    if (out.stiffness > 0) out.rest = at_rest / out.stiffness;
    return out;
  }
  std::string step() const {
    const GiNaC::exmap subs = m.common.substitutions(m.common.default_parameters());
    return num(m.evaluate(m.common.step.t0, subs)) + " " + num(m.evaluate(m.common.step.t1, subs)) +
           " " + std::to_string(m.common.step.samples);
  }
};

}  // namespace

UrdfExport export_urdf(const SpatialModel& model, const std::string& source) {
  const Layout L(model);
  const SpatialGraph& g = L.graph();
  const auto& inst = L.solver.instance();
  std::ostringstream u, links, joints;
  const size_t nb = model.bodies.size();
  // Link frames: on the axis of the tree joint (URDF turns a child about its frame's origin).
  std::vector<Frame> link(nb, Frame::Identity());
  for (const int b : g.order) {
    const int j = g.parent_joint[static_cast<size_t>(b)];
    if (j < 0 || model.joints[static_cast<size_t>(j)].type == SpatialJointType::fixed)
      link[static_cast<size_t>(b)] = model.bodies[static_cast<size_t>(b)].ground
                                         ? Frame::Identity()
                                         : L.body[static_cast<size_t>(b)];
    else
      link[static_cast<size_t>(b)] = at(L.body[static_cast<size_t>(b)].linear(), L.s0(j));
  }
  auto link_text = [&](const std::string& name, const Frame* L_frame, int b) {
    links << "  <link name=\"" << name << "\">\n";
    if (b >= 0 && !model.bodies[static_cast<size_t>(b)].ground &&
        inst.mass[static_cast<size_t>(b)] > 0) {
      const Frame to_link = L_frame->inverse() * L.body[static_cast<size_t>(b)];
      const Vec3 com = to_link * vec(inst.com[static_cast<size_t>(b)]);
      Mat3 I;
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) I(i, k) = inst.inertia[static_cast<size_t>(b)](i, k);
      I = to_link.linear() * I * to_link.linear().transpose();
      links << "    <inertial>\n      <origin xyz=\"" << triple(com) << "\" rpy=\"0 0 0\"/>\n"
            << "      <mass value=\"" << num(inst.mass[static_cast<size_t>(b)]) << "\"/>\n"
            << "      <inertia ixx=\"" << num(I(0, 0)) << "\" ixy=\"" << num(I(0, 1)) << "\" ixz=\""
            << num(I(0, 2)) << "\" iyy=\"" << num(I(1, 1)) << "\" iyz=\"" << num(I(1, 2))
            << "\" izz=\"" << num(I(2, 2)) << "\"/>\n    </inertial>\n";
    }
    links << "  </link>\n";
  };
  auto joint_text = [&](const std::string& name, const std::string& type, const std::string& parent,
                        const std::string& child, const Frame& origin, const Vec3* axis) {
    joints << "  <joint name=\"" << name << "\" type=\"" << type << "\">\n"
           << "    <origin xyz=\"" << triple(origin.translation()) << "\" rpy=\""
           << triple(rpy(origin.linear())) << "\"/>\n"
           << "    <parent link=\"" << parent << "\"/>\n    <child link=\"" << child << "\"/>\n";
    if (axis) joints << "    <axis xyz=\"" << triple(*axis) << "\"/>\n";
    if (type == "prismatic")  // URDF wants limits on a prismatic joint: none meant
      joints << "    <limit lower=\"-1e9\" upper=\"1e9\" effort=\"0\" velocity=\"0\"/>\n";
    joints << "  </joint>\n";
  };
  // A joint as a chain of revolutes and prismatics from link `parent` (frame P) to link `child`
  // (frame C, on the joint's point): massless links between.
  auto chain = [&](int j, int from, const std::string& parent, const Frame& P,
                   const std::string& child, const Frame& C) {
    const std::vector<Step> st = L.steps(j, from);
    const std::string& name = model.joints[static_cast<size_t>(j)].name;
    std::string prev = parent;
    Frame prev_frame = P;
    for (size_t k = 0; k < st.size(); ++k) {
      const bool last = k + 1 == st.size();
      const std::string next = last ? child : name + "_int" + std::to_string(k + 1);
      const Vec3 axis = C.linear().transpose() * st[k].axis;
      joint_text(
          st.size() == 1 ? name : name + (st[k].rotation ? "_rev" : "_pri") + std::to_string(k),
          st[k].rotation ? "continuous" : "prismatic", prev, next, prev_frame.inverse() * C, &axis);
      if (!last) link_text(next, nullptr, -1);
      prev = next, prev_frame = C;
    }
  };
  for (size_t b = 0; b < nb; ++b) link_text(model.bodies[b].name, &link[b], static_cast<int>(b));
  for (const int b : g.order) {
    const int j = g.parent_joint[static_cast<size_t>(b)];
    if (j < 0) continue;
    const int p = g.parent[static_cast<size_t>(b)];
    const SpatialJoint& joint = model.joints[static_cast<size_t>(j)];
    if (joint.type == SpatialJointType::fixed)
      joint_text(joint.name, "fixed", model.bodies[static_cast<size_t>(p)].name,
                 model.bodies[static_cast<size_t>(b)].name,
                 link[static_cast<size_t>(p)].inverse() * link[static_cast<size_t>(b)], nullptr);
    else
      chain(j, p, model.bodies[static_cast<size_t>(p)].name, link[static_cast<size_t>(p)],
            model.bodies[static_cast<size_t>(b)].name, link[static_cast<size_t>(b)]);
  }
  // Named points (each on the first body that carries it, as the sweep reports it): frame links
  // on fixed joints.
  for (const auto& [name, bi] : model.named_points()) {
    const size_t b = static_cast<size_t>(bi);
    size_t k = 0;
    while (model.bodies[b].points[k].name != name) ++k;
    link_text(name, nullptr, -1);
    joint_text(name + "_frame", "fixed", model.bodies[b].name, name,
               at(Mat3::Identity(), link[b].inverse() * (L.body[b] * vec(inst.points[b][k]))),
               nullptr);
  }
  std::ostringstream pairs, types, mot;
  for (const int j : g.chords) {
    const SpatialJoint& joint = model.joints[static_cast<size_t>(j)];
    const std::string& A = model.bodies[static_cast<size_t>(joint.first)].name;
    const std::string& B = model.bodies[static_cast<size_t>(joint.second)].name;
    const Frame& LA = link[static_cast<size_t>(joint.first)];
    const Frame& LB = link[static_cast<size_t>(joint.second)];
    const Frame cut = at(L.body[static_cast<size_t>(joint.second)].linear(), L.s0(j));
    if (joint.type == SpatialJointType::spherical) {
      link_text(joint.name + "_A", nullptr, -1);
      joint_text(joint.name + "_A_frame", "fixed", A, joint.name + "_A", LA.inverse() * cut,
                 nullptr);
      types << (pairs.tellp() > 0 ? ", " : "") << "'3d'";
    } else {
      link_text(joint.name + "_A", nullptr, -1);
      if (joint.type == SpatialJointType::fixed)
        joint_text(joint.name + "_A_frame", "fixed", A, joint.name + "_A", LA.inverse() * cut,
                   nullptr);
      else
        chain(j, joint.first, A, LA, joint.name + "_A", cut);
      types << (pairs.tellp() > 0 ? ", " : "") << "'6d'";
    }
    link_text(joint.name + "_B", nullptr, -1);
    joint_text(joint.name + "_B_frame", "fixed", B, joint.name + "_B", LB.inverse() * cut, nullptr);
    pairs << (pairs.tellp() > 0 ? ", " : "") << "['" << joint.name << "_A', '" << joint.name
          << "_B']";
  }
  for (size_t d = 0; d < model.drivers.size(); ++d)
    mot << (d ? ", " : "") << "'" << model.joints[static_cast<size_t>(model.drivers[d].joint)].name
        << "'";
  u << "<?xml version=\"1.0\"?>\n<!-- Exported by `mechgen export` from " << source
    << " (default parameters, reference pose): the joint graph's spanning tree; the loops it cuts "
       "are closed by the Extended URDF file beside it. -->\n<robot name=\""
    << model.common.name << "\">\n"
    << links.str() << joints.str() << "</robot>\n";
  UrdfExport out;
  out.urdf = u.str();
  std::ostringstream y;
  y << "# Extended URDF closures, exported by `mechgen export` from " << source << ".\n";
  for (const SpatialDriver& d : model.drivers)
    y << "# driver " << d.name << " on " << model.joints[static_cast<size_t>(d.joint)].name
      << ": value " << d.value.text
      << (d.passive ? " (passive, effort " + d.effort->text +
                          ": URDF has no joint spring, so it is a driver held at its value here)"
                    : "")
      << "\n";
  y << "gravity: [" << num(inst.gravity[0]) << ", " << num(inst.gravity[1]) << ", "
    << num(inst.gravity[2]) << "]  # not in the Extended URDF convention: mechgen's addition\n";
  y << "closed_loop: [" << pairs.str() << "]\ntype: [" << types.str() << "]\nname_mot: ["
    << mot.str() << "]\n";
  y << "# mechgen's additions: each driver's law (default parameters) and name, the default step\n";
  std::string values, names;
  for (const SpatialDriver& d : model.drivers) {
    values += (values.empty() ? "'" : ", '") + L.law(d) + "'";
    names += (names.empty() ? "'" : ", '") + d.name + "'";
  }
  y << "driver_values: [" << values << "]\ndriver_names: [" << names << "]\n";
  const std::string st = L.step();
  y << "step: [" << st.substr(0, st.find(' ')) << ", "
    << st.substr(st.find(' ') + 1, st.rfind(' ') - st.find(' ') - 1) << ", "
    << st.substr(st.rfind(' ') + 1) << "]\n";
  out.closures = y.str();
  return out;
}

std::string export_mjcf(const SpatialModel& model, const std::string& source) {
  const Layout L(model);
  const SpatialGraph& g = L.graph();
  const auto& inst = L.solver.instance();
  const size_t nb = model.bodies.size();
  std::vector<Frame> frame(nb);  // the frames bodies nest in: the ground is the world
  for (size_t b = 0; b < nb; ++b) frame[b] = model.bodies[b].ground ? Frame::Identity() : L.body[b];
  std::ostringstream x, eq;
  auto x_site = [&](const std::string& indent, const std::string& name, const Vec3& p) {
    x << indent << "<site name=\"" << name << "\" pos=\"" << triple(p) << "\"/>\n";
  };
  auto inertial = [&](int b, const std::string& indent) {
    if (model.bodies[static_cast<size_t>(b)].ground || inst.mass[static_cast<size_t>(b)] <= 0)
      return;
    const auto& I = inst.inertia[static_cast<size_t>(b)];
    x << indent << "<inertial pos=\"" << triple(vec(inst.com[static_cast<size_t>(b)]))
      << "\" mass=\"" << num(inst.mass[static_cast<size_t>(b)]) << "\" ";
    Mat3 inertia;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) inertia(i, k) = I(i, k);
    // Principal axes and moments (zero moments of a point mass lifted by the compiler's bound):
    // MuJoCo would find them from a fullinertia itself, but only to about 1e-8 of the moments
    // (the round trip of leg6 then 6.5e-13 off in its efforts), and it refuses one without positive
    // eigenvalues (the Delta's rods).
    if (inertia.isDiagonal(0)) {
      x << "diaginertia=\"" << triple(inertia.diagonal()) << "\"/>\n";
      return;
    }
    const Eigen::SelfAdjointEigenSolver<Mat3> principal(inertia);
    Mat3 axes = principal.eigenvectors();
    if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
    x << "quat=\"" << quat(axes) << "\" diaginertia=\""
      << triple(principal.eigenvalues().cwiseMax(0)) << "\"/>\n";
  };
  // A joint's steps as joints of the body they move (axes and point in its frame F).
  auto steps = [&](int j, int from, const Frame& F, const std::string& indent) {
    const SpatialJoint& joint = model.joints[static_cast<size_t>(j)];
    const std::vector<Step> st = L.steps(j, from);
    if (joint.type == SpatialJointType::spherical) {
      x << indent << "<joint name=\"" << joint.name << "\" type=\"ball\" pos=\""
        << triple(F.inverse() * L.s0(j)) << "\"/>\n";
      return;
    }
    // A passive driver's spring (its joint has one coordinate), its rest in the tree's sense.
    std::string spring;
    for (const SpatialDriver& d : model.drivers)
      if (d.passive && d.joint == j) {
        const Layout::Spring k = L.spring(d);
        spring = " stiffness=\"" + num(k.stiffness) + "\" damping=\"" + num(k.damping) +
                 "\" springref=\"" + num(from == joint.second ? -k.rest : k.rest) + "\"";
      }
    for (size_t k = 0; k < st.size(); ++k)
      x << indent << "<joint name=\""
        << (st.size() == 1 ? joint.name
                           : joint.name + (st[k].rotation ? "_rev" : "_pri") + std::to_string(k))
        << "\" type=\"" << (st[k].rotation ? "hinge" : "slide") << "\" pos=\""
        << triple(F.inverse() * L.s0(j)) << "\" axis=\""
        << triple(F.linear().transpose() * st[k].axis) << "\"" << spring << "/>\n";
  };
  // Named points (each on the first body that carries it) as sites, body frame.
  auto sites = [&](int b, const std::string& indent) {
    for (const auto& [name, bi] : model.named_points()) {
      if (bi != b) continue;
      size_t k = 0;
      while (model.bodies[static_cast<size_t>(b)].points[k].name != name) ++k;
      const Vec3 x = frame[static_cast<size_t>(b)].inverse() *
                     (L.body[static_cast<size_t>(b)] * vec(inst.points[static_cast<size_t>(b)][k]));
      x_site(indent, name, x);
    }
  };
  std::function<void(int, const std::string&)> body = [&](int b, const std::string& indent) {
    const int p = g.parent[static_cast<size_t>(b)];
    const Frame rel = frame[static_cast<size_t>(p)].inverse() * frame[static_cast<size_t>(b)];
    x << indent << "<body name=\"" << model.bodies[static_cast<size_t>(b)].name << "\" pos=\""
      << triple(rel.translation()) << "\" quat=\"" << quat(rel.linear()) << "\">\n";
    const int j = g.parent_joint[static_cast<size_t>(b)];
    if (model.joints[static_cast<size_t>(j)].type != SpatialJointType::fixed)
      steps(j, p, frame[static_cast<size_t>(b)], indent + "  ");
    inertial(b, indent + "  ");
    sites(b, indent + "  ");
    for (const int c : g.order)
      if (g.parent[static_cast<size_t>(c)] == b) body(c, indent + "  ");
    // Cut links of the chords from this body: the chord's joint, welded to its second body.
    for (const int cj : g.chords) {
      const SpatialJoint& joint = model.joints[static_cast<size_t>(cj)];
      if (joint.first != b || joint.type == SpatialJointType::spherical ||
          joint.type == SpatialJointType::fixed)
        continue;
      const Frame cut = at(L.body[static_cast<size_t>(joint.second)].linear(), L.s0(cj));
      const Frame crel = frame[static_cast<size_t>(b)].inverse() * cut;
      x << indent << "  <body name=\"" << joint.name << "_A\" pos=\"" << triple(crel.translation())
        << "\" quat=\"" << quat(crel.linear()) << "\">\n";
      steps(cj, b, cut, indent + "    ");
      // The compiler's bounds, written out: 1e-12 kg (a weight MuJoCo's driver efforts feel, 1e-12
      // of them). Left to the bounds (no <inertial>), MuJoCo's soft weld no longer holds the cut
      // link: rsur/mujoco's crank acceleration was off by twice its scale at any impedance.
      x << indent
        << "    <inertial pos=\"0 0 0\" mass=\"1e-12\" diaginertia=\"1e-14 1e-14 1e-14\"/>\n";
      x << indent << "  </body>\n";
    }
    x << indent << "</body>\n";
  };
  // Massless bodies (no <inertial>) take the compiler's bounds; MuJoCo refuses a moving body whose
  // mass or inertia is below mjMINVAL (1e-15) unless a welded child carries some, so the bounds
  // are above it (a massless subtree on joints: the Bioloid's wrists and hands).
  x << "<!-- Exported by `mechgen export` from " << source
    << " (default parameters, reference pose): the joint graph's spanning tree; the loops it cuts "
       "are closed by equality constraints. -->\n<mujoco model=\""
    << model.common.name << "\">\n  <compiler angle=\"radian\" boundmass=\"1e-12\" "
    << "boundinertia=\"1e-14\"/>\n  <option gravity=\"" << triple(vec(inst.gravity)) << "\"/>\n"
    << "  <worldbody>\n";
  sites(model.ground, "    ");
  for (const int b : g.order)
    if (g.parent[static_cast<size_t>(b)] >= 0 &&
        model.bodies[static_cast<size_t>(g.parent[static_cast<size_t>(b)])].ground)
      body(b, "    ");
  x << "  </worldbody>\n";
  for (const int cj : g.chords) {
    const SpatialJoint& joint = model.joints[static_cast<size_t>(cj)];
    const std::string& A = model.bodies[static_cast<size_t>(joint.first)].name;
    const std::string& B = model.bodies[static_cast<size_t>(joint.second)].name;
    if (joint.type == SpatialJointType::spherical)
      eq << "    <connect name=\"" << joint.name << "\" body1=\"" << A << "\" body2=\"" << B
         << "\" anchor=\"" << triple(frame[static_cast<size_t>(joint.first)].inverse() * L.s0(cj))
         << "\"/>\n";
    else
      eq << "    <weld name=\"" << joint.name << "\" body1=\""
         << (joint.type == SpatialJointType::fixed ? A : joint.name + "_A") << "\" body2=\"" << B
         << "\"/>\n";
  }
  if (eq.tellp() > 0) x << "  <equality>\n" << eq.str() << "  </equality>\n";
  // Passive drivers are their joints' springs (above), named back by `import --springs`.
  std::ostringstream motors, texts;
  for (const SpatialDriver& d : model.drivers) {
    const std::string& joint = model.joints[static_cast<size_t>(d.joint)].name;
    if (d.passive) {
      texts << "    <text name=\"mechgen_spring_" << joint << "\" data=\"" << d.name << "\"/>\n";
      continue;
    }
    motors << "    <motor name=\"" << d.name << "\" joint=\"" << joint << "\"/>  <!-- value "
           << d.value.text << " -->\n";
    texts << "    <text name=\"mechgen_value_" << d.name << "\" data=\"" << L.law(d) << "\"/>\n";
  }
  if (motors.tellp() > 0) x << "  <actuator>\n" << motors.str() << "  </actuator>\n";
  if (!model.drivers.empty())
    x << "  <custom>\n"
      << texts.str() << "    <text name=\"mechgen_step\" data=\"" << L.step()
      << "\"/>\n  </custom>\n";
  x << "</mujoco>\n";
  return x.str();
}

}  // namespace mechgen::import
