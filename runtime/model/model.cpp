#include "model/model.hpp"

#include <cmath>
#include <sstream>

#include "model/value_checks.hpp"

namespace mechgen {

namespace {
std::string format_location(const SourceLoc& loc, const std::string& message) {
  std::ostringstream out;
  out << (loc.file.empty() ? "<model>" : loc.file);
  if (loc.line > 0) out << ':' << loc.line << ':' << (loc.col > 0 ? loc.col : 1);
  out << ": error: " << message;
  return out.str();
}
}  // namespace

ModelError::ModelError(const SourceLoc& loc, const std::string& message)
    : std::runtime_error(format_location(loc, message)), loc_(loc) {}

const BodyPoint* Body::find_point(const std::string& point) const {
  for (const BodyPoint& p : points)
    if (p.name == point) return &p;
  return nullptr;
}

int Model::body_index(const std::string& body_name) const {
  for (size_t i = 0; i < bodies.size(); ++i)
    if (bodies[i].name == body_name) return static_cast<int>(i);
  return -1;
}

int Model::parameter_index(const std::string& parameter_name) const {
  for (size_t i = 0; i < parameters.size(); ++i)
    if (parameters[i].name == parameter_name) return static_cast<int>(i);
  return -1;
}

int Model::derived_index(const std::string& parameter_name) const {
  for (size_t i = 0; i < derived.size(); ++i)
    if (derived[i].name == parameter_name) return static_cast<int>(i);
  return -1;
}

std::vector<double> Model::derived_values(const std::vector<double>& values) const {
  const GiNaC::exmap subs = substitutions(values);
  std::vector<double> result;
  for (const DerivedParameter& d : derived) result.push_back(evaluate(d.value, subs));
  return result;
}

std::vector<std::pair<std::string, int>> Model::named_points() const {
  std::vector<std::pair<std::string, int>> result;
  for (size_t b = 0; b < bodies.size(); ++b) {
    for (const BodyPoint& p : bodies[b].points) {
      bool seen = false;
      for (const auto& entry : result) seen = seen || entry.first == p.name;
      if (!seen) result.emplace_back(p.name, static_cast<int>(b));
    }
  }
  return result;
}

std::vector<double> Model::default_parameters() const {
  std::vector<double> values;
  for (const Parameter& p : parameters) values.push_back(p.value);
  return values;
}

GiNaC::exmap Model::substitutions(const std::vector<double>& values) const {
  GiNaC::exmap map;
  for (size_t i = 0; i < parameters.size() && i < values.size(); ++i)
    map[parameters[i].symbol] = values[i];
  return map;
}

double Model::evaluate(const Expr& e, const GiNaC::exmap& subs) const {
  GiNaC::ex value;
  try {
    // subs() options for a map of symbols: exact lookups. GiNaC's default matches every key as a
    // pattern at every node: `check` was quadratic in the parameter count (10 000: 60 s).
    value = e.ex.subs(subs,
                      GiNaC::subs_options::no_pattern | GiNaC::subs_options::pattern_is_not_product)
                .evalf();
  } catch (const std::exception& error) {
    throw ModelError(e.loc, "cannot evaluate '" + e.text + "': " + error.what());
  }
  if (!GiNaC::is_a<GiNaC::numeric>(value))
    throw ModelError(e.loc, "'" + e.text + "' does not evaluate to a number");
  const GiNaC::numeric& number = GiNaC::ex_to<GiNaC::numeric>(value);
  if (!number.is_real()) throw ModelError(e.loc, "'" + e.text + "' evaluates to a complex number");
  const double result = number.to_double();
  if (!std::isfinite(result)) throw ModelError(e.loc, "'" + e.text + "' is not finite");
  return result;
}

void apply_overrides(const Model& model, const std::vector<std::string>& overrides,
                     std::vector<double>& values) {
  const SourceLoc command_line{"<command line>", 0, 0};
  for (const std::string& item : overrides) {
    const auto eq = item.find('=');
    if (eq == std::string::npos)
      throw ModelError(command_line, "--set expects NAME=VALUE, got '" + item + "'");
    const std::string name = item.substr(0, eq);
    const int index = model.parameter_index(name);
    if (const int derived = model.derived_index(name); index < 0 && derived >= 0) {
      const DerivedParameter& d = model.derived[static_cast<size_t>(derived)];
      std::string uses;
      for (const std::string& u : d.uses) uses += (uses.empty() ? "" : ", ") + u;
      throw ModelError(command_line, "--set: parameter '" + name + "' is derived (" + name + " = " +
                                         d.value.text + "); set what it depends on: " + uses);
    }
    if (index < 0)
      throw ModelError(command_line,
                       "--set: model '" + model.name + "' has no parameter '" + name + "'");
    const std::string text = item.substr(eq + 1);
    size_t used = 0;
    double value = 0;
    try {
      value = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != text.size() || !std::isfinite(value))
      throw ModelError(command_line, "--set " + name + ": '" + text + "' is not a number");
    values[static_cast<size_t>(index)] = value;
  }
  if (!overrides.empty()) check_values(model, values);  // the checks the file's values get
}

const char* to_string(JointType type) {
  switch (type) {
    case JointType::revolute:
      return "revolute";
    case JointType::prismatic:
      return "prismatic";
    case JointType::pin_in_slot:
      return "pin_in_slot";
  }
  return "?";
}

const char* to_string(DriverKind kind) {
  return kind == DriverKind::angle ? "angle" : "length";
}

}  // namespace mechgen
