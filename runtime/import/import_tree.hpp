// What `mechgen import` builds from a URDF (with its Extended URDF closures) or an MJCF file, and
// turns into a spatial description: a kinematic tree as the source writes it (link frames, joint
// origins, axes, inertias), the loop closures that cut it, the actuated joints; then the loops
// closed by Newton-Raphson from the source's configuration (import_assembly.cpp), the closures
// made joints of our graph and idle spins removed (import_graph.cpp), the description written out
// (model_writer.cpp).
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

namespace mechgen::import {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Frame = Eigen::Isometry3d;

// A problem with a source file: printed as "FILE:LINE: error: MESSAGE".
class ImportError : public std::runtime_error {
 public:
  ImportError(const std::string& file, int line, const std::string& message)
      : std::runtime_error(file + ":" + std::to_string(line > 0 ? line : 1) +
                           ": error: " + message) {}
};

struct Link {
  std::string name;
  double mass = 0;
  Vec3 com = Vec3::Zero();                           // link frame
  Mat3 inertia = Mat3::Zero();                       // about the centre of mass, link frame
  std::vector<std::pair<std::string, Vec3>> points;  // named points (MJCF sites), link frame
  int line = 0;
};

enum class JointType { revolute, prismatic, fixed, spherical, universal };

struct TreeJoint {
  std::string name;
  JointType type = JointType::fixed;
  int parent = -1, child = -1;       // links
  Frame origin = Frame::Identity();  // the joint frame in the parent's frame
  Frame after = Frame::Identity();   // the child's frame in the joint frame (moving with it)
  Vec3 axis = Vec3::UnitZ();         // joint frame; universal: A = x, then B = y
  double value = 0;                  // the source's coordinate (URDF: 0; MJCF: keyframe - qpos0)
  std::vector<double> start;         // several coordinates (a ball): the source's, else zeros
  double lower = 0, upper = 0;       // limits (lower < upper when given)
  double stiffness = 0, springref = 0;
  bool floating = false;  // a free joint (held fixed; a pose driver with --floating)
  int line = 0;
  int dofs() const {
    return type == JointType::revolute || type == JointType::prismatic ? 1
           : type == JointType::spherical                              ? 3
           : type == JointType::universal                              ? 2
                                                                       : 0;
  }
};

struct Closure {
  std::string a, b;  // the source's frame names
  int link_a = -1, link_b = -1;
  Frame in_a = Frame::Identity(), in_b = Frame::Identity();  // the frames in their links
  bool weld = true;  // 6d / weld; false: 3d / connect (position only)
  std::string name;
  std::string file;  // where the closure is written
  int line = 0;
};

struct Actuator {
  std::string name;  // driver name
  int joint = -1;
  int line = 0;
  std::string value;  // its law of t when the source carries one (mechgen export), else empty
  // A joint's spring (MJCF stiffness under --springs): no actuator; its effort -stiffness *
  // (q - rest) - damping * q', its rest the spring's, where the assembly holds it.
  bool passive = false;
  double stiffness = 0, damping = 0;
};

struct SweepStep {  // the default sweep when the source carries one (mechgen export)
  double t0 = 0, t1 = 1;
  int samples = 101;
};

struct Tree {
  std::string source;       // the file read
  std::string name;         // the robot's name
  std::vector<Link> links;  // links[0] is the root (the ground)
  std::vector<TreeJoint> joints;
  std::vector<Closure> closures;
  std::vector<Actuator> actuators;
  std::vector<std::string> notes;  // conversions done, for the header comment
  Vec3 gravity{0, 0, -9.81};
  std::optional<SweepStep> step;
};

// A file's text; the line of `<tag name="NAME"` in it (0 when not found).
std::string read_text(const std::string& path);
int line_of(const std::string& text, const std::string& tag, const std::string& name);

// A closure's joint name from its two frames: their common prefix (`jB_A`, `jB_B`: jB), else
// both joined.
std::string closure_name(const std::string& a, const std::string& b);

// URDF through urdfdom; closures (Extended URDF YAML) optional. Throws ImportError.
Tree read_urdf(const std::string& urdf_path, const std::string& closures_path);
// MJCF through MuJoCo's compiler. A joint with stiffness is held rigid at its spring's rest, or,
// with `springs`, a passive driver (Actuator::passive). Throws ImportError.
Tree read_mjcf(const std::string& path, bool springs = false);

// --floating: the base floats, placed by a pose driver from a new ground `world` (URDF: the root
// link; MJCF: the body of the free joint), at its source pose. Before assemble().
void float_base(Tree& tree);

// Joint coordinates of the tree (per joint, its dofs in order) and the link frames they give.
struct TreePose {
  std::vector<Eigen::VectorXd> q;  // per joint
  std::vector<Frame> link;         // per link, in the root's frame
};
// A joint's motion (joint frame) at its coordinates.
Frame joint_motion(const TreeJoint& joint, const Eigen::VectorXd& q);
TreePose place(const Tree& tree, const std::vector<Eigen::VectorXd>& q);
// The closure residuals (3d: 3 rows, 6d: 6) at a pose, stacked in closure order.
Eigen::VectorXd closure_residual(const Tree& tree, const TreePose& pose);

struct AssemblyReport {
  double initial = 0, final = 0;  // largest closure residual (m, rad)
  int iterations = 0;
  bool restarts = false;  // trapped from the source's configuration: closed from other starts
  // Other assemblies at the same motor positions, found from `starts` deterministic starts; the
  // kept one's distance from the source's coordinates and the nearest other's (rad, m).
  int starts = 0, others = 0;
  double kept_distance = 0, other_distance = 0;
};
// Closes the loops by Newton-Raphson (minimum-norm steps) from the source's coordinates, the
// actuated joints held; throws ImportError naming the closure that stays open and its distance.
TreePose assemble(const Tree& tree, AssemblyReport& report);

// A joint neither actuated nor in a loop would be free (no driver fixes it): held rigid at its
// assembled value (a fixed joint), named in the notes.
void hold_free_joints(Tree& tree, TreePose& pose);

// A spatial description (everything at the assembled pose, ground frame), ready to be written.
struct Body {
  std::string name;
  bool ground = false;
  Frame frame = Frame::Identity();  // body frame at the reference pose, ground frame
  double mass = 0;
  Vec3 com = Vec3::Zero();                           // body frame
  Mat3 inertia = Mat3::Zero();                       // about the centre of mass, body frame
  std::vector<std::pair<std::string, Vec3>> points;  // body frame
  std::vector<std::string> merged;                   // source links merged into this body
  std::string link;         // the source link whose frame is the body frame
  bool spin_fixed = false;  // between two spherical joints: its idle spin fixed by a universal
  // Links welded to this body where their spin about a pin was idle: placed as the source's
  // tree places them only up to that spin.
  std::vector<std::string> idle_links;
};
struct Joint {
  std::string name;
  JointType type = JointType::revolute;
  int first = -1, second = -1;
  Vec3 s = Vec3::UnitZ(), s2 = Vec3::UnitX(), s0 = Vec3::Zero();  // ground frame
  double source_value = 0;  // the source's coordinate at the reference pose (1-dof joints)
  double lower = 0, upper = 0;
  std::string comment;
};
struct Driver {
  std::string name;
  int joint = -1;
  std::string value;     // empty: amplitude*sin(w*t)
  bool passive = false;  // as Actuator: a spring-damper at its rest (coordinate 0)
  double stiffness = 0, damping = 0;
};
struct PoseDriver {  // every coordinate prescribed, constant: the base at its source pose
  std::string name;
  int first = -1, second = -1;
  Vec3 at = Vec3::Zero();  // ground frame, reference pose
};
struct Description {
  std::string name, source;
  std::vector<Body> bodies;
  std::vector<Joint> joints;
  std::vector<Driver> drivers;
  std::vector<PoseDriver> pose_drivers;
  std::vector<std::string> notes;
  Vec3 gravity{0, 0, -9.81};
  std::optional<SweepStep> step;
};
// The tree at the assembled pose as a description: fixed joints and welds merge bodies, connects
// become spherical joints, revolutes meeting at a point spherical or universal, idle spins
// removed.
// `floating`: free joints become pose drivers (else the base is welded to the ground).
Description describe(const Tree& tree, const TreePose& pose, bool floating = false);
// The description as YAML text.
std::string write_model(const Description& d);
// The shortest text that reads back as the same double; round-off dust (|v| < dust) as 0.
std::string shortest(double v, double dust);
// A name as a C++ identifier (the kernel's fields): other characters become '_'.
std::string identifier(const std::string& name);

}  // namespace mechgen::import
