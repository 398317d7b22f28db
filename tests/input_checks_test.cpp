// Bad input never crashes and never lies (issue 16): run-time values get the file's checks,
// expressions are bounded before parsing, and a sweep whose results overflow is an error naming
// the sample, its time and the stage, with either solver.
#include <gtest/gtest.h>

#include <cmath>
#include <new>
#include <string>
#include <vector>

#include "model/model.hpp"
#include "model/value_checks.hpp"
#include "sweep/parallel.hpp"
#include "sweep/sweep.hpp"

namespace mechgen {
namespace {

std::string pasibot_path() {
  return std::string(MECHGEN_SOURCE_DIR) + "/models/pasibot.yaml";
}

// The message of the ModelError that `run` throws ("" when it throws none).
template <class Run>
std::string error_of(Run&& run) {
  try {
    run();
  } catch (const ModelError& error) {
    return error.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The values the file rejects are rejected from --set too (all were accepted before).
TEST(RunTimeValues, SetGetsTheFilesChecks) {
  const Model model = read_model(pasibot_path());
  const std::pair<const char*, const char*> cases[] = {
      {"m_hip=-4", "non-positive mass"},
      {"rho=0", "must be positive"},
      {"rho=-2700", "must be positive"},
      {"bar_w=0", "must be positive"},
  };
  for (const auto& [set, message] : cases) {
    std::vector<double> parameters = model.default_parameters();
    const std::string error = error_of([&] { apply_overrides(model, {set}, parameters); });
    EXPECT_TRUE(contains(error, message)) << set << ": " << error;
    // Located at the file's expression, and naming the value that made it fail.
    EXPECT_EQ(error.rfind(model.file + ":", 0), 0u) << error;
    const std::string name = std::string(set).substr(0, std::string(set).find('='));
    EXPECT_TRUE(contains(error, "(with " + name + " = ")) << error;
  }
  std::vector<double> parameters = model.default_parameters();
  EXPECT_EQ(error_of([&] { apply_overrides(model, {"m_hip=5", "bar_w=0.03"}, parameters); }), "");
  EXPECT_EQ(parameters[static_cast<size_t>(model.parameter_index("m_hip"))], 5.0);
}

// A grid value or a catalogue motor's mass reaches the sweep through default_sweep: checked there.
TEST(RunTimeValues, DefaultSweepChecksGivenParameters) {
  const Model model = read_model(pasibot_path());
  std::vector<double> parameters = model.default_parameters();
  parameters[static_cast<size_t>(model.parameter_index("m_hip"))] = -1;
  EXPECT_TRUE(contains(error_of([&] { default_sweep(model, parameters); }), "non-positive mass"));
  parameters[static_cast<size_t>(model.parameter_index("m_hip"))] = 4;
  parameters[static_cast<size_t>(model.parameter_index("l8"))] = INFINITY;
  EXPECT_TRUE(contains(error_of([&] { check_values(model, parameters); }), "not finite"));
}

// w8 = 1e200 gave 140 NaN columns of 328 with exit 0; now the first sample stops the sweep.
TEST(NonFiniteResults, SweepNamesSampleTimeAndStage) {
  const Model model = read_model(pasibot_path());
  std::vector<double> parameters = model.default_parameters();
  apply_overrides(model, {"w8=1e200"}, parameters);
  {  // The numeric solver refuses at its assembly (the velocity system is then singular).
    SweepOptions options = default_sweep(model, parameters);
    options.solver = "numeric";
    EXPECT_TRUE(contains(error_of([&] { run_sweep(model, options); }), "error: ")) << "numeric";
  }
  for (const char* solver : {"generated"}) {
    SweepOptions options = default_sweep(model, parameters);
    options.solver = solver;
    options.samples = 11;
    const std::string error = error_of([&] { run_sweep(model, options); });
    SCOPED_TRACE(solver);
    EXPECT_TRUE(contains(error, "sample ")) << error;
    EXPECT_TRUE(contains(error, " of 11, t = ")) << error;
    EXPECT_TRUE(contains(error, "non-finite")) << error;
    if (std::string(solver) == "generated") {
      EXPECT_TRUE(contains(error, "in group rates") || contains(error, "in group forces") ||
                  contains(error, "in group positions"))
          << error;
      EXPECT_TRUE(contains(error_of([&] { sweep_ranges(model, options); }), "non-finite"));
    }
  }
}

// A std::bad_alloc in a worker thread aborted the process (an exception escaping a std::thread);
// now every task finishes and the first failure is rethrown on the calling thread.
TEST(Threads, WorkerExceptionIsOneErrorAfterEveryTaskFinished) {
  std::vector<int> done(6, 0);
  try {
    run_parallel(6, [&](size_t k) {
      if (k == 2 || k == 4) throw std::bad_alloc();
      done[k] = 1;
    });
    FAIL() << "no exception";
  } catch (const std::bad_alloc&) {
  }
  EXPECT_EQ(done, (std::vector<int>{1, 1, 0, 1, 0, 1}));
}

// --threads 100000 started 100 000 threads (SIGABRT after 40 s and 2.2 GB): now an error.
TEST(Threads, TooManyThreadsIsAnError) {
  const Model model = read_model(pasibot_path());
  SweepOptions options = default_sweep(model);
  options.threads = thread_limit() + 1;
  EXPECT_TRUE(contains(error_of([&] { sweep_ranges(model, options); }), "threads asked for"));
  options.threads = thread_limit();
  options.samples = 64;
  EXPECT_EQ(sweep_ranges(model, options).samples, 64u);
}

// A model with one expression `text` as a point's x.
std::string model_with_expression(const std::string& text) {
  return "name: m\nparameters: {l: 1}\nbodies:\n  - {name: g, ground: true, points: {A: [0, 0]}}\n"
         "  - name: b\n    points: {A: [0, 0], B: [" +
         text +
         ", 0]}\n    mass: {mass: 1, com: [0, 0], inertia: 1}\n"
         "joints:\n  - {name: j, type: revolute, first: g, second: b, point: A}\n"
         "drivers:\n  - {name: d, joint: j, kind: angle, value: t}\nstep: {t0: 0, t1: 1}\n";
}

// 10 000 nested parentheses overflowed the stack in GiNaC's parser (SIGSEGV).
TEST(ExpressionBounds, DeepNestingIsALocatedError) {
  const auto nested = [](int depth) {
    return std::string(static_cast<size_t>(depth), '(') + "l" +
           std::string(static_cast<size_t>(depth), ')');
  };
  EXPECT_NO_THROW(read_model_text(model_with_expression(nested(64)), "m.yaml"));
  // Line 6, the scalar starts at column 29: the 65th '(' is at column 29 + 64.
  const std::string error =
      error_of([&] { read_model_text(model_with_expression(nested(65)), "m.yaml"); });
  EXPECT_EQ(error.rfind("m.yaml:6:93: error: point 'B' x nests parentheses more than 64", 0), 0u)
      << error;
  // The 10 000 levels (20 001 characters): refused by length before any parsing.
  EXPECT_EQ(error_of([&] {
              read_model_text(model_with_expression(nested(10000)), "m.yaml");
            }).rfind("m.yaml:6:29: error: point 'B' x is 20001 characters long", 0),
            0u);
  std::string sum = "l";
  for (int i = 0; i < 1000; ++i) sum += "+l";
  EXPECT_TRUE(contains(error_of([&] { read_model_text(model_with_expression(sum), "m.yaml"); }),
                       "is 2001 characters long (at most 2000)"));
}

}  // namespace
}  // namespace mechgen
