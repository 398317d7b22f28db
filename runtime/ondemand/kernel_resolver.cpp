#include "ondemand/kernel_resolver.hpp"

#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

#include "kernel_fingerprint.hpp"
#include "ondemand/data_paths.hpp"
#include "ondemand/kernel_cache.hpp"

namespace mechgen::ondemand {

namespace {

std::uint64_t fingerprint_of(const Model& model, gen::KernelKind kind) {
  try {
    return gen::kernel_fingerprint(model, templates_dir(), false, kind);
  } catch (const std::runtime_error& error) {
    // A binary copied away from its source tree, not installed with `cmake --install`.
    throw std::runtime_error(std::string(error.what()) +
                             ": mechgen needs its templates to check a kernel against the "
                             "description (an installed mechgen finds them in share/mechgen)");
  }
}

const CompiledKernel* current_of(const Model& model, gen::KernelKind kind) {
  const CompiledKernel* kernel = find_compiled_kernel(model.name);
  return kernel && kernel->fingerprint == fingerprint_of(model, kind) ? kernel : nullptr;
}

const CompiledKernel& resolve(const Model& model, gen::KernelKind kind,
                              const std::string& support = "") {
  static std::mutex mutex;
  static std::map<std::pair<std::string, std::uint64_t>, const CompiledKernel*> resolved;
  const std::lock_guard<std::mutex> lock(mutex);
  const std::uint64_t fingerprint = fingerprint_of(model, kind);
  const CompiledKernel*& kernel = resolved[{model.name, fingerprint}];
  if (kernel) return *kernel;
  const CompiledKernel* compiled_in = find_compiled_kernel(model.name);
  if (compiled_in && compiled_in->fingerprint == fingerprint) return *(kernel = compiled_in);
  const std::string reason =
      compiled_in ? " (the compiled-in kernel is of another description)" : "";
  return *(kernel = &cached_kernel(model, fingerprint, reason, kind, support));
}

}  // namespace

std::uint64_t expected_fingerprint(const Model& model) {
  return fingerprint_of(model, gen::KernelKind::planar);
}

const CompiledKernel* current_compiled_kernel(const Model& model) {
  return current_of(model, gen::KernelKind::planar);
}

const CompiledKernel& kernel_for(const Model& model) {
  return resolve(model, gen::KernelKind::planar);
}

std::uint64_t expected_fingerprint(const SpatialModel& model) {
  return fingerprint_of(model.common, gen::KernelKind::spatial);
}

const CompiledKernel* current_compiled_kernel(const SpatialModel& model) {
  return current_of(model.common, gen::KernelKind::spatial);
}

const CompiledKernel& kernel_for(const SpatialModel& model) {
  return resolve(model.common, gen::KernelKind::spatial);
}

const CompiledKernel& kernel_for(const SpatialModel& welded, const std::string& support) {
  return resolve(welded.common, gen::KernelKind::spatial, support);
}

}  // namespace mechgen::ondemand
