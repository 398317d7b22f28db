// URDF (urdfdom) and the Extended URDF closure file of LAAS-CNRS into an import tree.
#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include "import/import_tree.hpp"

namespace mechgen::import {

namespace {

// urdfdom reports through console_bridge: keep its messages for our own error line.
class Collect : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN)
      messages += (messages.empty() ? "" : "; ") + text;
  }
  std::string messages;
};

Frame frame_of(const urdf::Pose& p) {
  Frame f = Frame::Identity();
  f.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  f.translation() = Vec3(p.position.x, p.position.y, p.position.z);
  return f;
}

int yaml_line(const YAML::Node& n) {
  return n.Mark().line + 1;
}

std::vector<std::string> string_list(const YAML::Node& n, const std::string& file,
                                     const std::string& key) {
  std::vector<std::string> out;
  if (!n) return out;
  if (!n.IsSequence()) throw ImportError(file, yaml_line(n), key + " must be a list");
  for (const auto& item : n) {
    if (!item.IsScalar()) throw ImportError(file, yaml_line(item), key + ": a name expected");
    out.push_back(item.as<std::string>());
  }
  return out;
}

// UJOINT_ZY and the like (the collection's re-typing): the two axes of the joint frame, in order.
std::optional<std::pair<std::optional<Vec3>, std::optional<Vec3>>> ujoint_axes(
    const std::string& type) {
  if (type.size() != 9 || type.rfind("UJOINT_", 0) != 0) return std::nullopt;
  auto axis = [](char c) -> std::optional<Vec3> {
    if (c < 'X' || c > 'Z') return std::nullopt;
    return Vec3(Vec3::Unit(c - 'X'));
  };
  const auto a = axis(type[7]), b = axis(type[8]);
  if (!a || !b || type[7] == type[8]) return std::nullopt;
  return std::make_pair(a, b);
}

// urdfdom's "link 'X' is not unique." and the like: the line of the second `<TAG name="X"`.
int duplicate_line(const std::string& text, const std::string& message) {
  for (const std::string tag : {"link", "joint"}) {
    const std::string key = tag + " '";
    const size_t at = message.find(key);
    if (at == std::string::npos || message.find("' is not unique", at) == std::string::npos)
      continue;
    const size_t end = message.find('\'', at + key.size());
    const std::string name = message.substr(at + key.size(), end - at - key.size());
    const int first = line_of(text, tag, name);
    if (first == 0) continue;
    size_t from = 0;  // past the first one's line
    for (int l = 1; l < first && from != std::string::npos; ++l) from = text.find('\n', from) + 1;
    from = text.find('\n', from);
    if (from == std::string::npos) continue;
    const int second = line_of(text.substr(from), tag, name);
    return second ? first + second - 1 : first;
  }
  return 0;
}

}  // namespace

