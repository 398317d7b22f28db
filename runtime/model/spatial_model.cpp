// Look-ups on a spatial description and the entry points of its reader (spatial_reader.cpp).
#include "model/spatial_model.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>

#include "model/description_syntax.hpp"

namespace mechgen {

const SpatialPoint* SpatialBody::find_point(const std::string& point) const {
  for (const SpatialPoint& p : points)
    if (p.name == point) return &p;
  return nullptr;
}

int SpatialModel::body_index(const std::string& name) const {
  for (size_t i = 0; i < bodies.size(); ++i)
    if (bodies[i].name == name) return static_cast<int>(i);
  return -1;
}

bool SpatialModel::emits_jacobian(const std::string& name) const {
  return !kernel_jacobians || std::find(kernel_jacobians->begin(), kernel_jacobians->end(), name) !=
                                  kernel_jacobians->end();
}

int SpatialModel::joint_index(const std::string& name) const {
  for (size_t i = 0; i < joints.size(); ++i)
    if (joints[i].name == name) return static_cast<int>(i);
  return -1;
}

std::vector<std::pair<std::string, int>> SpatialModel::named_points() const {
  std::vector<std::pair<std::string, int>> out;
  for (size_t b = 0; b < bodies.size(); ++b)
    for (const SpatialPoint& p : bodies[b].points) {
      bool seen = false;
      for (const auto& [name, body] : out) seen = seen || name == p.name;
      if (!seen) out.emplace_back(p.name, static_cast<int>(b));
    }
  return out;
}

const char* to_string(SpatialJointType type) {
  switch (type) {
    case SpatialJointType::revolute:
      return "revolute";
    case SpatialJointType::prismatic:
      return "prismatic";
    case SpatialJointType::helical:
      return "helical";
    case SpatialJointType::cylindrical:
      return "cylindrical";
    case SpatialJointType::universal:
      return "universal";
    case SpatialJointType::spherical:
      return "spherical";
    case SpatialJointType::fixed:
      return "fixed";
  }
  return "?";
}

int coordinate_count(SpatialJointType type) {
  switch (type) {
    case SpatialJointType::fixed:
      return 0;
    case SpatialJointType::cylindrical:
    case SpatialJointType::universal:
      return 2;
    case SpatialJointType::spherical:
      return 3;
    default:
      return 1;
  }
}

bool is_spatial_description(const std::string& path) {
  try {
    const YAML::Node root = YAML::LoadFile(path);
    return root.IsMap() && root["dimension"] && root["dimension"].IsScalar() &&
           root["dimension"].Scalar() == "spatial";
  } catch (const std::exception&) {
    return false;
  }
}

SpatialModel read_spatial_model(const std::string& path) {
  return read_spatial_model_text(read_description_file(path), path);
}

}  // namespace mechgen
