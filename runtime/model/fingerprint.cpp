#include "model/fingerprint.hpp"

#include <yaml-cpp/yaml.h>

#include <cstdio>

namespace mechgen {

void Fnv1a64::add(std::string_view bytes) {
  for (const char c : bytes) {
    hash_ ^= static_cast<unsigned char>(c);
    hash_ *= 0x100000001b3ULL;
  }
}

void Fnv1a64::add_field(std::string_view field) {
  add(std::to_string(field.size()));
  add(":");
  add(field);
}

namespace {
// Scalars and tags are written with their length in front: no text can fake a structure.
void append_canonical(const YAML::Node& node, std::string& out) {
  const auto field = [&out](const std::string& text) {
    out += std::to_string(text.size()) + ":" + text;
  };
  switch (node.Type()) {
    case YAML::NodeType::Scalar:
      out += "s";
      field(node.Tag());
      field(node.Scalar());
      return;
    case YAML::NodeType::Sequence:
      out += "[";
      for (const YAML::Node& item : node) append_canonical(item, out), out += ",";
      out += "]";
      return;
    case YAML::NodeType::Map:
      out += "{";
      for (const auto& item : node) {
        append_canonical(item.first, out);
        out += "=";
        append_canonical(item.second, out);
        out += ",";
      }
      out += "}";
      return;
    case YAML::NodeType::Null:
      out += "~";
      return;
    case YAML::NodeType::Undefined:
      out += "?";
      return;
  }
}
}  // namespace

std::string canonical_yaml(const YAML::Node& node) {
  std::string out;
  append_canonical(node, out);
  return out;
}

std::uint64_t description_fingerprint(const YAML::Node& root) {
  Fnv1a64 hash;
  hash.add(canonical_yaml(root));
  return hash.value();
}

std::string hex64(std::uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

}  // namespace mechgen
