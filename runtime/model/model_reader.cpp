// Reads models/<name>.yaml into a Model. Every problem is a ModelError carrying the YAML location
// of the offending node; see docs/model_format.md for the format.
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "model/description_syntax.hpp"
#include "model/fingerprint.hpp"
#include "model/link_mass.hpp"
#include "model/mechanism_graph.hpp"
#include "model/model.hpp"
#include "model/parameter_resolver.hpp"
#include "model/spatial_model.hpp"
#include "model/value_checks.hpp"

namespace mechgen {

namespace {

using GiNaC::ex;

bool is_identifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

class Reader : public DescriptionSyntax {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  Model read(const YAML::Node& root);
  SpatialModel read_spatial(const YAML::Node& root);

  SourceLoc loc(const YAML::Node& node) const override {
    const YAML::Mark mark = node.Mark();
    if (mark.is_null()) return {file_, 0, 0};
    return {file_, mark.line + 1, mark.column + 1};
  }
  void expect_keys(const YAML::Node& node, const std::string& what,
                   const std::set<std::string>& allowed) const override;
  YAML::Node required(const YAML::Node& parent, const std::string& key,
                      const std::string& what) const override;
  std::string scalar(const YAML::Node& node, const std::string& what) const override;
  std::string identifier(const YAML::Node& node, const std::string& what) const override;
  bool flag(const YAML::Node& node, const std::string& what) const override {
    try {
      return node.as<bool>();
    } catch (const YAML::Exception&) {
      fail(node, what + " must be true or false");
    }
  }
  Expr expression(const YAML::Node& node, const std::string& what,
                  bool time_allowed) const override;
  Expr effort_law(const YAML::Node& node, const std::string& what) const override;

 private:
  Expr parse_expression(const YAML::Node& node, const std::string& what, bool time_allowed,
                        const GiNaC::symtab& symbols) const;
  [[noreturn]] void fail(const YAML::Node& node, const std::string& message) const {
    throw ModelError(loc(node), message);
  }

  void expect_map(const YAML::Node& node, const std::string& what) const {
    if (!node.IsMap()) fail(node, what + " must be a mapping");
  }
  Vec2Expr vector2(const YAML::Node& node, const std::string& what, bool time_allowed) const;
  int body_ref(const YAML::Node& node, const std::string& what) const;

  void read_parameters(const YAML::Node& node);
  void read_body(const YAML::Node& node);
  void read_mass(const YAML::Node& node, Body& body);
  void read_link_mass(const YAML::Node& node, Body& body, const std::string& what);
  void read_section(const YAML::Node& node, Body& body);
  void read_joint(const YAML::Node& node);
  void read_driver(const YAML::Node& node);
  void read_force(const YAML::Node& node);
  void check_values();
  void read_header(const YAML::Node& root, std::set<std::string> keys);
  void read_step(const YAML::Node& root);

