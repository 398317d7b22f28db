// A spatial model over time with the reference solver: DESIGN.md's spatial CSV columns (bodies'
// centre of mass, quaternion, velocities and accelerations; points; joint coordinates and
// reaction wrenches; drivers, a pose driver with one group per prescribed coordinate).
#pragma once

#include <string>
#include <vector>

#include "model/spatial_model.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {

struct SpatialSweepOptions {
  std::vector<double> parameters;  // empty: the defaults
  double t0 = 0, t1 = 0;
  int samples = 2;
  // Issue 22: append the mass matrix and bias in the driver groups' coordinates
  // (numeric::mass_bias_columns of spatial_driver_names) to every row.
  bool mass_matrix = false;
};

struct SpatialSweepResult {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::vector<std::string> warnings;  // for the user, one line each (no "warning: " prefix)
};

std::vector<std::string> spatial_column_names(const SpatialModel& model);

// The driver groups in column order (joint drivers, then each pose driver's prescribed
// coordinates), each one primary coordinate: its name (`<name>.q` is its column) and its index in
// graph().primary order.
struct SpatialDriverGroup {
  std::string name;
  int column = -1;    // coordinate column
  int primary = -1;   // index in graph().primary
  double offset = 0;  // added to the column's q (a pose coordinate's reference value)
};
std::vector<SpatialDriverGroup> spatial_driver_groups(const SpatialSolver& solver);

// One row of spatial_column_names at a solved state with its inverse dynamics.
std::vector<double> spatial_sweep_row(const SpatialSolver& solver,
                                      const std::vector<SpatialDriverGroup>& groups,
                                      const SpatialState& state, const SpatialLoads& loads);
SpatialSweepOptions default_spatial_sweep(const SpatialModel& model,
                                          const std::vector<double>& parameters = {});
// Throws ModelError (naming t) for a sample the solver cannot evaluate.
// A sweep of a model with table drivers stays within every table's time range (a table is not
// extrapolated): else a ModelError at the driver's table naming both ranges.
void check_table_times(const SpatialModel& model, const SpatialSweepOptions& options);
SpatialSweepResult run_spatial_sweep(const SpatialModel& model, const SpatialSweepOptions& options);

}  // namespace mechgen::spatial
