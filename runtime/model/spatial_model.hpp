// A spatial mechanism description (`dimension: spatial`, docs/model_format.md), as read from
// models/<name>.yaml. Joints are screws given at the reference pose (every joint coordinate zero)
// in the ground frame, as in seed 001 Table 1. Pose drivers are expanded by the reader into their
// 3P3R virtual chains (massless virtual bodies and virtual one-coordinate joints), so everything
// downstream (graph, Davies' network, solver, Newton-Euler) sees one uniform joint graph.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "model/cubic_spline.hpp"
#include "model/model.hpp"

namespace mechgen {

struct Vec3Expr {
  Expr x, y, z;
};

struct SpatialPoint {
  std::string name;
  Vec3Expr local;  // body frame
};

struct SpatialMass {
  enum class Source { none, explicit_values, bar, box };
  Source source = Source::none;
  Expr mass;                         // kg
  Vec3Expr com;                      // body frame
  std::array<GiNaC::ex, 9> inertia;  // about the centre of mass, body frame, row-major (kg m^2)
  // The shape the mass came from, for drawings (mechgen view): a bar's end points and radius, a
  // box's edge lengths (its centre is com).
  std::string bar_from, bar_to;
  Expr radius;
  Vec3Expr box_size;
  SourceLoc loc;
};

struct SpatialBody {
  std::string name;
  bool ground = false;
  bool is_virtual = false;  // a massless body of a pose driver's virtual chain
  Vec3Expr origin;          // body frame origin at the reference pose (ground frame)
  Vec3Expr rotation_axis;   // body frame orientation at the reference pose: axis and angle
  Expr rotation_angle;
  std::vector<SpatialPoint> points;
  SpatialMass mass;
  SourceLoc loc;

  const SpatialPoint* find_point(const std::string& point) const;
};

enum class SpatialJointType {
  revolute,
  prismatic,
  helical,
  cylindrical,
  universal,
  spherical,
  fixed
};

// One joint coordinate: an elementary screw of a joint at the reference pose (ground frame).
enum class ScrewColumnKind { rotation, translation, helical };
struct ScrewColumnExpr {
  ScrewColumnKind kind = ScrewColumnKind::rotation;
  Vec3Expr s;  // unit axis
};

struct SpatialJoint {
  std::string name;
  SpatialJointType type = SpatialJointType::revolute;
  int first = -1, second = -1;  // body indices; wrenches are the first body's on the second
  Vec3Expr s, s2;               // unit axis; s2: a universal joint's second axis
  Vec3Expr s0;                  // a point on the axis (ground frame, reference pose)
  std::string point;            // the named point s0 was given by, or empty
  Expr pitch;                   // helical: m per rad
  std::vector<ScrewColumnExpr> columns;  // the joint's coordinates in product-of-exponentials order
  std::vector<Expr> assembly;            // per coordinate: the Newton-Raphson start at t0
  std::optional<std::array<Expr, 2>> range;
  bool is_virtual = false;  // a pose driver's virtual joint
  int pose_driver = -1;     // index in SpatialModel::pose_drivers for a virtual joint
  SourceLoc loc;
};

// A driver on one coordinate of a joint.
struct SpatialDriver {
  std::string name;
  int joint = -1;
  int column = 0;  // which coordinate of the joint (cylindrical: 0 translation, 1 rotation)
  DriverKind kind = DriverKind::angle;
  // A law of t: value and its exact derivatives. For a table driver (`table` set), the table's
  // first value as a constant: the placeholder the generated kernel's own driver motion and
  // assembly take (the runtime passes the spline's motion through the kernel's driven entry).
  Expr value;
  GiNaC::ex value_d, value_dd;
  std::optional<DriverTable> table;  // `value: {table: FILE.csv, column: NAME}`
  std::optional<std::array<Expr, 2>> range;
  std::optional<Expr> effort;  // `mechgen simulate`: a law of t, q, qd (as Driver::effort)
  bool passive = false;        // as Driver::passive
  SourceLoc loc;
};

// A pose driver: a frame on `second` relative to `first` (origin at `at`, axes those of `first`'s
// frame at the reference pose) follows prescribed translations and rotations. It is the seed's
// 3P3R virtual chain: virtual prismatic joints along x, y, z, then virtual revolutes about the
// named axes; coordinates not prescribed stay free (secondary) virtual joints.
struct PoseCoordinate {
  std::string name;           // x, y, z (translations); rx, ry, rz (rotations)
  int joint = -1;             // its virtual joint
  std::optional<Expr> value;  // prescribed (absolute: position of `at` in first's frame, angle)
  GiNaC::ex value_d, value_dd;
  GiNaC::ex reference;  // value at the reference pose: the virtual joint's q is value - reference
};

struct PoseDriver {
  std::string name;
  int first = -1, second = -1;
  Vec3Expr at;  // ground frame, reference pose
  std::string at_point;
  std::vector<PoseCoordinate> coordinates;  // always 6: x, y, z, then three rotations
  SourceLoc loc;
};

// An applied load: a force at a named point of a body, or a couple on a body; ground-frame
// components, functions of the parameters and t.
struct SpatialLoad {
  std::string name;
  bool torque = false;
  int body = -1;
  std::string point;  // force: the point it acts at
  Vec3Expr value;     // N (force) or N m (torque)
  SourceLoc loc;
};

struct SpatialModel {
  Model common;  // name, file, description, parameters, step, t, and their evaluation
  Vec3Expr gravity;
  std::vector<SpatialBody> bodies;
  std::vector<SpatialJoint> joints;
  std::vector<SpatialDriver> drivers;
  std::vector<PoseDriver> pose_drivers;
  std::vector<SpatialLoad> loads;  // `forces:`
  int ground = -1;
  // `kernel: {jacobians: [...]}`: the bodies (twist Jacobian) and named points (velocity
  // Jacobian) whose Jacobians a generated kernel emits; absent: every moving one.
  std::optional<std::vector<std::string>> kernel_jacobians;
  // What the reader changed and why (`mechgen check` prints them): a link between two spherical
  // joints whose idle spin was held (model/idle_spin.hpp).
  std::vector<std::string> notes;

  int body_index(const std::string& name) const;
  // Whether a generated kernel emits the Jacobian of this body or named point.
  bool emits_jacobian(const std::string& name) const;
  int joint_index(const std::string& name) const;
  // Distinct point names in order of first appearance (real bodies only), with their body.
  std::vector<std::pair<std::string, int>> named_points() const;
  double evaluate(const Expr& e, const GiNaC::exmap& subs) const {
    return common.evaluate(e, subs);
  }
};

const char* to_string(SpatialJointType type);
// Coordinates of a joint type (fixed: 0, revolute: 1, universal: 2, spherical: 3, ...).
int coordinate_count(SpatialJointType type);

// True when the file is a YAML mapping with `dimension: spatial` (false on any problem: the
// planar reader then reports it).
bool is_spatial_description(const std::string& path);

// Reads and validates a spatial description; throws ModelError (FILE:LINE:COL) on the first
// problem.
SpatialModel read_spatial_model(const std::string& path);
SpatialModel read_spatial_model_text(const std::string& text, const std::string& file_label);

}  // namespace mechgen
