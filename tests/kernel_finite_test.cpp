// Property: a generated kernel that says `ok` returns only finite outputs. Random finite parameters
// and inputs over wide ranges (near the defaults, up to 1e10, up to 1e300, either sign) through
// every compiled model's scalar entries (double and float, the model's own motion and a given
// one) and its batch entry; a failure names a solve group or a stage. Spatial kernels (leg6) too.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "model/model.hpp"
#include "model/spatial_model.hpp"
#include "model/support_model.hpp"
#include "sweep/compiled_kernel.hpp"

namespace mechgen {
namespace {

// A finite value: a third near `typical` (times 0.9 .. 1.1), a third up to 1e10, a third up to
// 1e300 in magnitude, with a random sign for the last two.
double wide(std::mt19937_64& rng, double typical) {
  std::uniform_int_distribution<int> kind(0, 2);
  std::uniform_real_distribution<double> unit(0, 1);
  const double sign = unit(rng) < 0.5 ? -1 : 1;
  switch (kind(rng)) {
    case 0:
      return typical * (0.9 + 0.2 * unit(rng));
    case 1:
      return sign * std::pow(10.0, 20 * unit(rng) - 10);
    default:
      return sign * std::pow(10.0, 600 * unit(rng) - 300);
  }
}

// Parameters: half the draws the defaults (times 0.9 .. 1.1) with one or two drawn wide, half
// every one wide.
void draw_parameters(std::mt19937_64& rng, const std::vector<double>& defaults,
                     std::vector<double>& parameters) {
  std::uniform_real_distribution<double> unit(0, 1);
  const bool near = unit(rng) < 0.5;
  for (size_t i = 0; i < defaults.size(); ++i) {
    const double typical = defaults[i] == 0 ? 0.1 : defaults[i];
    parameters[i] = near ? typical * (0.9 + 0.2 * unit(rng)) : wide(rng, typical);
  }
  if (near && !defaults.empty())
    for (int k = 0; k < 2; ++k) {
      const size_t i = std::uniform_int_distribution<size_t>(0, defaults.size() - 1)(rng);
      parameters[i] = wide(rng, parameters[i]);
    }
}

// The outputs of one call: ok with every column finite, or a failure naming an entry of
// group_names. Counts what it saw.
struct Tally {
  int ok = 0, non_finite = 0, other = 0;
};
void expect_honest(const CompiledKernel& k, int status, int group, const std::vector<double>& row,
                   const std::string& where, Tally& tally) {
  if (status == 0) {
    ++tally.ok;
    for (int c = 0; c < k.column_count; ++c) {
      ASSERT_TRUE(std::isfinite(row[static_cast<size_t>(c)]))
          << k.model << " " << where << ": ok with " << k.column_names[c] << " = "
          << row[static_cast<size_t>(c)];
    }
    return;
  }
  ASSERT_GE(status, 1) << where;
  ASSERT_LE(status, 3) << where;
  ASSERT_GE(group, 0) << k.model << " " << where << ": status " << status << " names no group";
  ASSERT_LT(group, k.group_count) << where;
  if (status == 3) {
    ++tally.non_finite;
    const std::string stage = k.group_names[group];
    EXPECT_TRUE(stage == "positions" || stage == "rates" || stage == "forces") << stage;
  } else {
    ++tally.other;
  }
}

// The defaults of a shipped model, planar or spatial.
std::vector<double> shipped_defaults(const std::string& name) {
  if (const auto support = split_support_model_name(name))
    return weld_support(read_spatial_model(std::string(MECHGEN_SOURCE_DIR) + "/models/" +
                                           support->first + ".yaml"),
                        support->second)
        .common.default_parameters();
  const std::string path = std::string(MECHGEN_SOURCE_DIR) + "/models/" + name + ".yaml";
  return is_spatial_description(path) ? read_spatial_model(path).common.default_parameters()
                                      : read_model(path).default_parameters();
}

TEST(KernelFinite, OkImpliesEveryOutputFinite) {
  std::mt19937_64 rng(16);
  std::vector<std::string> models = compiled_kernel_models();
  ASSERT_NE(std::find(models.begin(), models.end(), "leg6"), models.end());
  for (const std::string& name : models) {
    const CompiledKernel& k = *find_compiled_kernel(name);
    SCOPED_TRACE(name);
    const std::vector<double> defaults = shipped_defaults(name);
    ASSERT_EQ(defaults.size(), static_cast<size_t>(k.parameter_count));
    std::vector<double> parameters(defaults.size());
    std::vector<double> row(static_cast<size_t>(k.column_count));
    std::vector<double> drivers(static_cast<size_t>(3 * k.driver_count));
    Tally scalar, batch;
    for (int call = 0; call < 1500; ++call) {
      draw_parameters(rng, defaults, parameters);
      const double t = wide(rng, 1.0);
      for (double& d : drivers) d = wide(rng, 1.0);
      int group = -1;
      const std::string where = "call " + std::to_string(call);
      int status = k.evaluate_double(parameters.data(), t, row.data(), &group);
      expect_honest(k, status, group, row, where + " (double)", scalar);
      group = -1;
      status = k.evaluate_float(parameters.data(), t, row.data(), &group);
      expect_honest(k, status, group, row, where + " (float)", scalar);
      group = -1;
      status = k.evaluate_driven_double(parameters.data(), t, drivers.data(), row.data(), &group);
      expect_honest(k, status, group, row, where + " (driven)", scalar);
      if (HasFatalFailure()) return;
    }
    constexpr long n = 64;
    std::vector<double> times(n), out(static_cast<size_t>(n * k.column_count));
    std::vector<int> status(n), group(n);
    for (int block = 0; block < 40; ++block) {
      draw_parameters(rng, defaults, parameters);
      for (double& t : times) t = wide(rng, 1.0);
      k.evaluate_batch_double(parameters.data(), times.data(), n, out.data(), status.data(),
                              group.data());
      for (long i = 0; i < n; ++i) {
        for (int c = 0; c < k.column_count; ++c)
          row[static_cast<size_t>(c)] = out[static_cast<size_t>(c * n + i)];
        expect_honest(k, status[static_cast<size_t>(i)], group[static_cast<size_t>(i)], row,
                      "batch " + std::to_string(block) + " sample " + std::to_string(i), batch);
        if (HasFatalFailure()) return;
      }
    }
    // The draws reach every outcome: ok, a failed check and an overflow caught as non_finite.
    EXPECT_GT(scalar.ok, 0);
    EXPECT_GT(scalar.non_finite + batch.non_finite, 0);
    EXPECT_GT(batch.ok + batch.other, 0);
  }
}

}  // namespace
}  // namespace mechgen
