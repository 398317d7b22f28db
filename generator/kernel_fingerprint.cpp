#include "kernel_fingerprint.hpp"

#include "model/fingerprint.hpp"
#include "template_renderer.hpp"

namespace mechgen::gen {

std::uint64_t kernel_fingerprint(const Model& model, const std::string& templates_dir, bool bake) {
  Fnv1a64 hash;
  hash.add_field("mechgen kernel");
  hash.add_field(std::to_string(kEmissionVersion));
  hash.add_field(hex64(model.description_hash));
  hash.add_field(bake ? "baked" : "run-time parameters");
  for (const char* name : {"kernel.hpp.in", "kernel_entry.cpp.in"}) {
    hash.add_field(name);
    hash.add_field(read_template(templates_dir + "/" + name));
  }
  return hash.value();
}

}  // namespace mechgen::gen
