// MJCF through MuJoCo's own compiler (mj_loadXML): defaults, frames (euler, xyaxes, quat, ...),
// units and inertias as MuJoCo interprets them, read back from the compiled mjModel.
#include <mujoco/mujoco.h>

#include <cmath>
#include <memory>
#include <regex>
#include <sstream>

#include "import/import_tree.hpp"

namespace mechgen::import {

namespace {

Frame pose_of(const mjtNum* pos, const mjtNum* quat) {
  Frame f = Frame::Identity();
  f.linear() =
      Eigen::Quaterniond(quat[0], quat[1], quat[2], quat[3]).normalized().toRotationMatrix();
  f.translation() = Vec3(pos[0], pos[1], pos[2]);
  return f;
}

Frame shift(const Vec3& p) {
  Frame f = Frame::Identity();
  f.translation() = p;
  return f;
}

std::string name_at(const mjModel* m, int address, const std::string& fallback) {
  const std::string n = m->names + address;
  return n.empty() ? fallback : n;
}

}  // namespace

Tree read_mjcf(const std::string& path, bool springs) {
  const std::string text = read_text(path);
  char error[1000] = "";
  const std::unique_ptr<mjModel, void (*)(mjModel*)> model(
      mj_loadXML(path.c_str(), nullptr, error, sizeof error), mj_deleteModel);
  if (!model) {
    std::string message = error;
    int line = 0;
    std::smatch match;
    if (std::regex_search(message, match, std::regex("line ([0-9]+)"))) line = std::stoi(match[1]);
    while (!message.empty() && (message.back() == '\n' || message.back() == ' '))
      message.pop_back();
    for (char& c : message)
      if (c == '\n') c = ' ';
    throw ImportError(path, line, "MuJoCo cannot compile the model: " + message);
  }
  const mjModel* m = model.get();
  Tree tree;
  tree.source = path;
  tree.name = m->names;  // the model name comes first
  tree.gravity = Vec3(m->opt.gravity[0], m->opt.gravity[1], m->opt.gravity[2]);
  const mjtNum* qstart = m->nkey > 0 ? m->key_qpos : m->qpos0;
  if (m->nkey > 0)
    tree.notes.push_back("loops closed from keyframe " + name_at(m, m->name_keyadr[0], "0"));

  std::vector<int> link_of(static_cast<size_t>(m->nbody), -1);  // body -> its link
  std::vector<int> joint_of(static_cast<size_t>(m->njnt), -1);  // MuJoCo joint -> tree joint
  std::vector<Actuator> spring_drivers;  // --springs: a passive driver per sprung joint
  Link world;
  world.name = name_at(m, m->name_bodyadr[0], "world");
  tree.links.push_back(world);
  link_of[0] = 0;
  for (int b = 1; b < m->nbody; ++b) {
    const std::string bname = name_at(m, m->name_bodyadr[b], "body" + std::to_string(b));
    const int line = line_of(text, "body", bname);
    int parent = link_of[static_cast<size_t>(m->body_parentid[b])];
    Frame origin = pose_of(m->body_pos + 3 * b, m->body_quat + 4 * b);
    const int nj = m->body_jntnum[b];
    auto add_link = [&](const std::string& name) {
      Link l;
      l.name = name;
      l.line = line;
      tree.links.push_back(l);
      return static_cast<int>(tree.links.size()) - 1;
    };
    if (nj == 0) {
      TreeJoint j;
      j.name = bname + "_weld";
      j.type = JointType::fixed;
      j.parent = parent;
      j.origin = origin;
      j.child = add_link(bname);
      j.line = line;
      parent = j.child;
      tree.joints.push_back(j);
    }
    for (int k = 0; k < nj; ++k) {
      const int id = m->body_jntadr[b] + k;
      const std::string jname =
          name_at(m, m->name_jntadr[id], bname + "_joint" + std::to_string(k));
      TreeJoint j;
      j.name = jname;
      j.line = line_of(text, "joint", jname);
      j.parent = parent;
      const Vec3 p(m->jnt_pos[3 * id], m->jnt_pos[3 * id + 1], m->jnt_pos[3 * id + 2]);
      j.origin = origin * shift(p);
      j.after = shift(-p);
      j.axis =
          Vec3(m->jnt_axis[3 * id], m->jnt_axis[3 * id + 1], m->jnt_axis[3 * id + 2]).normalized();
      const int qa = m->jnt_qposadr[id];
      switch (m->jnt_type[id]) {
        case mjJNT_FREE:
          if (m->body_parentid[b] != 0)
            throw ImportError(path, j.line, "joint '" + jname + "': a free joint below the root");
          j.type = JointType::fixed;
          j.floating = true;
          j.origin = pose_of(qstart + qa, qstart + qa + 3);
          j.after = Frame::Identity();
          break;
        case mjJNT_BALL: {
          j.type = JointType::spherical;
          const Eigen::Quaterniond qs(qstart[qa], qstart[qa + 1], qstart[qa + 2], qstart[qa + 3]);
          const Vec3 e = qs.normalized().toRotationMatrix().eulerAngles(0, 1, 2);
          j.start = {e[0], e[1], e[2]};
          break;
        }
        case mjJNT_SLIDE:
        case mjJNT_HINGE:
          j.type = m->jnt_type[id] == mjJNT_HINGE ? JointType::revolute : JointType::prismatic;
          j.value = qstart[qa] - m->qpos0[qa];
          if (m->jnt_limited[id])
            j.lower = m->jnt_range[2 * id] - m->qpos0[qa],
            j.upper = m->jnt_range[2 * id + 1] - m->qpos0[qa];
          j.stiffness = m->jnt_stiffness[id];
          j.springref = m->qpos_spring[qa] - m->qpos0[qa];
          break;
        default:
          throw ImportError(path, j.line, "joint '" + jname + "': unknown joint type");
      }
      if (j.stiffness > 0 && springs) {
        // Free, at its spring's rest in the reference pose (the assembly holds it there); a
        // passive driver whose law is the spring and the joint's damping.
        j.value = j.springref;
        Actuator spring{jname, static_cast<int>(tree.joints.size()), j.line, ""};
        spring.passive = true;
        spring.stiffness = j.stiffness;
        spring.damping = m->dof_damping[m->jnt_dofadr[id]];
        spring_drivers.push_back(spring);
        tree.notes.push_back("joint " + jname + " (stiffness " + std::to_string(j.stiffness) +
                             ", damping " + std::to_string(spring.damping) +
                             ") a passive driver at its spring's rest (" +
                             std::to_string(j.springref) + " from qpos0), the spring its effort");
      } else if (j.stiffness > 0) {
        // Rigid at the spring's rest: the joint's motion there, frozen.
        j.origin = j.origin * joint_motion(j, Eigen::VectorXd::Constant(1, j.springref)) * j.after;
        j.after = Frame::Identity();
        j.type = JointType::fixed;
        tree.notes.push_back("joint " + jname + " (stiffness " + std::to_string(j.stiffness) +
                             ") kept rigid at its spring's rest (" + std::to_string(j.springref) +
                             " from qpos0; --springs frees it)");
      }
      j.child = add_link(k + 1 == nj ? bname : bname + "_" + jname);
      joint_of[static_cast<size_t>(id)] = static_cast<int>(tree.joints.size());
      tree.joints.push_back(j);
      parent = j.child;
      origin = Frame::Identity();
    }
    link_of[static_cast<size_t>(b)] = parent;
    Link& l = tree.links[static_cast<size_t>(parent)];
    l.mass = m->body_mass[b] > 1e-9 ? m->body_mass[b] : 0;  // boundmass of a massless body
    const Frame inertial = pose_of(m->body_ipos + 3 * b, m->body_iquat + 4 * b);
    l.com = inertial.translation();
    const Vec3 d(m->body_inertia[3 * b], m->body_inertia[3 * b + 1], m->body_inertia[3 * b + 2]);
    l.inertia = l.mass > 0
                    ? Mat3(inertial.linear() * d.asDiagonal() * inertial.linear().transpose())
                    : Mat3::Zero();
  }
  // Sites: named points of their bodies (foot contacts, sensors).
  for (int k = 0; k < m->nsite; ++k) {
    const std::string sname = name_at(m, m->name_siteadr[k], "");
    if (sname.empty()) continue;
    const int link = link_of[static_cast<size_t>(m->site_bodyid[k])];
    // The site's body frame is its link's frame (the last link of the body's joints).
    tree.links[static_cast<size_t>(link)].points.push_back(
        {sname, Vec3(m->site_pos[3 * k], m->site_pos[3 * k + 1], m->site_pos[3 * k + 2])});
  }
  for (int e = 0; e < m->neq; ++e) {
    if (!m->eq_active[e]) continue;
    const std::string ename = name_at(m, m->name_eqadr[e], "equality" + std::to_string(e));
    const int type = m->eq_type[e];
    const mjtNum* data = m->eq_data + mjNEQDATA * e;
    Closure c;
    c.name = ename;
    c.line = line_of(text, type == mjEQ_CONNECT ? "connect" : "weld", ename);
    c.link_a = link_of[static_cast<size_t>(m->eq_obj1id[e])];
    c.link_b = link_of[static_cast<size_t>(m->eq_obj2id[e])];
    c.a = tree.links[static_cast<size_t>(c.link_a)].name;
    c.b = tree.links[static_cast<size_t>(c.link_b)].name;
    if (type == mjEQ_CONNECT) {
      c.weld = false;
      c.in_a = shift(Vec3(data[0], data[1], data[2]));
      c.in_b = shift(Vec3(data[3], data[4], data[5]));
    } else if (type == mjEQ_WELD) {
      c.weld = true;
      c.in_a = pose_of(data + 3, data + 6);
      c.in_b = Frame::Identity();
    } else {
      throw ImportError(path, c.line,
                        "equality '" + ename + "': only connect and weld are imported");
    }
    tree.closures.push_back(c);
  }
  for (int u = 0; u < m->nu; ++u) {
    const std::string uname = name_at(m, m->name_actuatoradr[u], "actuator" + std::to_string(u));
    const int line = line_of(text, "motor", uname) ? line_of(text, "motor", uname)
                                                   : line_of(text, "position", uname);
    if (m->actuator_trntype[u] != mjTRN_JOINT) {
      tree.notes.push_back("actuator " + uname +
                           " acts through a tendon or a site: not a driver (only actuators on "
                           "joints are)");
      continue;
    }
    const int tj = joint_of[static_cast<size_t>(m->actuator_trnid[2 * u])];
    if (tj >= 0 && tree.joints[static_cast<size_t>(tj)].type == JointType::fixed) {
      tree.notes.push_back("actuator " + uname + ": its joint has a spring and is held rigid");
      continue;
    }
    if (tj < 0 || tree.joints[static_cast<size_t>(tj)].dofs() != 1)
      throw ImportError(path, line,
                        "actuator '" + uname + "': its joint is not a hinge or a slide");
    bool twice = false;
    for (const Actuator& a : tree.actuators) twice = twice || a.joint == tj;
    if (twice) {
      tree.notes.push_back("actuator " + uname + ": its joint has a driver already");
      continue;
    }
    tree.actuators.push_back({uname, tj, line, ""});
  }
  for (const Actuator& spring : spring_drivers) {
    bool driven = false;
    for (const Actuator& a : tree.actuators) driven = driven || a.joint == spring.joint;
    if (driven)
      tree.notes.push_back("joint " + spring.name +
                           ": an actuator drives it, so its spring is not in the model");
    else
      tree.actuators.push_back(spring);
  }
  // mechgen's additions (written by `mechgen export`): custom texts mechgen_value_<actuator> (a
  // driver's law), mechgen_spring_<joint> (a passive driver's name) and mechgen_step ("t0 t1
  // samples").
  for (int k = 0; k < m->ntext; ++k) {
    const std::string tname = name_at(m, m->name_textadr[k], "");
    const std::string data(m->text_data + m->text_adr[k]);
    if (tname.rfind("mechgen_value_", 0) == 0) {
      for (Actuator& a : tree.actuators)
        if (a.name == tname.substr(14)) a.value = data;
    } else if (tname.rfind("mechgen_spring_", 0) == 0) {  // a passive driver's name
      for (Actuator& a : tree.actuators)
        if (a.passive && tree.joints[static_cast<size_t>(a.joint)].name == tname.substr(15))
          a.name = data;
    } else if (tname == "mechgen_step") {
      std::istringstream in(data);
      SweepStep st;
      if (!(in >> st.t0 >> st.t1 >> st.samples))
        throw ImportError(path, line_of(text, "text", tname), "mechgen_step: \"t0 t1 samples\"");
      tree.step = st;
    }
  }
  return tree;
}

}  // namespace mechgen::import
