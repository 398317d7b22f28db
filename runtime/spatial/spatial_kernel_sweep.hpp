// A spatial model over time with its generated kernel (issue 11): the same samples and CSV
// columns as the reference solver's sweep (spatial_sweep.hpp), each row from the kernel.
#pragma once

#include "model/spatial_model.hpp"
#include "spatial/spatial_sweep.hpp"
#include "sweep/compiled_kernel.hpp"

namespace mechgen::spatial {

// The instant of sample i of the sweep (t0 and t1 included).
double spatial_sample_time(const SpatialSweepOptions& options, int i);

// The kernel must be one of this description (ondemand::kernel_for). Throws ModelError for a
// kernel whose columns are not the model's and for a sample the kernel reports unreachable,
// singular or non-finite (naming the sample, its time and the failing group or stage).
SpatialSweepResult run_spatial_kernel_sweep(const SpatialModel& model,
                                            const SpatialSweepOptions& options,
                                            const CompiledKernel& kernel);

}  // namespace mechgen::spatial
