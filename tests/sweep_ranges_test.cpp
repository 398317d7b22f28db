// sweep_ranges (summary-only sweeps: batch entry, threads, no table kept) against the ranges of the
// full table run_sweep returns, and against a column's closed form; failures are reported as
// run_sweep reports them.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "model/model.hpp"
#include "sweep/sweep.hpp"

namespace mechgen {
namespace {

const Model& pasibot() {
  static const Model model = read_model(std::string(MECHGEN_SOURCE_DIR) + "/models/pasibot.yaml");
  return model;
}

TEST(SweepRanges, EqualTheRangesOfTheFullTableOnEveryThreadCount) {
  SweepOptions options = default_sweep(pasibot());
  options.samples = 1001;  // not a multiple of the block size
  options.threads = 1;
  const ColumnRanges table = column_ranges(run_sweep(pasibot(), options));
  ASSERT_EQ(table.samples, 1001u);
  for (int threads : {1, 2, 3}) {
    options.threads = threads;
    const ColumnRanges folded = sweep_ranges(pasibot(), options);
    ASSERT_EQ(folded.columns, table.columns);
    EXPECT_EQ(folded.samples, 1001u);
    for (size_t c = 0; c < table.columns.size(); ++c) {
      EXPECT_EQ(folded.min[c], table.min[c]) << table.columns[c] << ", " << threads << " threads";
      EXPECT_EQ(folded.max[c], table.max[c]) << table.columns[c] << ", " << threads << " threads";
    }
  }
}

// The driver column is the model's own motion: theta8 = theta8_0 + w8 t over [t0, t1].
TEST(SweepRanges, DriverColumnSpansItsMotion) {
  SweepOptions options = default_sweep(pasibot());
  options.samples = 5000;
  options.threads = 2;
  const ColumnRanges ranges = sweep_ranges(pasibot(), options);
  size_t t = 0, q = 0;
  for (size_t c = 0; c < ranges.columns.size(); ++c) {
    if (ranges.columns[c] == "t") t = c;
    if (ranges.columns[c] == "theta8.q") q = c;
  }
  EXPECT_EQ(ranges.min[t], options.t0);
  EXPECT_EQ(ranges.max[t], options.t1);
  // The default step is half a turn at constant speed (from pi/2 to 3 pi/2).
  EXPECT_NEAR(ranges.max[q] - ranges.min[q], M_PI, 1e-12);
}

// A crank 1.2 times its rod cannot assemble over part of the turn: sweep_ranges names the same
// (earliest) failing sample as run_sweep, whatever the thread that met it.
TEST(SweepRanges, AnUnreachableSampleIsTheSameErrorAsInRunSweep) {
  const Model model = read_model(std::string(MECHGEN_SOURCE_DIR) + "/models/slider_crank.yaml");
  std::vector<double> parameters = model.default_parameters();
  size_t r = 0, rod = 0;
  for (size_t i = 0; i < model.parameters.size(); ++i) {
    if (model.parameters[i].name == "r") r = i;
    if (model.parameters[i].name == "L") rod = i;
  }
  parameters[r] = 1.2 * parameters[rod];
  SweepOptions options = default_sweep(model, parameters);
  options.samples = 1000;
  options.threads = 3;
  auto message = [&](auto&& run) {
    try {
      run();
    } catch (const ModelError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string expected = message([&] { run_sweep(model, options); });
  EXPECT_NE(expected.find("unreachable"), std::string::npos) << expected;
  EXPECT_EQ(message([&] { sweep_ranges(model, options); }), expected);
}

}  // namespace
}  // namespace mechgen
