#include "model/columns.hpp"

namespace mechgen {

ColumnLayout column_layout(const Model& model) {
  ColumnLayout layout;
  int next = 1;  // column 0 is t
  for (size_t i = 0; i < model.drivers.size(); ++i, next += 4) layout.driver.push_back(next);
  for (const Body& body : model.bodies) {
    layout.body.push_back(body.ground ? -1 : next);
    if (!body.ground) next += 9;
  }
  for (size_t i = 0; i < model.named_points().size(); ++i, next += 2) layout.point.push_back(next);
  for (const Joint& joint : model.joints) {
    layout.joint.push_back(next);
    next += joint.type == JointType::prismatic ? 3 : 2;
  }
  for (size_t i = 0; i < model.named_points().size(); ++i, next += 4)
    layout.point_rates.push_back(next);
  layout.count = next;
  return layout;
}

std::vector<std::string> column_names(const Model& model) {
  std::vector<std::string> names{"t"};
  for (const Driver& d : model.drivers)
    for (const char* s : {".q", ".qd", ".qdd", ".effort"}) names.push_back(d.name + s);
  for (const Body& b : model.bodies) {
    if (b.ground) continue;
    for (const char* s : {".x", ".y", ".th", ".vx", ".vy", ".w", ".ax", ".ay", ".al"})
      names.push_back(b.name + s);
  }
  for (const auto& [point, body] : model.named_points()) {
    names.push_back(point + ".x");
    names.push_back(point + ".y");
  }
  for (const Joint& j : model.joints) {
    names.push_back(j.name + ".fx");
    names.push_back(j.name + ".fy");
    if (j.type == JointType::prismatic) names.push_back(j.name + ".m");
  }
  // Appended after the original columns, so a script reading them by position reads the same.
  for (const auto& [point, body] : model.named_points())
    for (const char* s : {".vx", ".vy", ".ax", ".ay"}) names.push_back(point + s);
  return names;
}

}  // namespace mechgen
