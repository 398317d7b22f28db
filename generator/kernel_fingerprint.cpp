#include "kernel_fingerprint.hpp"

#include <vector>

#include "model/fingerprint.hpp"
#include "template_renderer.hpp"

namespace mechgen::gen {

std::uint64_t kernel_fingerprint(const Model& model, const std::string& templates_dir, bool bake,
                                 KernelKind kind) {
  const bool spatial = kind == KernelKind::spatial;
  Fnv1a64 hash;
  hash.add_field(spatial ? "mechgen spatial kernel" : "mechgen kernel");
  hash.add_field(std::to_string(kEmissionVersion));
  hash.add_field(hex64(model.description_hash));
  hash.add_field(bake ? "baked" : "run-time parameters");
  const std::vector<const char*> planar{"kernel.hpp.in", "kernel_entry.cpp.in"};
  const std::vector<const char*> spatial_templates{"spatial_kernel.hpp.in",
                                                   "spatial_kernel_entry.cpp.in", "kernel.hpp.in"};
  std::vector<const char*> names = spatial ? spatial_templates : planar;
  names.push_back("forward_dynamics.hpp.in");
  names.push_back("forward_dynamics_entry.cpp.in");
  for (const char* name : names) {
    hash.add_field(name);
    hash.add_field(read_template(templates_dir + "/" + name));
  }
  return hash.value();
}

}  // namespace mechgen::gen
