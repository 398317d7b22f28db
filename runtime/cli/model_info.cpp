#include "cli/model_info.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace mechgen::cli {

std::string number_text(double value) {
  if (!std::isfinite(value)) return std::isnan(value) ? "nan" : value > 0 ? "inf" : "-inf";
  char text[40];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  return text;
}

std::string json_string(const std::string& text) {
  std::string out = "\"";
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\b':
        out += "\\b";
        break;
      case '\f':
        out += "\\f";
        break;
      default:
        if (c < 0x20) {
          char escaped[8];
          std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned>(c));
          out += escaped;
        } else {
          out += ch;  // UTF-8 passes through unchanged
        }
    }
  }
  return out + "\"";
}

std::pair<double, double> mass_properties(const Model& model, const Body& body,
                                          const GiNaC::exmap& subs) {
  if (body.ground || body.mass.source == MassProperties::Source::none) return {0.0, 0.0};
  return {model.evaluate(body.mass.mass, subs), model.evaluate(body.mass.inertia, subs)};
}

std::string model_info_json(const Model& model) {
  const GiNaC::exmap subs = model.substitutions(model.default_parameters());
  const auto name_of_body = [&](int b) {
    return json_string(model.bodies[static_cast<size_t>(b)].name);
  };
  std::string j = "{\"name\": " + json_string(model.name) + ",\n";
  j += " \"gravity\": [" + number_text(model.evaluate(model.gravity.x, subs)) + ", " +
       number_text(model.evaluate(model.gravity.y, subs)) + "],\n";
  j += " \"parameters\": {";
  for (size_t i = 0; i < model.parameters.size(); ++i)
    j += (i ? ", " : "") + json_string(model.parameters[i].name) + ": " +
         number_text(model.parameters[i].value);
  j += "},\n";
  if (!model.derived.empty()) {  // values at the defaults; not settable (set what they use)
    const std::vector<double> derived = model.derived_values(model.default_parameters());
    j += " \"derived_parameters\": {";
    for (size_t i = 0; i < model.derived.size(); ++i)
      j += (i ? ", " : "") + json_string(model.derived[i].name) + ": " + number_text(derived[i]);
    j += "},\n";
  }
  j += " \"bodies\": [";
  for (size_t i = 0; i < model.bodies.size(); ++i) {
    const Body& body = model.bodies[i];
    const auto [mass, inertia] = mass_properties(model, body, subs);
    j += std::string(i ? ",\n   " : "\n   ") + "{\"name\": " + json_string(body.name) +
         ", \"mass\": " + number_text(mass) + ", \"inertia\": " + number_text(inertia) +
         ", \"ground\": " + (body.ground ? "true" : "false") + "}";
  }
  j += "],\n \"points\": [";
  const auto points = model.named_points();
  for (size_t i = 0; i < points.size(); ++i) j += (i ? ", " : "") + json_string(points[i].first);
  j += "],\n \"joints\": [";
  for (size_t i = 0; i < model.joints.size(); ++i) {
    const Joint& joint = model.joints[i];
    j += std::string(i ? ",\n   " : "\n   ") + "{\"name\": " + json_string(joint.name) +
         ", \"type\": " + json_string(to_string(joint.type)) +
         ", \"first\": " + name_of_body(joint.first) +
         ", \"second\": " + name_of_body(joint.second) +
         ", \"point\": " + json_string(joint.point) + "}";
  }
  j += "],\n \"drivers\": [";
  for (size_t i = 0; i < model.drivers.size(); ++i) {
    const Driver& d = model.drivers[i];
    j += std::string(i ? ",\n   " : "\n   ") + "{\"name\": " + json_string(d.name) +
         ", \"joint\": " + json_string(model.joints[static_cast<size_t>(d.joint)].name) +
         ", \"kind\": " + json_string(to_string(d.kind)) + "}";
  }
  return j + "]}\n";
}

}  // namespace mechgen::cli
