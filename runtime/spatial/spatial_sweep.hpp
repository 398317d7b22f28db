// A spatial model over time with the reference solver: DESIGN.md's spatial CSV columns (bodies'
// centre of mass, quaternion, velocities and accelerations; points; joint coordinates and
// reaction wrenches; drivers, a pose driver with one group per prescribed coordinate).
#pragma once

#include <string>
#include <vector>

#include "model/spatial_model.hpp"

namespace mechgen::spatial {

struct SpatialSweepOptions {
  std::vector<double> parameters;  // empty: the defaults
  double t0 = 0, t1 = 0;
  int samples = 2;
};

struct SpatialSweepResult {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::vector<std::string> warnings;  // for the user, one line each (no "warning: " prefix)
};

std::vector<std::string> spatial_column_names(const SpatialModel& model);
SpatialSweepOptions default_spatial_sweep(const SpatialModel& model,
                                          const std::vector<double>& parameters = {});
// Throws ModelError (naming t) for a sample the solver cannot evaluate.
SpatialSweepResult run_spatial_sweep(const SpatialModel& model, const SpatialSweepOptions& options);

}  // namespace mechgen::spatial
