// Fingerprints: FNV-1a 64 hashes of what a generated kernel depends on. A description's fingerprint
// is that of its parsed YAML document in a canonical form (every key, value and tag in document
// order; comments, layout, quoting style and anchors are not part of it), so editing a comment
// keeps a kernel current while any edit the reader could see makes it stale. Hashing the parsed
// document rather than the Model keeps the check safe by construction: no field of the model can
// be forgotten. A key the kernels never read (a bar's section, the material) also changes it: the
// only cost is one unneeded regeneration.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace YAML {
class Node;
}

namespace mechgen {

// FNV-1a, 64 bits. add_field() prefixes the length, so a sequence of fields hashes unambiguously.
class Fnv1a64 {
 public:
  void add(std::string_view bytes);
  void add_field(std::string_view field);
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

// The canonical text of a parsed YAML document (see above): deterministic, one line.
std::string canonical_yaml(const YAML::Node& node);
// FNV-1a 64 of canonical_yaml(root).
std::uint64_t description_fingerprint(const YAML::Node& root);
// 16 lower-case hex digits.
std::string hex64(std::uint64_t value);

}  // namespace mechgen
