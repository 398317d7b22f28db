// On-demand spatial kernels (issue 14 for `dimension: spatial`): leg6 copied into a temporary
// folder and edited but not renamed makes the compiled-in leg6 kernel stale; `mechgen sweep
// --solver generated` builds, caches and runs a kernel of the edited description (never the stale
// one), equal to `--solver numeric`, and a second run loads it from the cache. A spatial model the
// generator cannot handle (nothing driven) is a clear error, never a stale kernel nor a fallback.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "ondemand_test_support.hpp"
#include "report/csv_table.hpp"
#include "sweep_column_compare.hpp"

namespace mechgen {
namespace {

namespace fs = std::filesystem;

using test::file_text;
using test::replaced;

fs::path fresh_dir(const std::string& what) {
  return test::fresh_dir("mechgen_spatial_ondemand", what);
}

// Runs the mechgen binary; returns its exit code, with its stderr in `err`.
int mechgen(const std::string& arguments, const fs::path& dir, std::string& err) {
  return test::run_mechgen(arguments, dir, err);
}

TEST(SpatialOnDemand, EditedLeg6InAnotherFolderGetsItsOwnKernelEqualToNumeric) {
  const fs::path dir = fresh_dir("leg6");
  const fs::path model = dir / "leg6.yaml";
  std::string text = file_text(std::string(MECHGEN_SOURCE_DIR) + "/models/leg6.yaml");
  text = replaced(text, "gravity: [0, 0, -9.81]", "gravity: [0.5, 0, -5]");
  text = replaced(text, "value: 0.1*sin(w*t)", "value: 0.2*sin(w*t)");
  text = replaced(text, "toe: [0.06, 0,", "toe: [0.07, 0,");
  text = replaced(text, "l1: {value: 0.075,", "l1: {value: 0.085,");
  std::ofstream(model) << text;
  const std::string cache = " --cache " + (dir / "cache").string();
  const std::string common = "sweep " + model.string() + " --samples 41";
  std::string err;
  ASSERT_EQ(mechgen(common + cache + " --out " + (dir / "first.csv").string(), dir, err), 0) << err;
  EXPECT_NE(err.find("mechgen: compiling kernel for leg6 (the compiled-in kernel is of another "
                     "description), first use: "),
            std::string::npos)
      << err;
  ASSERT_EQ(mechgen(common + cache + " --out " + (dir / "second.csv").string(), dir, err), 0)
      << err;
  EXPECT_EQ(err, "");  // loaded from the cache at once
  EXPECT_EQ(file_text(dir / "first.csv"), file_text(dir / "second.csv"));
  ASSERT_EQ(mechgen(common + " --solver numeric --out " + (dir / "numeric.csv").string(), dir, err),
            0)
      << err;
  const report::CsvTable generated = report::read_csv((dir / "second.csv").string());
  const report::CsvTable numeric = report::read_csv((dir / "numeric.csv").string());
  ASSERT_EQ(generated.header, numeric.header);
  ASSERT_EQ(generated.rows.size(), 41u);
  ASSERT_EQ(numeric.rows.size(), 41u);
  for (size_t r = 0; r < 41; ++r) {
    ASSERT_EQ(generated.rows[r].size(), generated.header.size());
    ASSERT_EQ(numeric.rows[r].size(), numeric.header.size());
  }
  std::string where;
  const double worst =
      test::worst_column_difference(numeric.header, numeric.rows, generated.rows, where);
  EXPECT_LT(worst, 1e-9) << where;
  std::cout << "edited leg6, kernel built on demand against numeric: worst " << worst << " ("
            << where << ")\n";
  // The edits show in the kernel's own numbers: the doubled hip yaw law peaks at 0.2 rad (sample
  // 10 of 0..40 is a quarter period), the thigh is 85 mm (hip at the origin to knee).
  const auto column = [&generated](const std::string& name) {
    const auto at = std::find(generated.header.begin(), generated.header.end(), name);
    EXPECT_NE(at, generated.header.end()) << name;
    return static_cast<size_t>(at - generated.header.begin());
  };
  EXPECT_NEAR(generated.rows[10][column("q1.q")], 0.2, 1e-12);
  for (const auto& row : generated.rows) {
    const double x = row[column("K.x")], y = row[column("K.y")], z = row[column("K.z")];
    EXPECT_NEAR(std::sqrt(x * x + y * y + z * z), 0.085, 1e-12);
  }
  fs::remove_all(dir);
}

// A user's spatial slider-crank (RSUP: crank about z, a rod with a spherical and a universal end,
// a slider along x offset by e and h) written outside models/: its kernel is generated on demand
// with the slider in closed form (a quadratic, no Newton: the banner says so), equal to the
// numeric solver on every column, and its slider follows |C - B| = L written out here:
// x = a cos(theta) + sqrt(L^2 - (e - a sin(theta))^2 - h^2). The period is a parameter named T
// and the slider's point is T too (the kernels' structs take their scalar as Real, not T).
TEST(SpatialOnDemand, UserSpatialSliderCrankClosesInClosedFormEqualToNumeric) {
  const fs::path dir = fresh_dir("rsup");
  const fs::path model = dir / "rsup.yaml";
  std::ofstream(model)
      << "name: rsup\ndimension: spatial\ngravity: [0, 0, -9.81]\nparameters:\n"
         "  a: {value: 0.03, unit: m}\n  e: {value: 0.02, unit: m}\n"
         "  h: {value: 0.015, unit: m}\n  L: {value: 0.12, unit: m}\n"
         "  T: {value: 2.5, unit: s}\n  w: {value: 2*pi/T}\n  x0: {value: 0.03 + sqrt(0.12^2 - "
         "0.02^2 - 0.015^2)}\n"
         "bodies:\n  - {name: ground, ground: true, points: {A: [0, 0, 0]}}\n"
         "  - {name: crank, points: {B: [a, 0, 0]}, mass: {mass: 0.1, com: [a/2, 0, 0], "
         "inertia: [1e-5, 1e-5, 1e-5]}}\n"
         "  - {name: rod, points: {C: [x0, e, h]}, mass: {mass: 0.2, com: [(a + x0)/2, e/2, h/2], "
         "inertia: [1e-4, 1e-4, 1e-4]}}\n"
         "  - {name: slider, points: {T: [x0, e, h]}, mass: {mass: 0.5, com: [x0, e, h], "
         "inertia: [1e-4, 1e-4, 1e-4]}}\n"
         "joints:\n"
         "  - {name: jA, type: revolute, first: ground, second: crank, s: [0, 0, 1], s0: A}\n"
         "  - {name: jB, type: spherical, first: crank, second: rod, s0: [a, 0, 0]}\n"
         "  - {name: jC, type: universal, first: rod, second: slider, s: [0, 0, 1], "
         "s2: [0, 1, 0], s0: [x0, e, h]}\n"
         "  - {name: jP, type: prismatic, first: ground, second: slider, s: [1, 0, 0], "
         "s0: [x0, e, h]}\n"
         "drivers:\n  - {name: theta, joint: jA, kind: angle, value: w*t}\n"
         "step: {t0: 0, t1: T, samples: 61}\n";
  std::string err;
  ASSERT_EQ(mechgen("generate " + model.string() + " -o " + (dir / "kernel").string(), dir, err), 0)
      << err;
  EXPECT_NE(file_text(dir / "kernel" / "rsup.hpp").find("every circuit in closed form, no Newton"),
            std::string::npos);
  const std::string cache = " --cache " + (dir / "cache").string();
  const std::string common = "sweep " + model.string();
  ASSERT_EQ(mechgen(common + cache + " --out " + (dir / "gen.csv").string(), dir, err), 0) << err;
  ASSERT_EQ(mechgen(common + " --solver numeric --out " + (dir / "num.csv").string(), dir, err), 0)
      << err;
  const report::CsvTable generated = report::read_csv((dir / "gen.csv").string());
  const report::CsvTable numeric = report::read_csv((dir / "num.csv").string());
  ASSERT_EQ(generated.header, numeric.header);
  ASSERT_EQ(generated.rows.size(), 61u);
  std::string where;
  EXPECT_LT(test::worst_column_difference(numeric.header, numeric.rows, generated.rows, where),
            1e-9)
      << where;
  const auto column = [&generated](const std::string& name) {
    const auto at = std::find(generated.header.begin(), generated.header.end(), name);
    EXPECT_NE(at, generated.header.end()) << name;
    return static_cast<size_t>(at - generated.header.begin());
  };
  const double a = 0.03, e = 0.02, h = 0.015, L = 0.12;
  const double x0 = a + std::sqrt(L * L - e * e - h * h);
  double worst_slider = 0;
  for (const auto& row : generated.rows) {
    const double theta = row[column("theta.q")];
    const double x =
        a * std::cos(theta) +
        std::sqrt(L * L - (e - a * std::sin(theta)) * (e - a * std::sin(theta)) - h * h);
    worst_slider = std::max(
        {worst_slider, std::abs(row[column("jP.q")] - (x - x0)), std::abs(row[column("T.x")] - x)});
  }
  EXPECT_LT(worst_slider, 1e-14);
  fs::remove_all(dir);
}

TEST(SpatialOnDemand, ModelTheGeneratorCannotHandleIsAClearErrorNeverAFallback) {
  // A body welded to the ground: a valid model with nothing driven, so no kernel to generate.
  const fs::path dir = fresh_dir("weld");
  {
    std::ofstream model(dir / "weld.yaml");
    model << "name: weld\ndimension: spatial\nbodies:\n  - {name: g, ground: true}\n"
             "  - {name: a, mass: {mass: 1, com: [0, 0, 0], inertia: [1, 1, 1]}}\njoints:\n"
             "  - {name: j, type: fixed, first: g, second: a, s0: [0, 0, 0]}\n"
             "step: {t0: 0, t1: 1}\n";
  }
  std::string err;
  const std::string out = (dir / "weld.csv").string();
  EXPECT_EQ(mechgen("sweep " + (dir / "weld.yaml").string() + " --samples 3 --cache " +
                        (dir / "cache").string() + " --out " + out,
                    dir, err),
            1);
  EXPECT_NE(err.find("cannot generate a kernel for 'weld'"), std::string::npos) << err;
  EXPECT_NE(err.find("nothing to generate"), std::string::npos) << err;
  // The advice once, the file once (the generator's own prefix is not repeated).
  const auto advice = err.find("--solver numeric");
  ASSERT_NE(advice, std::string::npos) << err;
  EXPECT_EQ(err.find("--solver numeric", advice + 1), std::string::npos) << err;
  EXPECT_EQ(err.find("error: ", err.find("error: ") + 1), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mechgen
