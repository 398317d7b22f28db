// The generated kernel's sweep of a closed chain against the numeric sweep, every column (shared by
// the closed-chain and pose-driven kernel tests).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "spatial/spatial_kernel_sweep.hpp"
#include "spatial/spatial_sweep.hpp"
#include "sweep/compiled_kernel.hpp"

namespace mechgen::spatial {

inline bool is_reaction(const std::string& column) {
  for (const char* suffix : {".fx", ".fy", ".fz", ".mx", ".my", ".mz"}) {
    const std::string s(suffix);
    if (column.size() > s.size() && column.compare(column.size() - s.size(), s.size(), s) == 0)
      return true;
  }
  return false;
}

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
// redundant the numeric solver's minimum-norm reactions) to 1e-9 of its scale (the column's
// largest magnitude, at least 1 % of the largest of its kind, as the leg6 test; a reaction's at
// least 1e-3 of the largest reaction force or moment: a component that is zero (a revolute's
// moments in chebyshev_spatial, the numeric solver's at 1e-16) has no scale of its own).
// At each of the parameter sets given; `floor`: the smallest scale of a column (SI).
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
    // The kind: the suffix without digits (a spherical joint's q1, q2, q3 are one kind).
    auto kind = [](const std::string& c) {
      std::string k;
      for (const char ch : c.substr(c.rfind('.') + 1))
        if (ch < '0' || ch > '9') k += ch;
      return k;
    };
    std::map<std::string, double> kind_scale;
    double force_scale = 0, moment_scale = 0;
    for (const auto& row : numeric.rows)
      for (size_t c = 0; c < numeric.columns.size(); ++c) {
        const std::string& n = numeric.columns[c];
        kind_scale[kind(n)] = std::max(kind_scale[kind(n)], std::abs(row[c]));
        double& reaction_scale = n[n.size() - 2] == 'f' ? force_scale : moment_scale;
        if (is_reaction(n)) reaction_scale = std::max(reaction_scale, std::abs(row[c]));
      }
    double worst = 0;
    std::string where;
    int compared = 0;
    for (size_t c = 0; c < numeric.columns.size(); ++c) {
      ++compared;
      // At least 1 % of its kind's largest, and 1e-6 (SI: 1e-15 absolute): a kind that stays
      // near round-off level over the whole step (the standing bioloid's vertical velocities and
      // accelerations) has no scale of its own.
      double scale = std::max(floor, 0.01 * kind_scale[kind(numeric.columns[c])]);
      if (is_reaction(numeric.columns[c]))
        scale = std::max(scale, 1e-3 * std::max(force_scale, moment_scale));
      for (const auto& row : numeric.rows) scale = std::max(scale, std::abs(row[c]));
      for (size_t r = 0; r < numeric.rows.size(); ++r) {
        const double e = std::abs(generated.rows[r][c] - numeric.rows[r][c]) / scale;
        if (!(e <= worst)) worst = e, where = numeric.columns[c];
      }
    }
    EXPECT_GT(compared, 80);
    EXPECT_LT(worst, 1e-9) << where;
    std::cout << name << " sweep (" << numeric.rows.size() << " samples, " << compared
              << " columns), generated against numeric: worst " << worst << " (" << where << ")\n";
  }
}

// At the default parameters, changed_parameters and `perturbed` more sets from
// perturbed_parameters.
inline void sweep_equals_numeric(const std::string& name, int perturbed = 0) {
  const SpatialModel model =
      read_spatial_model(std::string(MECHGEN_SOURCE_DIR "/models/") + name + ".yaml");
  std::vector<std::vector<double>> sets{model.common.default_parameters(),
                                        changed_parameters(model)};
  for (int k = 0; k < perturbed; ++k)
    sets.push_back(perturbed_parameters(model, static_cast<unsigned>(k + 1)));
  sweep_equals_numeric_at(name, sets);
}

}  // namespace mechgen::spatial
