// The mechanism description, as read from models/<name>.yaml. One model serves both the numeric
// reference solver and the symbolic generator, so every quantity keeps its GiNaC expression (in
// the model's parameters and time `t`) and the source location it was read from.
#pragma once

#include <ginac/ginac.h>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace mechgen {

struct SourceLoc {
  std::string file;
  int line = 0;  // 1-based; 0 when unknown
  int col = 0;   // 1-based
};

// Every problem with a description is reported as one line "FILE:LINE:COL: error: MESSAGE".
class ModelError : public std::runtime_error {
 public:
  ModelError(const SourceLoc& loc, const std::string& message);
  const SourceLoc& where() const { return loc_; }

 private:
  SourceLoc loc_;
};

struct Expr {
  GiNaC::ex ex;
  std::string text;  // as written in the model
  SourceLoc loc;
};

struct Vec2Expr {
  Expr x, y;
};

struct Parameter {
  std::string name;
  double value = 0;     // default, SI units (converted from the file's unit when read)
  std::string unit;     // the SI unit of value ("m" for a parameter written in mm); "" if none
  std::string written;  // as the file gives it when converted ("38 mm"), else empty
  std::string doc;
  GiNaC::symbol symbol;
  SourceLoc loc;
};

// A parameter whose value is an expression of other parameters (`hip_x: {value: -a}`): not a
// run-time field of its own; every expression that names it uses its definition, so it follows
// `--set` of the parameters it depends on in the numeric solver and the generated kernels alike.
struct DerivedParameter {
  std::string name;
  Expr value;  // in the base parameters' symbols (derived ones it uses are expanded)
  std::string unit, doc;
  std::vector<std::string> uses;  // the parameters its expression names (base or derived)
  SourceLoc loc;
};

// A named point carried by a body, in that body's frame.
struct BodyPoint {
  std::string name;
  Vec2Expr local;
};

// Mass properties, always resolved to mass, centre of mass (body frame) and inertia about it.
struct MassProperties {
  enum class Source { none, explicit_values, bar, bars, plate };
  Source source = Source::none;
  Expr mass, inertia;  // kg, kg m^2 about the centre of mass
  Vec2Expr com;        // body frame
  // For Source::bar: the bar's end points, width (in the plane), thickness and density.
  std::string bar_from, bar_to;
  Expr width, thickness, density;    // bars: the same for every bar; plate: thickness, density
  std::vector<std::string> outline;  // bars: end points, two by two; plate: the polygon's points
};

// A bar's cross-section, for the stresses of runtime/analysis/link_loads (not used by the solvers).
// Bending is in the mechanism's plane, about the axis normal to it.
struct Section {
  enum class Shape { rectangle, general };
  Shape shape = Shape::rectangle;
  Expr width, thickness;      // rectangle: width in the plane (the bending depth), thickness normal
  Expr area, inertia, fibre;  // general: A (m^2), I about the normal axis (m^4), extreme fibre (m)
  std::optional<Expr> yield_strength;  // Pa; overrides the model's material
  std::optional<Expr> youngs_modulus;  // Pa; overrides the model's material
  SourceLoc loc;
};

struct Body {
  std::string name;
  bool ground = false;
  std::vector<BodyPoint> points;
  MassProperties mass;
  std::optional<Section> section;  // given explicitly (else a bar mass's width x thickness serves)
  std::optional<Expr>
      assembly_angle;  // approximate body angle at t0 (ground frame), picks the branch
  SourceLoc loc;

  const BodyPoint* find_point(const std::string& point) const;
};

enum class JointType { revolute, prismatic, pin_in_slot };

// A straight line fixed in the first body of a prismatic or pin-in-slot joint (first body frame).
struct Line {
  Vec2Expr through;
  Vec2Expr direction;  // need not be unit length
};

struct Joint {
  std::string name;
  JointType type = JointType::revolute;
  int first = -1, second = -1;  // body indices; reactions are the force of first on second
  std::string point;            // carried by both bodies (revolute) or by the second (others)
  Line line;                    // prismatic, pin_in_slot
  Expr angle;                   // prismatic: fixed value of theta_second - theta_first
  SourceLoc loc;