std::string closure_name(const std::string& a, const std::string& b) {
  size_t k = 0;
  while (k < a.size() && k < b.size() && a[k] == b[k]) ++k;
  std::string prefix = a.substr(0, k);
  while (!prefix.empty() && prefix.back() == '_') prefix.pop_back();
  return prefix.size() >= 2 ? prefix : a + "_" + b;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ImportError(path, 0, "cannot read the file");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The line of `<tag name="NAME"` in the text (urdfdom keeps no locations), else 0.
int line_of(const std::string& text, const std::string& tag, const std::string& name) {
  for (const char quote : {'"', '\''}) {
    const std::string key = "name=" + std::string(1, quote) + name + std::string(1, quote);
    for (size_t at = text.find(key); at != std::string::npos; at = text.find(key, at + 1)) {
      const size_t open = text.rfind('<', at);
      if (open == std::string::npos || text.compare(open + 1, tag.size(), tag) != 0) continue;
      return 1 +
             static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
    }
  }
  return 0;
}

Tree read_urdf(const std::string& urdf_path, const std::string& closures_path) {
  const std::string text = read_text(urdf_path);
  Collect collect;
  console_bridge::useOutputHandler(&collect);
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(text);
  console_bridge::restorePreviousOutputHandler();
  if (!model)
    throw ImportError(
        urdf_path, duplicate_line(text, collect.messages),
        "not a valid URDF (urdfdom: " +
            (collect.messages.empty() ? std::string("no message") : collect.messages) + ")");
  Tree tree;
  tree.source = urdf_path;
  tree.name = model->getName();
  const urdf::LinkConstSharedPtr root = model->getRoot();
  if (!root) throw ImportError(urdf_path, 0, "the URDF has no root link");

  // Links in depth-first order from the root, joints as met.
  std::map<std::string, int> link_index;
  std::vector<urdf::LinkConstSharedPtr> order{root};
  for (size_t i = 0; i < order.size(); ++i)
    for (const auto& child : order[i]->child_links) order.push_back(child);
  for (const auto& l : order) {
    Link link;
    link.name = l->name;
    link.line = line_of(text, "link", l->name);
    if (l->inertial) {
      link.mass = l->inertial->mass;
      const Frame o = frame_of(l->inertial->origin);
      link.com = o.translation();
      Mat3 I;
      I << l->inertial->ixx, l->inertial->ixy, l->inertial->ixz, l->inertial->ixy, l->inertial->iyy,
          l->inertial->iyz, l->inertial->ixz, l->inertial->iyz, l->inertial->izz;
      link.inertia = o.linear() * I * o.linear().transpose();
      if (!(link.mass >= 0))
        throw ImportError(urdf_path, link.line, "link '" + l->name + "': negative mass");
      // A tensor no rigid body has (a negative principal moment, or I1 + I2 < I3) is refused
      // here, at the source's link, as the description's reader would refuse it.
      const Eigen::Vector3d moments =
          Eigen::SelfAdjointEigenSolver<Mat3>(I, Eigen::EigenvaluesOnly).eigenvalues();
      const double scale = I.cwiseAbs().maxCoeff();
      if (!(moments[0] >= -1e-12 * scale) ||
          !(moments[0] + moments[1] >= moments[2] * (1 - 1e-9))) {
        std::ostringstream text;
        text << "link '" << l->name << "': its inertia's principal moments " << moments[0] << ", "
             << moments[1] << ", " << moments[2]
             << " kg m^2 are no rigid body's (each >= 0, I1 + I2 >= I3)";
        throw ImportError(urdf_path, link.line, text.str());
      }
    }
    link_index[l->name] = static_cast<int>(tree.links.size());
    tree.links.push_back(link);
  }
  std::map<std::string, int> joint_index;
  for (size_t i = 1; i < order.size(); ++i) {
    const urdf::JointSharedPtr& uj = order[i]->parent_joint;
    TreeJoint j;
    j.name = uj->name;
    j.line = line_of(text, "joint", uj->name);
    j.parent = link_index.at(uj->parent_link_name);
    j.child = link_index.at(uj->child_link_name);
    j.origin = frame_of(uj->parent_to_joint_origin_transform);
    j.axis = Vec3(uj->axis.x, uj->axis.y, uj->axis.z);
    switch (uj->type) {
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS:
        j.type = JointType::revolute;
        break;
      case urdf::Joint::PRISMATIC:
        j.type = JointType::prismatic;
        break;
      case urdf::Joint::FIXED:
        j.type = JointType::fixed;
        break;
      case urdf::Joint::FLOATING:  // a floating base: as MJCF's free joint (held; --floating)
        if (j.parent != 0)
          throw ImportError(urdf_path, j.line,
                            "joint '" + j.name + "': a floating joint below the root's children");
        j.type = JointType::fixed;
        j.floating = true;
        break;
      default:
        throw ImportError(urdf_path, j.line, "joint '" + j.name + "': type planar is not imported");
    }
    if (j.dofs() > 0) {
      if (j.axis.norm() < 1e-12)
        throw ImportError(urdf_path, j.line, "joint '" + j.name + "': zero axis");
      j.axis.normalize();
    }
    if (uj->limits && uj->type != urdf::Joint::CONTINUOUS && uj->limits->lower < uj->limits->upper)
      j.lower = uj->limits->lower, j.upper = uj->limits->upper;
    joint_index[j.name] = static_cast<int>(tree.joints.size());
    tree.joints.push_back(j);
  }
  if (closures_path.empty()) {  // a tree alone: every joint is driven
    for (size_t i = 0; i < tree.joints.size(); ++i)
      if (tree.joints[i].dofs() == 1)
        tree.actuators.push_back(
            {tree.joints[i].name, static_cast<int>(i), tree.joints[i].line, ""});
    if (!tree.actuators.empty())
      tree.notes.push_back("no closures file: a tree, every revolute and prismatic joint driven");
    return tree;
  }

  try {  // a value of the wrong kind (a list for a name) is located in the closures file
    // The closure file: closed_loop, type, name_mot, joint_name / joint_type.
    YAML::Node y;
    try {
      y = YAML::LoadFile(closures_path);
    } catch (const YAML::BadFile&) {
      throw ImportError(closures_path, 0, "cannot read the file");
    } catch (const YAML::Exception& e) {
      throw ImportError(closures_path, e.mark.line + 1, e.msg);
    }
    if (!y.IsMap())
      throw ImportError(closures_path, 1, "expected a map (closed_loop, type, name_mot)");
    for (const auto& kv : y) {
      const std::string key = kv.first.as<std::string>();
      if (key != "closed_loop" && key != "type" && key != "name_mot" && key != "joint_name" &&
          key != "joint_type" && key != "gravity" && key != "driver_values" &&
          key != "driver_names" && key != "step")
        throw ImportError(closures_path, yaml_line(kv.first),
                          "unknown key '" + key +
                              "' (closed_loop, type, name_mot, joint_name, joint_type; mechgen's "
                              "gravity, driver_values, "
                              "driver_names, step)");
    }
    // gravity: [x, y, z] (mechgen's addition: URDF has none; default [0, 0, -9.81]).
    if (const YAML::Node g = y["gravity"]) {
      if (!g.IsSequence() || g.size() != 3)
        throw ImportError(closures_path, yaml_line(g), "gravity must be [x, y, z] (m/s^2)");
      try {
        tree.gravity = Vec3(g[0].as<double>(), g[1].as<double>(), g[2].as<double>());
      } catch (const YAML::Exception&) {
        throw ImportError(closures_path, yaml_line(g), "gravity must be three numbers (m/s^2)");
      }
    }
    // A frame: a link, or a joint (its child link's frame).
    auto frame = [&](const YAML::Node& n, int& link, Frame& in) {
      const std::string name = n.as<std::string>();
      if (const auto it = link_index.find(name); it != link_index.end()) {
        link = it->second;
        in = Frame::Identity();
        return name;
      }
      if (const auto it = joint_index.find(name); it != joint_index.end()) {
        link = tree.joints[static_cast<size_t>(it->second)].child;
        in = Frame::Identity();
        return name;
      }
      throw ImportError(
          closures_path, yaml_line(n),
          "closure frame '" + name + "' is neither a link nor a joint of " + urdf_path);
    };
    const YAML::Node loops = y["closed_loop"];
    const std::vector<std::string> types = string_list(y["type"], closures_path, "type");
    if (loops) {
      if (!loops.IsSequence())
        throw ImportError(closures_path, yaml_line(loops),
                          "closed_loop must be a list of [frameA, frameB]");
      if (types.size() != loops.size())
        throw ImportError(closures_path, yaml_line(y["type"] ? y["type"] : loops),
                          "type: " + std::to_string(types.size()) + " entries for " +
                              std::to_string(loops.size()) + " closed loops");
      for (size_t i = 0; i < loops.size(); ++i) {
        const YAML::Node pair = loops[i];
        if (!pair.IsSequence() || pair.size() != 2)
          throw ImportError(closures_path, yaml_line(pair),
                            "a closed loop is a pair [frameA, frameB]");
        Closure c;
        c.line = yaml_line(pair);
        c.file = closures_path;
        c.a = frame(pair[0], c.link_a, c.in_a);
        c.b = frame(pair[1], c.link_b, c.in_b);
        const std::string t = types[i];
        if (t == "6d" || t == "6D")
          c.weld = true;
        else if (t == "3d" || t == "3D")
          c.weld = false;
        else
          throw ImportError(closures_path, yaml_line(y["type"][i]),
                            "closure type '" + t + "': 6d or 3d");
        c.name = closure_name(c.a, c.b);
        tree.closures.push_back(c);
      }
    }
    for (const auto& n : y["name_mot"] ? y["name_mot"] : YAML::Node()) {
      const std::string name = n.as<std::string>();
      const auto it = joint_index.find(name);
      if (it == joint_index.end())
        throw ImportError(closures_path, yaml_line(n),
                          "name_mot: '" + name + "' is not a joint of " + urdf_path);
      if (tree.joints[static_cast<size_t>(it->second)].dofs() != 1)
        throw ImportError(closures_path, yaml_line(n),
                          "name_mot: '" + name + "' is not a revolute or prismatic joint");
      tree.actuators.push_back({name, it->second, yaml_line(n), ""});
    }
    // mechgen's additions (written by `mechgen export`): each driver's law and name, the step.
    const std::vector<std::string> values =
        string_list(y["driver_values"], closures_path, "driver_values");
    const std::vector<std::string> names =
        string_list(y["driver_names"], closures_path, "driver_names");
    for (size_t i = 0; i < tree.actuators.size(); ++i) {
      if (i < values.size()) tree.actuators[i].value = values[i];
      if (i < names.size()) tree.actuators[i].name = names[i];
    }
    if ((!values.empty() && values.size() != tree.actuators.size()) ||
        (!names.empty() && names.size() != tree.actuators.size()))
      throw ImportError(closures_path,
                        yaml_line(y["driver_values"] ? y["driver_values"] : y["driver_names"]),
                        "driver_values / driver_names: one per name_mot entry");
    if (const YAML::Node st = y["step"]) {
      if (!st.IsSequence() || st.size() != 3)
        throw ImportError(closures_path, yaml_line(st), "step must be [t0, t1, samples]");
      tree.step = SweepStep{st[0].as<double>(), st[1].as<double>(), st[2].as<int>()};
    }
    const std::vector<std::string> retype_names =
        string_list(y["joint_name"], closures_path, "joint_name");
    const std::vector<std::string> retype_types =
        string_list(y["joint_type"], closures_path, "joint_type");
    if (retype_names.size() != retype_types.size())
      throw ImportError(closures_path,
                        yaml_line(y["joint_type"] ? y["joint_type"] : y["joint_name"]),
                        "joint_type: one type per joint_name");
    for (size_t i = 0; i < retype_names.size(); ++i) {
      const int line = yaml_line(y["joint_name"][i]);
      const auto it = joint_index.find(retype_names[i]);
      if (it == joint_index.end())
        throw ImportError(closures_path, line,
                          "joint_name: '" + retype_names[i] + "' is not a joint");
      TreeJoint& j = tree.joints[static_cast<size_t>(it->second)];
      std::string t = retype_types[i];
      std::transform(t.begin(), t.end(), t.begin(), ::toupper);
      if (t == "SPHERICAL")
        j.type = JointType::spherical;
      else if (t == "UJOINT_AB" || t == "UJOINT")
        j.type = JointType::universal;
      else if (const auto axes = ujoint_axes(t)) {
        // Our universal turns about the joint frame's x then y: the frame is turned so that
        // they are the named axes (the child's frame is unchanged at 0).
        Mat3 r;
        r << *axes->first, *axes->second, axes->first->cross(*axes->second);
        j.origin = j.origin * Frame(r);
        j.after = Frame(r.transpose()) * j.after;
        j.type = JointType::universal;
      } else if (t == "FIXED")
        j.type = JointType::fixed;
      else if (t == "REVOLUTE" || t == "PRISMATIC")
        continue;
      else
        throw ImportError(closures_path, yaml_line(y["joint_type"][i]),
                          "joint_type '" + retype_types[i] +
                              "': SPHERICAL, UJOINT_AB, UJOINT_<two of X, Y, Z> or FIXED");
      tree.notes.push_back("joint " + j.name + " re-typed " + t + " (" + closures_path + ")");
    }
    for (const Actuator& a : tree.actuators)
      if (tree.joints[static_cast<size_t>(a.joint)].dofs() != 1)
        throw ImportError(closures_path, a.line,
                          "name_mot: '" + a.name + "' was re-typed: not a 1-dof joint");
  } catch (const YAML::Exception& e) {
    throw ImportError(closures_path, e.mark.line + 1, e.msg);
  }
  return tree;
}

}  // namespace mechgen::import
