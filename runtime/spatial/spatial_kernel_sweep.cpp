// The spatial sweep through a generated kernel (spatial_kernel_sweep.hpp).
#include "spatial/spatial_kernel_sweep.hpp"

#include <cstdio>
#include <sstream>
#include <string>

namespace mechgen::spatial {

double spatial_sample_time(const SpatialSweepOptions& o, int i) {
  if (o.samples == 1) return o.t0;
  if (i == o.samples - 1) return o.t1;
  return o.t0 + (o.t1 - o.t0) * i / (o.samples - 1);
}

SpatialSweepResult run_spatial_kernel_sweep(const SpatialModel& model,
                                            const SpatialSweepOptions& options,
                                            const CompiledKernel& kernel) {
  SpatialSweepResult result;
  result.columns = spatial_column_names(model);
  const SourceLoc file{model.common.file, 0, 0};
  bool same = static_cast<int>(result.columns.size()) == kernel.column_count &&
              static_cast<int>(options.parameters.size()) == kernel.parameter_count;
  for (int c = 0; same && c < kernel.column_count; ++c)
    same = result.columns[static_cast<size_t>(c)] == kernel.column_names[c];
  if (!same)
    throw ModelError(file, "the generated kernel of '" + model.common.name +
                               "' does not match the description (rebuild to regenerate it)");
  bool newton_closure = false;
  for (int g = 0; g < kernel.group_count; ++g)
    newton_closure = newton_closure || std::string(kernel.group_names[g]) == "closure";
  for (int i = 0; i < options.samples; ++i) {
    const double t = spatial_sample_time(options, i);
    std::vector<double> row(static_cast<size_t>(kernel.column_count));
    int group = -1;
    const int status = kernel.evaluate_double(options.parameters.data(), t, row.data(), &group);
    if (status != 0) {
      // As the planar sweep words it (runtime/sweep/sweep.cpp): sample, time, status, group.
      char time[32];
      std::snprintf(time, sizeof time, "%.17g", t);
      std::ostringstream m;
      m << "generated kernel: sample " << i + 1 << " of " << options.samples << ", t = " << time
        << ": "
        << (status == 1   ? "unreachable"
            : status == 2 ? "singular"
                          : "non-finite result");
      if (group >= 0 && group < kernel.group_count) m << " in group " << kernel.group_names[group];
      m << (status == 1   ? " (the mechanism cannot assemble there with these parameters)"
            : status == 3 ? " (a singular geometry divides by zero, e.g. a length or offset set "
                            "to 0 or two axes made parallel; or the parameters or the motion are "
                            "too large for double precision)"
                          : " (the configuration is singular there)");
      // A Newton closure starts from the previous sample: samples far apart fail there too.
      if (status != 2 && i > 0 && newton_closure)
        m << "; or the samples are too far apart for the closure's Newton steps from the "
             "previous one: use more samples, or --solver numeric (it halves its steps)";
      throw ModelError(file, m.str());
    }
    result.rows.push_back(std::move(row));
  }
  return result;
}

}  // namespace mechgen::spatial
