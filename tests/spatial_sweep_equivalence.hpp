// The generated kernel's sweep of a closed chain against the numeric sweep, every column (shared by
// the closed-chain and pose-driven kernel tests).
#pragma once

#include <gtest/gtest.h>

#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "spatial/spatial_kernel_sweep.hpp"
#include "spatial/spatial_sweep.hpp"
#include "sweep/compiled_kernel.hpp"
#include "sweep_column_compare.hpp"

namespace mechgen::spatial {

// Small changes: every parameter by a few per cent (the reference pose stays assembled).
inline std::vector<double> changed_parameters(const SpatialModel& model) {
  std::vector<double> p = model.common.default_parameters();
  for (size_t i = 0; i < p.size(); ++i) p[i] *= 1.0 + 0.03 * static_cast<double>(i % 3 + 1);
  return p;
}

// Random geometry: every parameter by up to +-3 %, drawn from `seed`.
inline std::vector<double> perturbed_parameters(const SpatialModel& model, unsigned seed) {
  std::vector<double> p = model.common.default_parameters();
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> factor(0.97, 1.03);
  for (double& value : p) value *= factor(random);
  return p;
}

// The whole step through the registry's kernel (warm-started from one call to the next) and the
// numeric sweep: every column (kinematics, driver efforts, joint reactions; where circuits are
// redundant the numeric solver's minimum-norm reactions) to 1e-9 of its scale
// (test::worst_column_difference), at each of the parameter sets given; `floor`: the smallest
// scale of a column (SI).
inline void sweep_equals_numeric_at(const std::string& name,
                                    const std::vector<std::vector<double>>& sets,
                                    double floor = 1e-6) {
  const SpatialModel model =
      read_spatial_model(std::string(MECHGEN_SOURCE_DIR "/models/") + name + ".yaml");
  const CompiledKernel* kernel = find_compiled_kernel(name);
  ASSERT_NE(kernel, nullptr);
  for (const std::vector<double>& parameters : sets) {
    const SpatialSweepOptions options = default_spatial_sweep(model, parameters);
    const SpatialSweepResult numeric = run_spatial_sweep(model, options);
    const SpatialSweepResult generated = run_spatial_kernel_sweep(model, options, *kernel);
    ASSERT_EQ(numeric.columns, generated.columns);
    ASSERT_EQ(numeric.rows.size(), generated.rows.size());
    std::string where;
    const double worst =
        test::worst_column_difference(numeric.columns, numeric.rows, generated.rows, where, floor);
    const size_t compared = numeric.columns.size();
    EXPECT_GT(compared, 80u);
    EXPECT_LT(worst, 1e-9) << where;
    std::cout << name << " sweep (" << numeric.rows.size() << " samples, " << compared
              << " columns), generated against numeric: worst " << worst << " (" << where << ")\n";
  }
}

// At the default parameters and changed_parameters (or the `sets` given instead), and `perturbed`
// more sets from perturbed_parameters.
inline void sweep_equals_numeric(const std::string& name, int perturbed = 0,
                                 std::vector<std::vector<double>> sets = {}) {
  const SpatialModel model =
      read_spatial_model(std::string(MECHGEN_SOURCE_DIR "/models/") + name + ".yaml");
  if (sets.empty()) sets = {model.common.default_parameters(), changed_parameters(model)};
  for (int k = 0; k < perturbed; ++k)
    sets.push_back(perturbed_parameters(model, static_cast<unsigned>(k + 1)));
  sweep_equals_numeric_at(name, sets);
}

}  // namespace mechgen::spatial
