// On-demand spatial kernels (issue 14 for `dimension: spatial`): leg6 copied into a temporary
// folder and edited but not renamed makes the compiled-in leg6 kernel stale; `mechgen sweep
// --solver generated` builds, caches and runs a kernel of the edited description (never the stale
// one), equal to `--solver numeric`, and a second run loads it from the cache. A spatial model the
// generator cannot handle (nothing driven) is a clear error, never a stale kernel nor a fallback.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "ondemand_test_support.hpp"
#include "report/csv_table.hpp"

namespace mechgen {
namespace {

namespace fs = std::filesystem;

using test::file_text;
using test::replaced;

fs::path fresh_dir(const std::string& what) {
  const fs::path dir = fs::temp_directory_path() /
                       ("mechgen_spatial_ondemand_" + std::to_string(::getpid()) + "_" + what);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
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
  // Each column to 1e-9 of its largest magnitude over the sweep, at least 1 % of the largest of
  // its kind (a reaction moment about the joint's own axis is zero but for rounding), as
  // tests/spatial_kernel_test.cpp compares the compiled-in kernel.
  auto kind = [](const std::string& name) { return name.substr(name.rfind('.') + 1); };
  std::map<std::string, double> kind_scale;
  for (const auto& row : numeric.rows)
    for (size_t c = 0; c < numeric.header.size(); ++c)
      kind_scale[kind(numeric.header[c])] =
          std::max(kind_scale[kind(numeric.header[c])], std::abs(row[c]));
  double worst = 0;
  std::string where;
  for (size_t c = 0; c < numeric.header.size(); ++c) {
    double scale = std::max(1e-300, 0.01 * kind_scale[kind(numeric.header[c])]);
    for (const auto& row : numeric.rows) scale = std::max(scale, std::abs(row[c]));
    for (size_t r = 0; r < numeric.rows.size(); ++r) {
      const double e = std::abs(generated.rows[r][c] - numeric.rows[r][c]) / scale;
      if (e > worst) worst = e, where = numeric.header[c];
    }
  }
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
