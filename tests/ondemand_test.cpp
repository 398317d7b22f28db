// On-demand kernels: a model that no compiled-in kernel matches (a copy of slider_crank renamed and
// edited, in a temporary folder) is generated, compiled, cached and loaded on first use; a second
// process loads it from the cache without compiling; its sweep equals the numeric solver's; a
// compiler failure is an error naming the compiler's log, never a fallback to numeric.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "model/fingerprint.hpp"
#include "model/model.hpp"
#include "ondemand/kernel_resolver.hpp"
#include "report/csv_table.hpp"
#include "sweep/sweep.hpp"

#include "ondemand_test_support.hpp"

namespace mechgen {
namespace {

namespace fs = std::filesystem;

using test::file_text;
using test::replaced;

// A fresh folder holding `name`.yaml: slider_crank renamed, with a longer rod and a doubled speed.
fs::path write_model(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() /
                       ("mechgen_ondemand_test_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string text = file_text(std::string(MECHGEN_SOURCE_DIR) + "/models/slider_crank.yaml");
  text = replaced(text, "name: slider_crank", "name: " + name);
  text = replaced(text, "L: {value: 0.2,", "L: {value: 0.25,");
  text = replaced(text, "w: {value: 10,", "w: {value: 20,");
  std::ofstream(dir / (name + ".yaml")) << text;
  return dir;
}

// Environment variable set for one scope.
struct ScopedEnv {
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old, had_ = true;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() { had_ ? ::setenv(name_, old_.c_str(), 1) : ::unsetenv(name_); }
  const char* name_;
  std::string old_;
  bool had_ = false;
};

// Column by column to 1e-9 of the column's largest magnitude, at least 1e-6 of its unit and 1e-3 of
// the largest column of its kind (its field: a point fixed to the ground, or sliding along x, has
// round-off rates across it, the kernel's exact zeros against the solver's 1e-14); angles modulo a
// turn (the kernel reports (-pi, pi], the numeric solver follows the crank).
void expect_equal_to_numeric(const std::vector<std::string>& columns,
                             const std::vector<std::vector<double>>& generated,
                             const std::vector<std::vector<double>>& numeric) {
  ASSERT_EQ(generated.size(), numeric.size());
  const auto field = [](const std::string& column) { return column.substr(column.rfind('.') + 1); };
  std::map<std::string, double> kind;
  for (size_t c = 0; c < columns.size(); ++c)
    for (const auto& row : numeric)
      kind[field(columns[c])] = std::max(kind[field(columns[c])], std::abs(row[c]));
  for (size_t c = 0; c < columns.size(); ++c) {
    double scale = std::max(1e-6, 1e-3 * kind[field(columns[c])]);
    for (const auto& row : numeric) scale = std::max(scale, std::abs(row[c]));
    const bool angle = columns[c].ends_with(".th");
    for (size_t i = 0; i < numeric.size(); ++i) {
      double difference = generated[i][c] - numeric[i][c];
      if (angle) difference = std::remainder(difference, 2 * std::numbers::pi);
      ASSERT_LE(std::abs(difference), 1e-9 * scale) << columns[c] << " at sample " << i;
    }
  }
}

TEST(OnDemand, ModelInAnyFolderIsBuiltCachedAndEqualsNumeric) {
  const fs::path dir = write_model("crank_in_process");
  const ScopedEnv cache("MECHGEN_CACHE", (dir / "cache").string());
  const Model model = read_model((dir / "crank_in_process.yaml").string());
  EXPECT_EQ(find_compiled_kernel(model.name), nullptr);
  SweepOptions options = default_sweep(model);
  const SweepResult generated = run_sweep(model, options);
  // The library is in the cache, named by model, fingerprint and build key.
  int libraries = 0;
  for (const auto& entry : fs::directory_iterator(dir / "cache"))
    libraries += entry.path().extension() == ".so" &&
                 entry.path().filename().string().starts_with(
                     "crank_in_process-" + hex64(ondemand::expected_fingerprint(model)) + "-");
  EXPECT_EQ(libraries, 1);
  EXPECT_EQ(generated_kernel(model).fingerprint, ondemand::expected_fingerprint(model));
  options.solver = "numeric";
  expect_equal_to_numeric(generated.columns, generated.rows, run_sweep(model, options).rows);
  fs::remove_all(dir);
}

// Names a linkage drawing often uses: a period `T` (a parameter, and a derived speed 2 pi / T that
// names it) and a point `T` (the slider's). They are fields of the kernel's structs, whose scalar
// is Real (T in functions), so the kernel compiles and equals the numeric solver.
TEST(OnDemand, ParameterAndPointNamedTCompile) {
  const fs::path dir = write_model("crank_named_t");
  const fs::path model_file = dir / "crank_named_t.yaml";
  std::string text = file_text(model_file);
  text = replaced(text, "w: {value: 20, unit: rad/s,",
                  "T: {value: 0.314, unit: s, doc: \"period\"}\n  w: {value: 2*pi/T, unit: rad/s,");
  text = replaced(text, "points: {Q: [0, 0]}", "points: {Q: [0, 0], T: [0.01, 0.02]}");
  std::ofstream(model_file) << text;
  const ScopedEnv cache("MECHGEN_CACHE", (dir / "cache").string());
  const Model model = read_model(model_file.string());
  SweepOptions options = default_sweep(model);
  const SweepResult generated = run_sweep(model, options);
  options.solver = "numeric";
  expect_equal_to_numeric(generated.columns, generated.rows, run_sweep(model, options).rows);
  EXPECT_NE(std::find(generated.columns.begin(), generated.columns.end(), "T.x"),
            generated.columns.end());
  fs::remove_all(dir);
}

TEST(OnDemand, EditedShippedModelGetsItsOwnKernelBesideTheCompiledInOne) {
  // The case: slider_crank edited (no gravity, the crank law doubled) but not renamed. The
  // compiled-in slider_crank is stale; the one built on demand has the same namespace and names
  // (hidden visibility keeps the two apart) and gives the edited model's numbers.
  const fs::path dir = write_model("slider_crank");
  const fs::path path = dir / "slider_crank.yaml";
  std::string text = replaced(file_text(path), "gravity: [0, -9.81]", "gravity: [0, 0]");
  text = replaced(text, "kind: angle, value: w*t}", "kind: angle, value: 2*w*t}");
  std::ofstream(path) << text;
  const ScopedEnv cache("MECHGEN_CACHE", (dir / "cache").string());
  const Model model = read_model(path.string());
  const CompiledKernel& kernel = generated_kernel(model);
  ASSERT_NE(find_compiled_kernel("slider_crank"), nullptr);
  EXPECT_NE(&kernel, find_compiled_kernel("slider_crank"));
  EXPECT_NE(kernel.fingerprint, find_compiled_kernel("slider_crank")->fingerprint);
  SweepOptions options = default_sweep(model);
  const SweepResult generated = run_sweep(model, options);
  options.solver = "numeric";
  const SweepResult numeric = run_sweep(model, options);
  expect_equal_to_numeric(generated.columns, generated.rows, numeric.rows);
  // The edit shows: the crank turns at 2 w (40 rad/s with w = 20 here).
  const auto qd = std::find(generated.columns.begin(), generated.columns.end(), "crank_angle.qd");
  ASSERT_NE(qd, generated.columns.end());
  EXPECT_DOUBLE_EQ(generated.rows[5][static_cast<size_t>(qd - generated.columns.begin())], 40.0);
  fs::remove_all(dir);
}

// Runs the mechgen binary; returns its exit code, with its stderr in `err`.
int mechgen(const std::string& arguments, const fs::path& dir, std::string& err) {
  return test::run_mechgen(arguments, dir, err);
}

TEST(OnDemand, SecondRunLoadsFromTheCache) {
  const fs::path dir = write_model("crank_cli");
  const std::string model = (dir / "crank_cli.yaml").string(), cache = (dir / "cache").string();
  std::string err;
  ASSERT_EQ(
      mechgen("sweep " + model + " --cache " + cache + " --out " + (dir / "first.csv").string(),
              dir, err),
      0)
      << err;
  EXPECT_NE(err.find("mechgen: compiling kernel for crank_cli, first use: "), std::string::npos)
      << err;
  ASSERT_EQ(
      mechgen("sweep " + model + " --out " + (dir / "second.csv").string() + " --cache=" + cache,
              dir, err),
      0)
      << err;
  EXPECT_EQ(err, "");  // loaded at once, nothing compiled
  ASSERT_EQ(mechgen("sweep " + model + " --solver numeric --out " + (dir / "numeric.csv").string(),
                    dir, err),
            0)
      << err;
  EXPECT_EQ(file_text(dir / "first.csv"), file_text(dir / "second.csv"));
  const report::CsvTable generated = report::read_csv((dir / "second.csv").string());
  const report::CsvTable numeric = report::read_csv((dir / "numeric.csv").string());
  ASSERT_EQ(generated.header, numeric.header);
  expect_equal_to_numeric(generated.header, generated.rows, numeric.rows);
  fs::remove_all(dir);
}

TEST(OnDemand, ConcurrentFirstUsesLeaveOneGoodKernel) {
  // Two processes find the cache empty: one builds the kernel under the lock, the other waits and
  // loads it; both runs succeed with the same rows, and no build folder is left behind.
  const fs::path dir = write_model("crank_race");
  const std::string model = (dir / "crank_race.yaml").string(), cache = (dir / "cache").string();
  const std::string sweep = std::string(MECHGEN_BINARY) + " sweep " + model + " --cache " + cache;
  const std::string both = "(" + sweep + " --out " + (dir / "a.csv").string() + " 2>" +
                           (dir / "a.err").string() + " & " + sweep + " --out " +
                           (dir / "b.csv").string() + " 2>" + (dir / "b.err").string() +
                           "; b=$?; wait $!; a=$?; exit $((a | b))) >/dev/null";
  ASSERT_EQ(std::system(both.c_str()), 0) << file_text(dir / "a.err") << file_text(dir / "b.err");
  EXPECT_EQ(file_text(dir / "a.csv"), file_text(dir / "b.csv"));
  EXPECT_GT(file_text(dir / "a.csv").size(), 1000u);
  // The library, its hash record and its lock file (ondemand/kernel_cache.hpp); no build folder.
  std::vector<std::string> left;
  for (const auto& entry : fs::directory_iterator(cache)) left.push_back(entry.path().filename());
  std::sort(left.begin(), left.end());
  ASSERT_EQ(left.size(), 3u) << left.front() << " ...";
  EXPECT_TRUE(left[0].ends_with(".lock")) << left[0];
  EXPECT_TRUE(left[1].ends_with(".so")) << left[1];
  EXPECT_EQ(left[2], left[1] + ".sha256");
  std::string err;
  ASSERT_EQ(mechgen("sweep " + model + " --cache " + cache + " --out " + (dir / "c.csv").string(),
                    dir, err),
            0)
      << err;
  EXPECT_EQ(err, "");
  EXPECT_EQ(file_text(dir / "c.csv"), file_text(dir / "a.csv"));
  fs::remove_all(dir);
}

TEST(OnDemand, CompilerFailureNamesItsLogAndNeverFallsBack) {
  const fs::path dir = write_model("crank_broken");
  const ScopedEnv cache("MECHGEN_CACHE", (dir / "cache").string());
  // A "compiler" that runs (it answers the probe) but fails to compile.
  const fs::path compiler = dir / "broken-c++";
  std::ofstream(compiler) << "#!/bin/sh\ncase \" $* \" in *' -### '*) exit 0;; esac\n"
                             "echo 'error: no space left for this kernel' >&2; exit 3\n";
  fs::permissions(compiler, fs::perms::owner_all);
  const ScopedEnv cxx("MECHGEN_CXX", compiler.string());
  const Model model = read_model((dir / "crank_broken.yaml").string());
  try {
    run_sweep(model, default_sweep(model));
    FAIL() << "expected an error";
  } catch (const ModelError& error) {
    const std::string message = error.what();
    EXPECT_TRUE(message.starts_with(model.file + ": error: compiling the kernel of 'crank_broken'"))
        << message;
    const auto at = message.find("the compiler's output is in ");
    ASSERT_NE(at, std::string::npos) << message;
    const std::string log = message.substr(at + 28);
    EXPECT_NE(file_text(log).find("no space left for this kernel"), std::string::npos) << log;
  }
  // Nothing half-built stays behind: only the log (and the build's lock file).
  for (const auto& entry : fs::directory_iterator(dir / "cache"))
    EXPECT_TRUE(entry.path().extension() == ".log" || entry.path().extension() == ".lock")
        << entry.path();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mechgen