  // Scalar constraint equations and reaction unknowns of this joint (planar).
  int constraint_count() const { return type == JointType::pin_in_slot ? 1 : 2; }
};

enum class DriverKind { angle, length };

// A prescribed joint coordinate: angle = theta_second - theta_first (revolute), length = position
// of the joint point along the line, measured from line.through (prismatic, pin_in_slot).
struct Driver {
  std::string name;
  int joint = -1;
  DriverKind kind = DriverKind::angle;
  Expr value;                   // of t and parameters
  GiNaC::ex value_d, value_dd;  // exact time derivatives of value
  // `effort:` (optional): the driver's effort under `mechgen simulate`, a law of t, of the
  // parameters and of the driver's own coordinate and rate (Model::driver_q, Model::driver_qd).
  std::optional<Expr> effort;
  // `passive: true`: no actuator holds this coordinate (a joint's spring, say); under `simulate`
  // its effort is always its `effort:` law (neither --motor nor --track take it over). Kinematic
  // commands hold it at its `value:` and report the effort it would need there.
  bool passive = false;
  SourceLoc loc;
};

enum class ForceType { spring_damper, force, torque };

struct ForceElement {
  std::string name;
  ForceType type = ForceType::force;
  int body_a = -1, body_b = -1;          // body_b only for spring_damper
  std::string point_a, point_b;          // point_a: application point (force), spring end on a
  Expr stiffness, damping, free_length;  // spring_damper: N/m, N s/m, m
  Vec2Expr force;                        // force: ground-frame components, of t and parameters
  Expr torque;                           // torque: N m, counter-clockwise, of t and parameters
  SourceLoc loc;
};

struct Step {
  Expr t0, t1;
  int samples = 101;
};

struct Model {
  std::string name;
  std::string file;
  std::string description;
  Vec2Expr gravity;
  std::vector<Parameter> parameters;      // base parameters: the run-time values, file order
  std::vector<DerivedParameter> derived;  // dependency order
  std::vector<Body> bodies;
  std::vector<Joint> joints;
  std::vector<Driver> drivers;
  std::vector<ForceElement> forces;
  Step step;
  std::optional<Expr> yield_strength;  // Pa, `material: {yield_strength: ...}`; loads analysis only
  std::optional<Expr> youngs_modulus;  // Pa, `material: {youngs_modulus: ...}`; buckling only
  double assembly_tolerance = 0.35;    // rad: how far a converged assembly may be from the hint
  GiNaC::symbol t{"t"};
  // In a driver's `effort:` law: the driver's own coordinate and rate (`q`, `qd`).
  GiNaC::symbol driver_q{"q"}, driver_qd{"qd"};
  int ground = -1;
  // The description's fingerprint (model/fingerprint.hpp): its parsed YAML document, comments
  // and layout aside. Generated kernels carry it (combined with the generator's) to never be run
  // for another description.
  std::uint64_t description_hash = 0;

  int body_index(const std::string& name) const;       // -1 when absent
  int parameter_index(const std::string& name) const;  // -1 when absent
  int moving_body_count() const { return static_cast<int>(bodies.size()) - 1; }
  // Distinct point names in order of first appearance, with the body that locates each.
  std::vector<std::pair<std::string, int>> named_points() const;
  int derived_index(const std::string& name) const;  // -1 when absent
  std::vector<double> default_parameters() const;
  // Each derived parameter's value (order of `derived`) at the given base parameter values.
  std::vector<double> derived_values(const std::vector<double>& values) const;
  // Substitution map parameter symbol -> value.
  GiNaC::exmap substitutions(const std::vector<double>& values) const;
  // Evaluates an expression of parameters (and t when given) to a double; throws ModelError.
  double evaluate(const Expr& e, const GiNaC::exmap& subs) const;
};

// Reads and validates a description; throws ModelError on the first problem.
Model read_model(const std::string& path);
Model read_model_text(const std::string& text, const std::string& file_label);

// Applies "NAME=VALUE" overrides to a parameter vector; throws ModelError naming the bad one, or
// when the values fail the checks the file's values get (model/value_checks.hpp).
void apply_overrides(const Model& model, const std::vector<std::string>& overrides,
                     std::vector<double>& values);

const char* to_string(JointType type);
const char* to_string(DriverKind kind);

}  // namespace mechgen
