// The sweep driver, the info JSON and the summary behind the mechgen command line.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "cli/command.hpp"
#include "cli/model_info.hpp"
#include "model/columns.hpp"
#include "model/model.hpp"
#include "report/csv_table.hpp"
#include "sweep/summary.hpp"
#include "sweep/sweep.hpp"

namespace mechgen {
namespace {

std::string model_path(const std::string& name) {
  return std::string(MECHGEN_SOURCE_DIR) + "/models/" + name + ".yaml";
}

std::string file_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

bool ends_with(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

size_t count(const std::string& text, const std::string& needle) {
  size_t n = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
  return n;
}

// Largest difference per column relative to the column's largest magnitude (angles compared
// modulo 2 pi); expects both tables to have the same shape.
void expect_columns_agree(const SweepResult& a, const SweepResult& b, double tolerance) {
  ASSERT_EQ(a.columns, b.columns);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (size_t c = 0; c < a.columns.size(); ++c) {
    const bool angle = ends_with(a.columns[c], ".th");
    double scale = 0, worst = 0;
    size_t worst_row = 0;
    for (size_t r = 0; r < a.rows.size(); ++r) {
      scale = std::max({scale, std::abs(a.rows[r][c]), std::abs(b.rows[r][c])});
      double diff = a.rows[r][c] - b.rows[r][c];
      if (angle) diff = std::remainder(diff, 2 * std::numbers::pi);
      if (std::abs(diff) > worst) worst = std::abs(diff), worst_row = r;
    }
    // Columns that are zero up to rounding (a velocity of a fixed point) are compared absolutely
    // at the scale of the model's other quantities.
    const double reference = angle ? 1.0 : std::max(scale, 1e-6);
    EXPECT_LE(worst / reference, tolerance)
        << a.columns[c] << " at t = " << a.rows[worst_row][0] << ": " << a.rows[worst_row][c]
        << " vs " << b.rows[worst_row][c];
  }
}

TEST(Sweep, NumericAndGeneratedAgreeOnChebyshev) {
  const Model model = read_model(model_path("chebyshev"));
  SweepOptions options = default_sweep(model);
  options.solver = "numeric";
  const SweepResult numeric = run_sweep(model, options);
  options.solver = "generated";
  const SweepResult generated = run_sweep(model, options);
  EXPECT_EQ(numeric.columns, column_names(model));
  EXPECT_EQ(numeric.rows.size(), static_cast<size_t>(model.step.samples));
  expect_columns_agree(numeric, generated, 1e-9);
}

TEST(Sweep, SamplesAreUniformAndEndExactly) {
  const std::vector<double> t = sample_times(0.5, 2.0, 4);
  ASSERT_EQ(t.size(), 4u);
  EXPECT_EQ(t.front(), 0.5);
  EXPECT_DOUBLE_EQ(t[1], 1.0);
  EXPECT_DOUBLE_EQ(t[2], 1.5);
  EXPECT_EQ(t.back(), 2.0);
  EXPECT_EQ(sample_times(3.0, 4.0, 1), std::vector<double>{3.0});
}

TEST(Sweep, OverridesAndThreadsGiveTheSameRows) {
  const Model model = read_model(model_path("chebyshev"));
  std::vector<double> parameters = model.default_parameters();
  apply_overrides(model, {"l=0.04", "w=3"}, parameters);
  SweepOptions options = default_sweep(model, parameters);
  EXPECT_DOUBLE_EQ(options.t1, 2 * std::numbers::pi / 3);  // the step follows the override
  options.samples = 1001;
  options.threads = 1;
  const SweepResult one = run_sweep(model, options);
  options.threads = 3;
  const SweepResult three = run_sweep(model, options);
  EXPECT_EQ(one.rows, three.rows);
  options.solver = "numeric";
  expect_columns_agree(run_sweep(model, options), one, 1e-9);
}

TEST(Sweep, UnreachableSampleIsAnErrorNamingTimeAndGroup) {
  // A rod shorter than the crank: the slider's line is out of reach once r sin(w t) > L.
  const Model model = read_model(model_path("slider_crank"));
  std::vector<double> parameters = model.default_parameters();
  apply_overrides(model, {"L=0.03"}, parameters);
  SweepOptions options = default_sweep(model, parameters);
  for (int threads : {1, 2}) {
    options.threads = threads;
    try {
      run_sweep(model, options);
      FAIL() << "expected an error";
    } catch (const ModelError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find("t = "), std::string::npos) << message;
      EXPECT_NE(message.find("unreachable in group g"), std::string::npos) << message;
      EXPECT_EQ(message.rfind(model.file + ": error: ", 0), 0u) << message;
    }
  }
  options.solver = "numeric";
  EXPECT_THROW(run_sweep(model, options), ModelError);
}

TEST(Sweep, BadRequestsAreErrors) {
  const Model model = read_model(model_path("chebyshev"));
  SweepOptions options = default_sweep(model);
  options.solver = "symbolic";
  EXPECT_THROW(run_sweep(model, options), ModelError);
  options = default_sweep(model);
  options.samples = 0;
  EXPECT_THROW(run_sweep(model, options), ModelError);
  options = default_sweep(model);
  options.parameters.pop_back();
  EXPECT_THROW(run_sweep(model, options), ModelError);
}

TEST(Sweep, CsvHasFullPrecision) {
  SweepResult result{{"t", "a.x"}, {{0.1, 1.0 / 3.0}, {0.2, -2e-300}}};
  const std::string path =
      (std::filesystem::temp_directory_path() / "mechgen_cli_test_sweep.csv").string();
  write_csv(path, result);
  EXPECT_EQ(file_text(path),
            "t,a.x\n0.10000000000000001,0.33333333333333331\n"
            "0.20000000000000001,-2.0000000000000001e-300\n");
  const report::CsvTable table = report::read_csv(path);
  EXPECT_EQ(table.rows, result.rows);
  std::filesystem::remove(path);
  EXPECT_THROW(write_csv("/nonexistent-dir/x.csv", result), std::runtime_error);
}

TEST(Info, PasibotJsonCounts) {
  const Model model = read_model(model_path("pasibot"));
  const std::string json = cli::model_info_json(model);
  EXPECT_EQ(json.rfind("{\"name\": \"pasibot\",", 0), 0u) << json.substr(0, 80);
  EXPECT_NE(json.find("\"gravity\": [0, -9.81]"), std::string::npos);
  EXPECT_NE(json.find("\"l8\": 0.03"), std::string::npos);
  EXPECT_EQ(count(json, "\"ground\": "), 24u);  // bodies
  EXPECT_EQ(count(json, "\"ground\": true"), 1u);
  EXPECT_EQ(count(json, "\"type\": "), 35u);  // joints
  EXPECT_EQ(count(json, "\"kind\": "), 1u);   // drivers
  EXPECT_NE(json.find("{\"name\": \"theta8\", \"joint\": \"A_13_8\", \"kind\": \"angle\"}"),
            std::string::npos);
  EXPECT_NE(json.find("{\"name\": \"S_13_10\", \"type\": \"pin_in_slot\", \"first\": \"l13\", "
                      "\"second\": \"l10\", \"point\": \"S\"}"),
            std::string::npos);
  EXPECT_NE(json.find("{\"name\": \"l13\", \"mass\": 4, "), std::string::npos);
  EXPECT_EQ(count(json, "{"), count(json, "}"));
  EXPECT_EQ(count(json, "["), count(json, "]"));
}

TEST(Info, JsonStringsAndNumbers) {
  EXPECT_EQ(cli::json_string("a\"b\\c\nd\x01"), "\"a\\\"b\\\\c\\nd\\u0001\"");
  EXPECT_EQ(cli::number_text(0.03), "0.03");
  EXPECT_EQ(cli::number_text(-9.81), "-9.81");
  EXPECT_EQ(cli::number_text(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(std::strtod(cli::number_text(1.0 / 3.0).c_str(), nullptr), 1.0 / 3.0);
}

// A hand-made sweep: driver d (with qd), driver e (no qd), body b, joint j.
report::CsvTable hand_table() {
  return report::parse_csv(
      "t,d.q,d.qd,d.qdd,d.effort,e.effort,b.x,b.y,b.th,j.fx,j.fy\n"
      "0,0,2,0,1,5,0.1,1.0,0,3,4\n"
      "1,2,2,0,-3,5,0.2,1.1,0,0,1\n"
      "2,4,2,0,2,5,0.3,0.9,0,6,8\n"
      "3,6,2,0,0,5,0.5,1.0,0,1,0\n",
      "hand.csv");
}

TEST(Summary, HandTable) {
  const SweepSummary s = summarize(hand_table());
  EXPECT_EQ(s.samples, 4u);
  EXPECT_EQ(s.t0, 0.0);
  EXPECT_EQ(s.t1, 3.0);
  ASSERT_EQ(s.drivers.size(), 2u);
  const DriverSummary& d = s.drivers[0];
  EXPECT_EQ(d.name, "d");
  EXPECT_EQ(d.peak_effort, -3.0);
  EXPECT_EQ(d.peak_time, 1.0);
  // Squares 1, 9, 4, 0: trapezoids (1+9)/2 + (9+4)/2 + (4+0)/2 = 13.5 over 3 s.
  EXPECT_DOUBLE_EQ(d.rms_effort, std::sqrt(4.5));
  ASSERT_TRUE(d.has_power);
  // Power 2, -6, 4, 0: (2-6)/2 + (-6+4)/2 + (4+0)/2 = -1 J over 3 s; |power|: 4 + 5 + 2 = 11 J.
  EXPECT_DOUBLE_EQ(d.mean_power, -1.0 / 3.0);
  EXPECT_DOUBLE_EQ(d.mean_abs_power, 11.0 / 3.0);
  EXPECT_DOUBLE_EQ(d.work, -1.0);
  EXPECT_EQ(d.peak_power, -6.0);
  const DriverSummary& e = s.drivers[1];
  EXPECT_EQ(e.peak_effort, 5.0);
  EXPECT_DOUBLE_EQ(e.rms_effort, 5.0);
  EXPECT_FALSE(e.has_power);

  ASSERT_TRUE(s.body.has_value());
  EXPECT_EQ(s.body->name, "b");
  EXPECT_DOUBLE_EQ(s.body->travel, 0.4);
  EXPECT_DOUBLE_EQ(s.body->height_variation, 0.2);
  // y 1.0, 1.1, 0.9, 1.0: (2.1 + 2.0 + 1.9) / 2 over 3 s = 1.0.
  EXPECT_DOUBLE_EQ(s.body->y_mean, 1.0);
  EXPECT_NEAR(s.body->relative_variation, 20.0, 1e-12);

  ASSERT_TRUE(s.joint.has_value());
  EXPECT_EQ(s.joint->name, "j");
  EXPECT_DOUBLE_EQ(s.joint->force, 10.0);
  EXPECT_EQ(s.joint->time, 2.0);

  const std::string text = format_summary(s);
  EXPECT_NE(text.find("driver d"), std::string::npos) << text;
  EXPECT_NE(text.find("body b"), std::string::npos) << text;
  EXPECT_NE(text.find("joint j"), std::string::npos) << text;
}

TEST(Summary, BodyChoiceAndErrors) {
  const report::CsvTable table = hand_table();
  SummaryOptions options;
  options.body = "nobody";
  EXPECT_THROW(summarize(table, options), report::CsvError);
  EXPECT_THROW(summarize(report::parse_csv("t,d.effort\n", "empty.csv")), report::CsvError);
  // Without a t column the sample index is the time axis.
  const SweepSummary s = summarize(report::parse_csv("d.effort\n1\n-1\n1\n", "no_t.csv"));
  EXPECT_TRUE(std::isnan(s.t0));
  EXPECT_DOUBLE_EQ(s.drivers.at(0).rms_effort, 1.0);
  EXPECT_FALSE(s.body.has_value());
}

// A crank turning in place (a full turn: the pin P comes back, its mean height is 0): no gait
// figure by default, and no "height variation / mean" of a path around y = 0 when asked.
report::CsvTable crank_turn() {
  std::string text = "t,d.q,d.qd,d.qdd,d.effort,crank.x,crank.y,crank.th,P.x,P.y,s.q,s.effort\n";
  for (int i = 0; i <= 8; ++i) {
    const double t = i * M_PI / 4, th = std::remainder(t, 2 * M_PI);
    char row[256];
    std::snprintf(row, sizeof row, "%.17g,%.17g,1,0,0.5,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,2\n", t,
                  t, 0.05 * std::cos(t), 0.05 * std::sin(t), th, 0.1 * std::cos(t),
                  0.1 * std::sin(t), 0.3 + 0.1 * std::cos(t));
    text += row;
  }
  return report::parse_csv(text, "crank.csv");
}

TEST(Summary, NoGaitFiguresForAMechanismTurningInPlace) {
  const SweepSummary s = summarize(crank_turn());
  EXPECT_FALSE(s.body.has_value());
  EXPECT_EQ(format_summary(s).find("height"), std::string::npos) << format_summary(s);
  SummaryOptions options;
  options.body = "crank";
  const SweepSummary asked = summarize(crank_turn(), options);
  ASSERT_TRUE(asked.body.has_value());
  EXPECT_NEAR(asked.body->height_variation, 0.1, 1e-15);
  EXPECT_TRUE(std::isnan(asked.body->relative_variation));
  const std::string text = format_summary(asked);
  EXPECT_NE(text.find("body crank (centre of mass)"), std::string::npos) << text;
  EXPECT_EQ(text.find("/ mean"), std::string::npos) << text;
}

TEST(Summary, APointIsLabelledAsAPoint) {
  SummaryOptions options;
  options.body = "P";
  const SweepSummary s = summarize(crank_turn(), options);
  ASSERT_TRUE(s.body.has_value());
  EXPECT_TRUE(s.body->point);
  EXPECT_NEAR(s.body->height_variation, 0.2, 1e-15);
  const std::string text = format_summary(s);
  EXPECT_NE(text.find("\npoint P\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("centre of mass"), std::string::npos) << text;
}

// Without a model: d's q equals crank.th modulo 2 pi (an angle driver: N m); s's q is a length.
TEST(Summary, EffortUnitsFromTheDriverKindWithoutAModel) {
  const SweepSummary s = summarize(crank_turn());
  ASSERT_EQ(s.drivers.size(), 2u);
  EXPECT_EQ(s.drivers[0].kind, "angle");
  EXPECT_TRUE(s.drivers[0].kind_inferred);
  EXPECT_EQ(s.drivers[1].kind, "length");
  const std::string text = format_summary(s);
  EXPECT_NE(text.find("driver d (angle, read from the columns)"), std::string::npos) << text;
  EXPECT_NE(text.find("0.5  N m"), std::string::npos) << text;
  EXPECT_NE(text.find("2  N "), std::string::npos) << text;
  EXPECT_EQ(text.find("N m|N"), std::string::npos) << text;
}

TEST(Summary, TimeAverages) {
  EXPECT_DOUBLE_EQ(time_average({0, 1, 3}, {1, 3, 3}), (2.0 + 6.0) / 3.0);
  EXPECT_DOUBLE_EQ(time_average({2}, {7}), 7.0);
  EXPECT_DOUBLE_EQ(time_rms({0, 1}, {3, 3}), 3.0);
}

// Issue 24: a misspelled command or option suggests the nearest; a word far from every name
// suggests nothing.
TEST(Suggestions, NearestByEditDistance) {
  const std::vector<std::string> commands{"check", "info", "sweep", "summary", "draw", "view"};
  EXPECT_EQ(mechgen::cli::nearest_word("swep", commands), "sweep");      // a deletion
  EXPECT_EQ(mechgen::cli::nearest_word("darw", commands), "draw");       // a transposition
  EXPECT_EQ(mechgen::cli::nearest_word("sumary", commands), "summary");  // a deletion
  EXPECT_EQ(mechgen::cli::nearest_word("chekc", commands), "check");
  EXPECT_EQ(mechgen::cli::nearest_word("frobnicate", commands), "");
  EXPECT_EQ(mechgen::cli::nearest_word("x", commands), "");  // one letter: nothing is near
  EXPECT_EQ(mechgen::cli::unknown_word("command", "veiw", commands),
            "unknown command 'veiw'; did you mean 'view'?");
  EXPECT_EQ(mechgen::cli::unknown_word("option", "--zz", {"--out"}), "unknown option '--zz'");
  // The option parser says it too.
  try {
    mechgen::cli::Args({"--outt", "x"}, {{"--out", "-o", true}, {"--samples", "", true}});
    ADD_FAILURE() << "no error for --outt";
  } catch (const mechgen::cli::UsageError& error) {
    EXPECT_STREQ(error.what(), "unknown option '--outt'; did you mean '--out'?");
  }
}

}  // namespace
}  // namespace mechgen
