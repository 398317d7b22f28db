// growth/<model>/generated: the time per sample of any description's generated kernel, for the
// growth family (issue 25 item 5, scripts/growth_kernels.sh). The descriptions are the paths in
// MECHGEN_BENCH_MODELS (separated by ':'); without it nothing registers. Each kernel comes through
// the on-demand cache (ondemand::kernel_for: built on first use, loaded after), as a user's sweep
// gets it, and is timed through CompiledKernel's row entry (evaluate() and the CSV row) at its
// model's default step times in order, as a sweep calls it. Before timing, every sample of the step
// must evaluate ok. A description whose kernel cannot be had (over the compile budget, a compiler
// error) or refuses a sample is not timed: stderr says why, and the others still run.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/model.hpp"
#include "model/spatial_model.hpp"
#include "ondemand/kernel_resolver.hpp"
#include "spatial/spatial_sweep.hpp"
#include "sweep/compiled_kernel.hpp"
#include "sweep/sweep.hpp"

namespace mechgen::bench {
namespace {

struct Samples {
  const CompiledKernel* kernel = nullptr;
  std::vector<double> parameters, t, row;
};

Samples samples_of(const std::string& path) {
  Samples s;
  double t0 = 0, t1 = 0;
  int count = 0;
  if (is_spatial_description(path)) {
    const SpatialModel model = read_spatial_model(path);
    const spatial::SpatialSweepOptions step = spatial::default_spatial_sweep(model);
    s.kernel = &ondemand::kernel_for(model);
    s.parameters = step.parameters;
    t0 = step.t0, t1 = step.t1, count = step.samples;
  } else {
    const Model model = read_model(path);
    const SweepOptions step = default_sweep(model);
    s.kernel = &ondemand::kernel_for(model);
    s.parameters = model.default_parameters();
    t0 = step.t0, t1 = step.t1, count = step.samples;
  }
  for (int i = 0; i < count; ++i) s.t.push_back(count > 1 ? t0 + (t1 - t0) * i / (count - 1) : t0);
  s.row.resize(static_cast<size_t>(s.kernel->column_count));
  for (const double t : s.t) {
    int group = -1;
    if (s.kernel->evaluate_double(s.parameters.data(), t, s.row.data(), &group) != 0)
      throw std::runtime_error(path + ": the generated kernel refuses t = " + std::to_string(t));
  }
  return s;
}

[[maybe_unused]] const bool registered = [] {
  const char* list = std::getenv("MECHGEN_BENCH_MODELS");
  if (list == nullptr) return false;
  std::istringstream paths(list);
  for (std::string path; std::getline(paths, path, ':');) {
    if (path.empty()) continue;
    std::shared_ptr<Samples> s;
    try {
      s = std::make_shared<Samples>(samples_of(path));
    } catch (const std::exception& error) {
      std::cerr << "growth_bench: " << path << ": not timed: " << error.what() << "\n";
      continue;
    }
    const std::string name = std::string("growth/") + s->kernel->model + "/generated";
    benchmark::RegisterBenchmark(name.c_str(), [s](benchmark::State& state) {
      size_t i = 0;
      int group = -1;
      for (auto _ : state) {
        benchmark::DoNotOptimize(
            s->kernel->evaluate_double(s->parameters.data(), s->t[i], s->row.data(), &group));
        i = i + 1 == s->t.size() ? 0 : i + 1;
      }
    })->Unit(benchmark::kNanosecond);
  }
  return true;
}();

}  // namespace
}  // namespace mechgen::bench