  std::string file_;
  Model model_;
  GiNaC::symtab symbols_;
  // Bodies, joints, drivers and forces share one namespace (column names): name -> what it names.
  std::map<std::string, std::string> names_;
  void claim_name(const YAML::Node& node, const std::string& name, const std::string& kind) {
    const auto [at, inserted] = names_.emplace(name, kind);
    if (!inserted)
      fail(node, "duplicate name '" + name + "' (already the name of a " + at->second + ")");
  }
};

void Reader::expect_keys(const YAML::Node& node, const std::string& what,
                         const std::set<std::string>& allowed) const {
  for (const auto& item : node) {
    if (!item.first.IsScalar()) fail(item.first, "a key in " + what + " must be a plain name");
    const std::string key = item.first.Scalar();
    if (!allowed.count(key)) {
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      fail(item.first, "unknown key '" + key + "' in " + what + " (expected one of: " + list + ")");
    }
  }
}

YAML::Node Reader::required(const YAML::Node& parent, const std::string& key,
                            const std::string& what) const {
  YAML::Node node = parent[key];
  if (!node || node.IsNull()) fail(parent, what + " needs '" + key + "'");
  return node;
}

std::string Reader::scalar(const YAML::Node& node, const std::string& what) const {
  if (!node.IsScalar()) fail(node, what + " must be a single value");
  return node.Scalar();
}

// Why a name cannot be a field of a generated kernel (empty when it can): every name becomes a
// member of a class template whose scalar parameter is `Real` (`T` is free: a point or a
// parameter is often called T) and whose nested types are the kernel's own, and C++ reserves its
// keywords and names with `__` or a leading `_X`.
std::string reserved_in_kernels(const std::string& s) {
  const auto words = [](const char* text) {
    std::set<std::string> out;
    std::istringstream in(text);
    for (std::string w; in >> w;) out.insert(w);
    return out;
  };
  static const std::set<std::string> kernel_names = words(
      "Real BatchInputs Bodies BodyJacobians BodyState Drivers DriverState Inputs JointForce "
      "JointForceMoment Joints Params PointJacobians PointState Points PositionConstants State "
      "Status Warm");
  static const std::set<std::string> keywords = words(
      "alignas alignof and and_eq asm auto bitand bitor bool break case catch char char8_t "
      "char16_t char32_t class compl concept const consteval constexpr constinit const_cast "
      "continue co_await co_return co_yield decltype default delete do double dynamic_cast else "
      "enum explicit export extern false float for friend goto if inline int long mutable "
      "namespace new noexcept not not_eq nullptr operator or or_eq private protected public "
      "register reinterpret_cast requires return short signed sizeof static static_assert "
      "static_cast struct switch template this thread_local throw true try typedef typeid "
      "typename union unsigned using virtual void volatile wchar_t while xor xor_eq");
  if (kernel_names.count(s)) return "the generated kernels use it (their scalar type or a struct)";
  if (keywords.count(s)) return "it is a C++ keyword (names become fields of generated kernels)";
  if (s.find("__") != std::string::npos ||
      (s.size() > 1 && s[0] == '_' && std::isupper(static_cast<unsigned char>(s[1]))))
    return "C++ reserves names with '__' or a leading '_' and capital letter";
  return "";
}

std::string Reader::identifier(const YAML::Node& node, const std::string& what) const {
  const std::string s = scalar(node, what);
  if (!is_identifier(s))
    fail(node, what + " '" + s + "' is not an identifier ([A-Za-z_][A-Za-z0-9_]*)");
  const std::string why = reserved_in_kernels(s);
  if (!why.empty())
    fail(node, what + " '" + s + "' is reserved: " + why + "; rename it" +
                   (s[0] == '_' ? std::string() : " (e.g. '" + s + "_')"));
  return s;
}

// Bounds on an expression's text, checked before GiNaC parses it: its parser recurses once per
// nesting level (10 000 parentheses overflow the stack), and so does every later walk of the
// expression tree. Models' expressions are under 120 characters and 5 levels deep.
constexpr size_t kMaxExpressionLength = 2000;
// A model's name is part of its cached kernel's file names (the longest,
// <name>-<fingerprint>-<build key>.so.sha256, adds 44 characters), which a file system limits to
// 255 bytes.
constexpr size_t kMaxModelNameLength = 128;
constexpr int kMaxExpressionDepth = 64;

Expr Reader::expression(const YAML::Node& node, const std::string& what, bool time_allowed) const {
  return parse_expression(node, what, time_allowed, symbols_);
}

Expr Reader::effort_law(const YAML::Node& node, const std::string& what) const {
  GiNaC::symtab symbols = symbols_;
  for (const auto& [name, symbol] :
       {std::pair{"q", model_.driver_q}, std::pair{"qd", model_.driver_qd}}) {
    if (symbols.count(name))
      fail(node, what + ": the parameter '" + name +
                     "' would hide the driver's own coordinate or rate in an effort law (q, qd): "
                     "rename the parameter");
    symbols[name] = symbol;
  }
  return parse_expression(node, what, true, symbols);
}

Expr Reader::parse_expression(const YAML::Node& node, const std::string& what, bool time_allowed,
                              const GiNaC::symtab& symbols) const {
  const std::string text = scalar(node, what);
  if (text.empty()) fail(node, what + " is empty");
  if (const std::string why = yaml_special_number(text); !why.empty())
    fail(node, what + " '" + text + "' " + why);
  if (text.size() > kMaxExpressionLength)
    fail(node, what + " is " + std::to_string(text.size()) + " characters long (at most " +
                   std::to_string(kMaxExpressionLength) + ")");
  int depth = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    depth += text[i] == '(' || text[i] == '[' || text[i] == '{';
    depth -= text[i] == ')' || text[i] == ']' || text[i] == '}';
    if (depth > kMaxExpressionDepth) {
      SourceLoc at = loc(node);
      if (node.Tag() != "!" && at.col > 0) at.col += static_cast<int>(i);  // a plain scalar
      throw ModelError(at, what + " nests parentheses more than " +
                               std::to_string(kMaxExpressionDepth) + " deep (at character " +
                               std::to_string(i + 1) + ")");
    }
  }
  Expr result{ex(0), text, loc(node)};
  // GiNaC evaluates while it parses: besides syntax errors it reports poles (1/0, log(0)).
  auto first_line = [](const std::string& message) {
    std::string line = message.substr(0, message.find('\n'));  // drop GiNaC's source trailer
    const std::string position = "parse error at line 0, column 0: ";
    const auto at = line.find(position);
    return at == std::string::npos ? line : line.substr(at + position.size());
  };
  try {
    GiNaC::parser parse(symbols, true);  // strict: unknown names are errors
    result.ex = parse(text);
  } catch (const GiNaC::pole_error& error) {
    fail(node, what + " '" + text + "' cannot be evaluated (" + first_line(error.what()) + ")");
  } catch (const std::exception& error) {
    const std::string message = first_line(error.what());
    const auto open = message.find('"'), close = message.rfind('"');
    if (message.find("not found") != std::string::npos && open != std::string::npos &&
        close > open) {
      std::string known;
      for (const Parameter& p : model_.parameters) known += (known.empty() ? "" : ", ") + p.name;
      for (const DerivedParameter& p : model_.derived)
        known += (known.empty() ? "" : ", ") + p.name;
      fail(node, what + " '" + text + "': undefined name '" +
                     message.substr(open + 1, close - open - 1) + "' (" +
                     (known.empty() ? "the model has no parameters" : "parameters: " + known) +
                     ")");
    }
    fail(node, what + " '" + text + "': syntax error (" + message + ")");
  }
  if (!time_allowed && result.ex.has(model_.t))
    fail(node, what + " '" + text + "' may not depend on time t");
  return result;
}

Vec2Expr Reader::vector2(const YAML::Node& node, const std::string& what, bool time_allowed) const {
  if (!node.IsSequence() || node.size() != 2)
    fail(node, what + " must be a pair [x, y] (got " +
                   (!node.IsSequence() ? std::string("no list")
                    : node.size() == 1 ? std::string("1 value")
                                       : std::to_string(node.size()) + " values") +
                   ")");
  return {expression(node[0], what + " x", time_allowed),
          expression(node[1], what + " y", time_allowed)};
}

int Reader::body_ref(const YAML::Node& node, const std::string& what) const {
  const std::string name = scalar(node, what);
  const int index = model_.body_index(name);
  if (index < 0) {
    std::string known;
    for (const Body& b : model_.bodies) known += (known.empty() ? "" : ", ") + b.name;
    fail(node, what + ": unknown body '" + name + "' (bodies: " + known + ")");
  }
  return index;
}

void Reader::read_parameters(const YAML::Node& node) {
  if (!node) return;
  expect_map(node, "parameters");
  std::vector<ParameterEntry> entries;
  for (const auto& item : node) {
    ParameterEntry p;
    p.name = identifier(item.first, "parameter name");
    p.name_loc = loc(item.first);
    if (p.name == "t" || p.name == "pi")
      fail(item.first, "parameter name '" + p.name + "' is reserved");
    for (const ParameterEntry& other : entries)
      if (other.name == p.name) fail(item.first, "duplicate parameter '" + p.name + "'");
    YAML::Node value = item.second;
    if (value.IsMap()) {
      expect_keys(value, "parameter '" + p.name + "'", {"value", "unit", "doc"});
      if (value["unit"]) {
        p.has_unit = true;
        p.unit = scalar(value["unit"], "unit");
        p.unit_loc = loc(value["unit"]);
      }
      if (value["doc"]) p.doc = scalar(value["doc"], "doc");
      value = required(value, "value", "parameter '" + p.name + "'");
    }
    p.text = scalar(value, "parameter '" + p.name + "'");
    p.value_loc = loc(value);
    if (p.text.empty()) fail(value, "parameter '" + p.name + "' is empty");
    entries.push_back(p);
  }
  resolve_parameters(entries, model_, symbols_);
}

void Reader::read_mass(const YAML::Node& node, Body& body) {
  const std::string what = "mass of body '" + body.name + "'";
  expect_map(node, what);
  MassProperties& m = body.mass;
  if (node["bar"]) {
    expect_keys(node, what, {"bar", "width", "thickness", "density"});
    const YAML::Node bar = node["bar"];
    if (!bar.IsSequence() || bar.size() != 2)
      fail(bar, what + ": bar must name two of the body's points [from, to]");
    m.source = MassProperties::Source::bar;
    m.bar_from = scalar(bar[0], "bar end");
    m.bar_to = scalar(bar[1], "bar end");
    const BodyPoint* from = body.find_point(m.bar_from);
    const BodyPoint* to = body.find_point(m.bar_to);
    if (!from) fail(bar[0], what + ": body has no point '" + m.bar_from + "'");
    if (!to) fail(bar[1], what + ": body has no point '" + m.bar_to + "'");
    m.width = expression(required(node, "width", what), what + " width", false);
    m.thickness = expression(required(node, "thickness", what), what + " thickness", false);
    m.density = expression(required(node, "density", what), what + " density", false);
    const ex dx = to->local.x.ex - from->local.x.ex, dy = to->local.y.ex - from->local.y.ex;
    const ex length = GiNaC::sqrt(dx * dx + dy * dy);
    const ex mass = m.density.ex * m.width.ex * m.thickness.ex * length;
    const SourceLoc at = loc(bar);
    m.mass = {mass, "density*width*thickness*length", at};
    m.inertia = {mass * (dx * dx + dy * dy + m.width.ex * m.width.ex) / 12, "bar inertia", at};
    m.com = {{(from->local.x.ex + to->local.x.ex) / 2, "bar middle x", at},
             {(from->local.y.ex + to->local.y.ex) / 2, "bar middle y", at}};
  } else if (node["bars"] || node["plate"]) {
    read_link_mass(node, body, what);
  } else {
    expect_keys(node, what, {"mass", "com", "inertia"});
    m.source = MassProperties::Source::explicit_values;
    m.mass = expression(required(node, "mass", what), what, false);
    m.com = vector2(required(node, "com", what), what + " com", false);
    m.inertia = expression(required(node, "inertia", what), what + " inertia", false);
  }
}

// `bars: [[A, B], [B, C]]` with width, thickness, density, or `plate: [A, B, C]` with thickness,
// density: runtime/model/link_mass.hpp.
void Reader::read_link_mass(const YAML::Node& node, Body& body, const std::string& what) {
  MassProperties& m = body.mass;
  const bool plate = static_cast<bool>(node["plate"]);
  const YAML::Node list = plate ? node["plate"] : node["bars"];
  if (plate)
    expect_keys(node, what + " (plate)", {"plate", "thickness", "density"});
  else
    expect_keys(node, what + " (bars)", {"bars", "width", "thickness", "density"});
  auto point_of = [&](const YAML::Node& n) {
    const std::string name = scalar(n, what + " point");
    const BodyPoint* p = body.find_point(name);
    if (!p) fail(n, what + ": body has no point '" + name + "'");
    m.outline.push_back(name);
    return PointEx{p->local.x.ex, p->local.y.ex};
  };
  if (!list.IsSequence() || list.size() < (plate ? 3u : 1u))
    fail(list, what + (plate ? ": plate must list at least three of the body's points"
                             : ": bars must list bars [from, to] between the body's points"));
  m.thickness = expression(required(node, "thickness", what), what + " thickness", false);
  m.density = expression(required(node, "density", what), what + " density", false);
  const SourceLoc at = loc(list);
  PlanarMass mass;
  if (plate) {
    m.source = MassProperties::Source::plate;
    std::vector<PointEx> vertices;
    for (const auto& n : list) vertices.push_back(point_of(n));
    const double area = model_.evaluate({signed_area(vertices), "plate area", at},
                                        model_.substitutions(model_.default_parameters()));
    if (std::abs(area) < 1e-300) fail(list, what + ": the plate's points enclose no area");
    mass = plate_mass(vertices, m.thickness.ex, m.density.ex, area > 0 ? 1 : -1);
  } else {
    m.source = MassProperties::Source::bars;
    m.width = expression(required(node, "width", what), what + " width", false);
    std::vector<std::pair<PointEx, PointEx>> bars;
    for (const auto& bar : list) {
      if (!bar.IsSequence() || bar.size() != 2)
        fail(bar, what + ": each bar must name two of the body's points [from, to]");
      bars.emplace_back(point_of(bar[0]), point_of(bar[1]));
    }
    mass = bars_mass(bars, m.width.ex, m.thickness.ex, m.density.ex);
  }
  const std::string kind = plate ? "plate" : "bars";
  m.mass = {mass.mass, kind + " mass", at};
  m.inertia = {mass.inertia, kind + " inertia", at};
  m.com = {{mass.com_x, kind + " centre of mass x", at},
           {mass.com_y, kind + " centre of mass y", at}};
}

void Reader::read_section(const YAML::Node& node, Body& body) {
  const std::string what = "section of body '" + body.name + "'";
  expect_map(node, what);
  Section s;
  s.loc = loc(node);
  if (node["width"] || node["thickness"]) {
    expect_keys(node, what + " (rectangle)",
                {"width", "thickness", "yield_strength", "youngs_modulus"});
    s.shape = Section::Shape::rectangle;
    s.width = expression(required(node, "width", what), what + " width", false);
    s.thickness = expression(required(node, "thickness", what), what + " thickness", false);
  } else {
    expect_keys(node, what + " (general)",
                {"area", "inertia", "fibre", "yield_strength", "youngs_modulus"});
    s.shape = Section::Shape::general;
    s.area = expression(required(node, "area", what), what + " area", false);
    s.inertia = expression(required(node, "inertia", what), what + " inertia", false);
    s.fibre = expression(required(node, "fibre", what), what + " fibre", false);
  }
  if (node["yield_strength"])
    s.yield_strength = expression(node["yield_strength"], what + " yield_strength", false);
  if (node["youngs_modulus"])
    s.youngs_modulus = expression(node["youngs_modulus"], what + " youngs_modulus", false);
  body.section = s;
}

void Reader::read_body(const YAML::Node& node) {
  expect_map(node, "a body");
  expect_keys(node, "body", {"name", "ground", "points", "mass", "section", "assembly"});
  Body body;
  body.name = identifier(required(node, "name", "a body"), "body name");
  body.loc = loc(node["name"]);
  if (model_.body_index(body.name) >= 0) fail(node["name"], "duplicate body '" + body.name + "'");
  if (node["ground"]) body.ground = flag(node["ground"], "ground");
  const YAML::Node points = required(node, "points", "body '" + body.name + "'");
  expect_map(points, "points of body '" + body.name + "'");
  for (const auto& item : points) {
    BodyPoint p;
    p.name = identifier(item.first, "point name");
    if (body.find_point(p.name))
      fail(item.first, "body '" + body.name + "': duplicate point '" + p.name + "'");
    p.local = vector2(item.second, "point '" + p.name + "'", false);
    body.points.push_back(p);
  }
  if (node["mass"]) {
    read_mass(node["mass"], body);
  } else if (!body.ground) {
    fail(node["name"], "body '" + body.name + "' has no mass (give mass, com, inertia or a bar)");
  }
  if (node["section"]) {
    if (body.ground) fail(node["section"], "the ground body takes no section (it is not loaded)");
    read_section(node["section"], body);
  }
  if (node["assembly"]) {
    if (body.ground) fail(node["assembly"], "the ground body takes no assembly hint");
    body.assembly_angle = expression(node["assembly"], "assembly angle", false);
  }
  model_.bodies.push_back(body);
}

void Reader::read_joint(const YAML::Node& node) {
  expect_map(node, "a joint");
  expect_keys(node, "joint", {"name", "type", "first", "second", "point", "line", "angle"});
  Joint j;
  j.name = identifier(required(node, "name", "a joint"), "joint name");
  j.loc = loc(node["name"]);
  claim_name(node["name"], j.name, "joint");
  const YAML::Node type = required(node, "type", "joint '" + j.name + "'");
  const std::string type_name = scalar(type, "joint type");
  if (type_name == "revolute") {
    j.type = JointType::revolute;
  } else if (type_name == "prismatic") {
    j.type = JointType::prismatic;
  } else if (type_name == "pin_in_slot") {
    j.type = JointType::pin_in_slot;
  } else {
    fail(type, "unknown joint type '" + type_name + "' (revolute, prismatic or pin_in_slot)");
  }
  const std::string what = "joint '" + j.name + "'";
  j.first = body_ref(required(node, "first", what), what + " first body");
  j.second = body_ref(required(node, "second", what), what + " second body");
  if (j.first == j.second) fail(node["second"], what + " joins a body to itself");
  const YAML::Node point = required(node, "point", what);
  j.point = scalar(point, "joint point");
  const Body& second = model_.bodies[static_cast<size_t>(j.second)];
  const Body& first = model_.bodies[static_cast<size_t>(j.first)];
  if (!second.find_point(j.point))
    fail(point, what + ": body '" + second.name + "' has no point '" + j.point + "'");
  if (j.type == JointType::revolute) {
    if (!first.find_point(j.point))
      fail(point, what + ": body '" + first.name + "' has no point '" + j.point + "'");
    if (node["line"]) fail(node["line"], what + ": a revolute joint takes no line");
    if (node["angle"]) fail(node["angle"], what + ": a revolute joint takes no angle");
  } else {
    const YAML::Node line = required(node, "line", what);
    expect_map(line, "line");
    expect_keys(line, "line", {"through", "direction"});
    j.line.through = vector2(required(line, "through", "line"), "line through", false);
    j.line.direction = vector2(required(line, "direction", "line"), "line direction", false);
    if (j.type == JointType::prismatic) {
      j.angle = node["angle"] ? expression(node["angle"], "prismatic angle", false)
                              : Expr{ex(0), "0", loc(node)};
    } else if (node["angle"]) {
      fail(node["angle"], what + ": a pin_in_slot joint takes no angle");
    }
  }
  model_.joints.push_back(j);
}

void Reader::read_driver(const YAML::Node& node) {
  expect_map(node, "a driver");
  expect_keys(node, "driver", {"name", "joint", "kind", "value", "effort", "passive"});
  Driver d;
  d.name = identifier(required(node, "name", "a driver"), "driver name");
  d.loc = loc(node["name"]);
  claim_name(node["name"], d.name, "driver");
  const YAML::Node joint = required(node, "joint", "driver '" + d.name + "'");
  const std::string joint_name = scalar(joint, "driver joint");
  for (size_t i = 0; i < model_.joints.size(); ++i)
    if (model_.joints[i].name == joint_name) d.joint = static_cast<int>(i);
  if (d.joint < 0) fail(joint, "driver '" + d.name + "': unknown joint '" + joint_name + "'");
  for (const Driver& other : model_.drivers)
    if (other.joint == d.joint)
      fail(joint, "joint '" + joint_name + "' is already driven by '" + other.name + "'");
  const YAML::Node kind = required(node, "kind", "driver '" + d.name + "'");
  const std::string kind_name = scalar(kind, "driver kind");
  const JointType type = model_.joints[static_cast<size_t>(d.joint)].type;
  if (kind_name == "angle") {
    d.kind = DriverKind::angle;
    if (type != JointType::revolute)
      fail(kind, "driver '" + d.name + "': an angle driver needs a revolute joint, '" + joint_name +
                     "' is " + to_string(type));
  } else if (kind_name == "length") {
    d.kind = DriverKind::length;
    if (type == JointType::revolute)
      fail(kind, "driver '" + d.name +
                     "': a length driver needs a prismatic or pin_in_slot joint, '" + joint_name +
                     "' is revolute");
  } else {
    fail(kind, "unknown driver kind '" + kind_name + "' (angle or length)");
  }
  const YAML::Node value = required(node, "value", "driver '" + d.name + "'");
  if (value.IsMap() && value["table"])
    fail(value, "driver '" + d.name +
                    "': a table driver is for spatial models only (planar ones take a law of t)");
  d.value = expression(value, "driver value", true);
  d.value_d = d.value.ex.diff(model_.t);
  d.value_dd = d.value_d.diff(model_.t);
  if (node["effort"]) d.effort = effort_law(node["effort"], "driver '" + d.name + "' effort");
  d.passive = passive_driver(node, *this, "driver '" + d.name + "'");
  model_.drivers.push_back(d);
}

void Reader::read_force(const YAML::Node& node) {
  expect_map(node, "a force element");
  ForceElement f;
  f.name = identifier(required(node, "name", "a force element"), "force name");
  f.loc = loc(node["name"]);
  claim_name(node["name"], f.name, "force");
  const std::string what = "force '" + f.name + "'";
  const YAML::Node type = required(node, "type", what);
  const std::string type_name = scalar(type, "force type");
  auto point_ref = [&](const YAML::Node& n, int body) {
    const std::string p = scalar(n, "point");
    if (!model_.bodies[static_cast<size_t>(body)].find_point(p))
      fail(n,
           "body '" + model_.bodies[static_cast<size_t>(body)].name + "' has no point '" + p + "'");
    return p;
  };
  if (type_name == "spring_damper") {
    expect_keys(node, what,
                {"name", "type", "first", "first_point", "second", "second_point", "stiffness",
                 "damping", "free_length"});
    f.type = ForceType::spring_damper;
    f.body_a = body_ref(required(node, "first", what), what);
    f.body_b = body_ref(required(node, "second", what), what);
    if (f.body_a == f.body_b) fail(node["second"], what + " joins a body to itself");
    f.point_a = point_ref(required(node, "first_point", what), f.body_a);
    f.point_b = point_ref(required(node, "second_point", what), f.body_b);
    f.stiffness = expression(required(node, "stiffness", what), what + " stiffness", false);
    f.damping = node["damping"] ? expression(node["damping"], what + " damping", false)
                                : Expr{ex(0), "0", loc(node)};
    f.free_length = expression(required(node, "free_length", what), what + " free length", false);
  } else if (type_name == "force") {
    expect_keys(node, what, {"name", "type", "body", "point", "value"});
    f.type = ForceType::force;
    f.body_a = body_ref(required(node, "body", what), what);
    f.point_a = point_ref(required(node, "point", what), f.body_a);
    f.force = vector2(required(node, "value", what), what, true);
  } else if (type_name == "torque") {
    expect_keys(node, what, {"name", "type", "body", "value"});
    f.type = ForceType::torque;
    f.body_a = body_ref(required(node, "body", what), what);
    f.torque = expression(required(node, "value", what), what, true);
  } else {
    fail(type, "unknown force type '" + type_name + "' (spring_damper, force or torque)");
  }
  model_.forces.push_back(f);
}

// Numbers that must make physical sense at the default parameters (model/value_checks.hpp).
void Reader::check_values() {
  mechgen::check_values(model_, model_.default_parameters());
}

void Reader::read_header(const YAML::Node& root, std::set<std::string> keys) {
  if (!root.IsDefined() || root.IsNull())
    fail(root, "the model description is empty (expected a YAML mapping)");
  if (!root.IsMap()) fail(root, "a model description must be a YAML mapping");
  keys.insert({"name", "description", "dimension", "parameters", "step", "assembly_tolerance"});
  expect_keys(root, "model", keys);
  model_.file = file_;
  model_.description_hash = description_fingerprint(root);
  model_.name = identifier(required(root, "name", "the model"), "model name");
  if (model_.name.size() > kMaxModelNameLength)
    fail(root["name"], "model name is " + std::to_string(model_.name.size()) +
                           " characters long (at most " + std::to_string(kMaxModelNameLength) +
                           ": it names the kernel's namespace and its files in the kernel cache)");
  if (root["description"]) model_.description = scalar(root["description"], "description");
  symbols_["t"] = model_.t;
  symbols_["pi"] = GiNaC::Pi;
  read_parameters(root["parameters"]);
}

Model Reader::read(const YAML::Node& root) {
  read_header(root, {"gravity", "bodies", "joints", "drivers", "forces", "material"});
  if (root["dimension"] && scalar(root["dimension"], "dimension") != "planar")
    fail(root["dimension"], scalar(root["dimension"], "dimension") == "spatial"
                                ? "a spatial model: this command takes planar models only "
                                  "(spatial ones: check, info, sweep --solver numeric, draw)"
                                : "dimension must be planar or spatial");
  model_.gravity = root["gravity"]
                       ? vector2(root["gravity"], "gravity", false)
                       : Vec2Expr{{ex(0), "0", loc(root)}, {ex(-9.81), "-9.81", loc(root)}};

  const YAML::Node bodies = required(root, "bodies", "the model");
  if (!bodies.IsSequence()) fail(bodies, "bodies must be a list");
  for (const auto& b : bodies) read_body(b);
  for (const Body& b : model_.bodies) names_.emplace(b.name, "body");
  for (size_t i = 0; i < model_.bodies.size(); ++i) {
    if (!model_.bodies[i].ground) continue;
    if (model_.ground >= 0)
      throw ModelError(model_.bodies[i].loc,
                       "more than one ground body ('" +
                           model_.bodies[static_cast<size_t>(model_.ground)].name + "' and '" +
                           model_.bodies[i].name + "')");
    model_.ground = static_cast<int>(i);
  }
  if (model_.ground < 0) fail(bodies, "no ground body (mark one body 'ground: true')");

  if (const YAML::Node joints = root["joints"]) {
    if (!joints.IsSequence()) fail(joints, "joints must be a list");
    for (const auto& j : joints) read_joint(j);
  }
  if (const YAML::Node drivers = root["drivers"]) {
    if (!drivers.IsSequence()) fail(drivers, "drivers must be a list");
    for (const auto& d : drivers) read_driver(d);
  }
  if (const YAML::Node forces = root["forces"]) {
    if (!forces.IsSequence()) fail(forces, "forces must be a list");
    for (const auto& f : forces) read_force(f);
  }
  if (const YAML::Node material = root["material"]) {
    expect_map(material, "material");
    expect_keys(material, "material", {"yield_strength", "youngs_modulus"});
    if (!material["yield_strength"] && !material["youngs_modulus"])
      fail(material, "material needs yield_strength or youngs_modulus (Pa)");
    if (material["yield_strength"])
      model_.yield_strength =
          expression(material["yield_strength"], "material yield_strength", false);
    if (material["youngs_modulus"])
      model_.youngs_modulus =
          expression(material["youngs_modulus"], "material youngs_modulus", false);
  }
  read_step(root);
  check_values();
  check_structure(model_);
  return model_;
}

void Reader::read_step(const YAML::Node& root) {
  const YAML::Node step = required(root, "step", "the model");
  expect_map(step, "step");
  expect_keys(step, "step", {"t0", "t1", "samples"});
  model_.step.t0 = expression(required(step, "t0", "step"), "step t0", false);
  model_.step.t1 = expression(required(step, "t1", "step"), "step t1", false);
  if (step["samples"]) {
    int samples = 0;
    try {
      samples = step["samples"].as<int>();
    } catch (const YAML::Exception&) {
      fail(step["samples"], "step samples must be an integer");
    }
    if (samples < 2) fail(step["samples"], "step samples must be at least 2");
    model_.step.samples = samples;
  }
  if (root["assembly_tolerance"]) {
    const Expr tol = expression(root["assembly_tolerance"], "assembly_tolerance", false);
    model_.assembly_tolerance =
        model_.evaluate(tol, model_.substitutions(model_.default_parameters()));
    if (!(model_.assembly_tolerance > 0))
      fail(root["assembly_tolerance"], "assembly_tolerance must be positive");
  }
}

SpatialModel Reader::read_spatial(const YAML::Node& root) {
  read_header(root, spatial_description_keys());
  if (root["assembly_tolerance"])
    fail(root["assembly_tolerance"],
         "assembly_tolerance is for planar models (spatial ones take per-joint `assembly:` hints)");
  // Without `step:` a model with table drivers takes the tables' span (spatial_reader.cpp).
  if (root["step"]) {
    read_step(root);
    const GiNaC::exmap subs = model_.substitutions(model_.default_parameters());
    if (!(model_.evaluate(model_.step.t1, subs) > model_.evaluate(model_.step.t0, subs)))
      throw ModelError(model_.step.t1.loc, "step: t1 must be greater than t0");
  }
  return read_spatial_elements(root, *this, model_);
}

YAML::Node load_yaml(const std::string& text, const std::string& file_label) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& error) {
    throw ModelError({file_label, error.mark.line + 1, error.mark.column + 1},
                     "invalid YAML: " + error.msg);
  }
}

}  // namespace

std::string reserved_name_reason(const std::string& name) {
  return reserved_in_kernels(name);
}

bool passive_driver(const YAML::Node& driver, const DescriptionSyntax& syntax,
                    const std::string& what) {
  const YAML::Node key = driver["passive"];
  if (!key) return false;
  const bool passive = syntax.flag(key, what + " passive");
  if (passive && !driver["effort"])
    throw ModelError(syntax.loc(key), what +
                                          ": a passive driver needs an `effort:` law (its "
                                          "spring or damper: nothing else drives it)");
  return passive;
}

SpatialModel read_spatial_model_text(const std::string& text, const std::string& file_label) {
  return Reader(file_label).read_spatial(load_yaml(text, file_label));
}

Model read_model_text(const std::string& text, const std::string& file_label) {
  return Reader(file_label).read(load_yaml(text, file_label));
}

Model read_model(const std::string& path) {
  return read_model_text(read_description_file(path), path);
}

std::string read_description_file(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) throw ModelError({path, 0, 0}, "no such model file");
  if (std::filesystem::is_directory(path, error))
    throw ModelError({path, 0, 0}, "is a directory, not a model file");
  std::ifstream in(path);
  if (!in) throw ModelError({path, 0, 0}, "cannot open model file");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace mechgen
