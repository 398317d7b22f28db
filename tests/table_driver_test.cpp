// Drivers from a recorded trajectory (issue 21 item 7): `value: {table: FILE.csv, column: NAME}`.
// The not-a-knot spline reproduces a cubic exactly and a sine to the known interpolation error;
// every bad table is an error located at the model's `table:` key; a changed table changes the
// fingerprint; and rsur driven by a table sampled from its own law sweeps as the law does, with
// both solvers (the generated one through a kernel built on demand).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "model/cubic_spline.hpp"
#include "model/spatial_model.hpp"
#include "ondemand_test_support.hpp"
#include "report/csv_table.hpp"
#include "sweep_column_compare.hpp"

namespace mechgen {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& what) {
  return test::fresh_dir("mechgen_table_driver", what);
}

// A CSV of columns t and theta: theta = f(t) at n equally spaced times over [t0, t1].
void write_table(const fs::path& file, double t0, double t1, int n,
                 const std::function<double(double)>& f) {
  std::ofstream out(file);
  out << "t,theta\n";
  char line[96];
  for (int i = 0; i < n; ++i) {
    const double t = t0 + (t1 - t0) * i / (n - 1);
    std::snprintf(line, sizeof line, "%.17g,%.17g\n", t, f(t));
    out << line;
  }
}

TEST(CubicSpline, ReproducesACubicExactlyWithItsDerivatives) {
  // Unequal intervals; p(t) = 1 - 2 t + 0.5 t^2 + 0.25 t^3.
  const std::vector<double> t{-1.0, -0.3, 0.1, 0.9, 1.0, 2.2, 3.0};
  std::vector<double> y;
  for (const double x : t) y.push_back(1 - 2 * x + 0.5 * x * x + 0.25 * x * x * x);
  const CubicSpline s(t, y, "cubic");
  for (int i = 0; i <= 400; ++i) {
    const double x = -1.0 + 4.0 * i / 400;
    EXPECT_NEAR(s(x, 0), 1 - 2 * x + 0.5 * x * x + 0.25 * x * x * x, 1e-12) << x;
    EXPECT_NEAR(s(x, 1), -2 + x + 0.75 * x * x, 1e-12) << x;
    EXPECT_NEAR(s(x, 2), 1 + 1.5 * x, 1e-12) << x;
  }
  // Four samples are the fewest: one cubic through them.
  const CubicSpline four({0, 1, 2, 3}, {0, 1, 8, 27}, "t^3");
  EXPECT_NEAR(four(1.5, 0), 3.375, 1e-12);
  EXPECT_NEAR(four(1.5, 1), 6.75, 1e-12);
  EXPECT_NEAR(four(0.0, 2), 0.0, 1e-12);
  EXPECT_NEAR(four(3.0, 2), 18.0, 1e-12);
  EXPECT_THROW(CubicSpline({0, 1, 2}, {0, 1, 2}, "three"), std::invalid_argument);
  EXPECT_THROW(four(3.001, 0), std::domain_error);
  EXPECT_THROW(four(-0.001, 1), std::domain_error);
}

// sin over [0, 2 pi]: away from the ends (where the not-a-knot condition, not the data, sets the
// spline) the error is within the cubic spline's bounds for |f''''| <= 1 (Hall and Meyer 1976):
// 5/384 h^4, h^3/24 and 3/8 h^2 for the value, the first and the second derivative; and the
// value's error is the uniform spline's asymptotic one, h^4/384 max |f''''| (at the intervals'
// midpoints), so it falls as h^4.
TEST(CubicSpline, InterpolatesASineWithinItsKnownError) {
  double previous = 0;
  for (const int n : {65, 129}) {
    std::vector<double> t, y;
    const double h = 2 * M_PI / (n - 1);
    for (int i = 0; i < n; ++i) t.push_back(h * i), y.push_back(std::sin(h * i));
    const CubicSpline s(t, y, "sine");
    double e0 = 0, e1 = 0, e2 = 0;
    for (int i = 4 * 8; i <= (n - 5) * 8; ++i) {  // four intervals in from each end
      const double x = h * i / 8;
      e0 = std::max(e0, std::abs(s(x, 0) - std::sin(x)));
      e1 = std::max(e1, std::abs(s(x, 1) - std::cos(x)));
      e2 = std::max(e2, std::abs(s(x, 2) + std::sin(x)));
    }
    EXPECT_LT(e0, 5.0 / 384 * std::pow(h, 4)) << n;
    EXPECT_LT(e1, std::pow(h, 3) / 24) << n;
    EXPECT_LT(e2, 3.0 / 8 * h * h) << n;
    EXPECT_NEAR(e0 / (std::pow(h, 4) / 384), 1.0, 0.02) << n;  // an interpolation, not sin
    if (previous > 0) {
      EXPECT_NEAR(previous / e0, 16.0, 0.3);
    }
    previous = e0;
    // At the knots the value is the sample's.
    EXPECT_NEAR(s(t[7], 0), y[7], 1e-15);
  }
}

const char* const kModel = R"(name: one_crank
dimension: spatial
bodies:
  - {name: ground, ground: true}
  - name: crank
    points: {A: [0, 0, 0], B: [0.1, 0, 0]}
    mass: {mass: 1, com: [0.05, 0, 0], inertia: [0.001, 0.001, 0.001]}
joints:
  - {name: jA, type: revolute, first: ground, second: crank, s: [0, 0, 1], s0: A}
drivers:
  - name: theta
    joint: jA
    kind: angle
    value: {table: motion.csv, column: theta}
)";

TEST(TableDriver, ReadsTheTableAndTakesItsSpanAsTheDefaultStep) {
  const fs::path dir = fresh_dir("read");
  write_table(dir / "motion.csv", 0.5, 2.5, 21, [](double t) { return t * t; });
  std::ofstream(dir / "m.yaml") << kModel;
  const SpatialModel m = read_spatial_model((dir / "m.yaml").string());
  ASSERT_EQ(m.drivers.size(), 1u);
  ASSERT_TRUE(m.drivers[0].table.has_value());
  const CubicSpline& s = *m.drivers[0].table->spline;
  EXPECT_NEAR(s(1.7, 0), 1.7 * 1.7, 1e-12);
  EXPECT_NEAR(s(1.7, 1), 3.4, 1e-12);
  EXPECT_NEAR(s(1.7, 2), 2.0, 1e-11);
  const GiNaC::exmap none;
  EXPECT_EQ(m.evaluate(m.common.step.t0, none), 0.5);
  EXPECT_EQ(m.evaluate(m.common.step.t1, none), 2.5);
  EXPECT_EQ(m.common.step.samples, 101);
  // The placeholder law: the table's first value (the generated kernel's own start).
  EXPECT_EQ(m.evaluate(m.drivers[0].value, none), 0.25);
  EXPECT_EQ(m.drivers[0].value_d, 0);
  // `step:` overrides the span; a `time:` column other than t.
  std::string text = kModel;
  text += "step: {t0: 1, t1: 2, samples: 11}\n";
  text = test::replaced(text, "column: theta}", "column: theta, time: seconds}");
  std::ofstream(dir / "m.yaml") << text;
  {
    std::ofstream csv(dir / "motion.csv");
    csv << "# logged\nseconds, theta\n0,0\n1,1\n2,8\n3,27\n\n";
  }
  const SpatialModel stepped = read_spatial_model((dir / "m.yaml").string());
  EXPECT_EQ(stepped.evaluate(stepped.common.step.t0, none), 1.0);
  EXPECT_EQ(stepped.common.step.samples, 11);
  EXPECT_NEAR((*stepped.drivers[0].table->spline)(2.5, 1), 3 * 2.5 * 2.5, 1e-12);
}

TEST(TableDriver, EveryBadTableIsAnErrorAtTheTableKey) {
  const fs::path dir = fresh_dir("errors");
  std::ofstream(dir / "m.yaml") << kModel;
  // At the `table:` key's value (line 14, column 20), as every description error is located.
  const std::string at = (dir / "m.yaml").string() + ":14:20: error: ";
  struct Case {
    const char* csv;  // nullptr: no file
    std::string message;
  };
  const std::string file = "table '" + (dir / "motion.csv").string() + "'";
  const Case cases[] = {
      {nullptr, file + ": cannot open the file"},
      {"t,phi\n0,0\n1,1\n2,2\n3,3\n", file + " line 1: no column 'theta' (the driver's value)"},
      {"time,theta\n0,0\n1,1\n2,2\n3,3\n", file + " line 1: no column 't' (the time, s)"},
      {"t,theta\n0,0\n1,1\n", file + ": 2 rows; a cubic spline needs at least 4 samples"},
      {"t,theta\n0,0\n1,1\n1,2\n3,3\n", file + " line 4: the times are not strictly increasing"},
      {"t,theta\n0,0\n1,nan\n2,2\n3,3\n",
       file + " line 3: column 'theta' holds 'nan', not a finite number"},
      {"t,theta\n0,0\n1,inf\n2,2\n3,3\n",
       file + " line 3: column 'theta' holds 'inf', not a finite number"},
      {"t,theta\n0,0\n1,\n2,2\n3,3\n", file + " line 3: column 'theta' holds '', not"},
      {"t,theta\n0,0\n1,2,3\n2,2\n3,3\n", file + " line 3: 3 fields, the header has 2"},
      {"", file + ": the file is empty"},
  };
  for (const Case& c : cases) {
    fs::remove(dir / "motion.csv");
    if (c.csv != nullptr) std::ofstream(dir / "motion.csv") << c.csv;
    try {
      read_spatial_model((dir / "m.yaml").string());
      ADD_FAILURE() << "no error for: " << (c.csv ? c.csv : "(no file)");
    } catch (const ModelError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(at + c.message, 0), 0u)
          << e.what() << "\nexpected: " << at << c.message;
    }
  }
}

// A planar model's driver takes a law only: the table is refused where it is written.
TEST(TableDriver, APlanarModelRefusesATable) {
  const fs::path dir = fresh_dir("planar");
  const std::string text =
      test::replaced(test::file_text(std::string(MECHGEN_SOURCE_DIR) + "/models/slider_crank.yaml"),
                     "value: w*t}", "value: {table: motion.csv, column: theta}}");
  std::ofstream(dir / "m.yaml") << text;
  try {
    read_model((dir / "m.yaml").string());
    ADD_FAILURE() << "no error";
  } catch (const ModelError& e) {
    EXPECT_EQ(std::string(e.what()),
              (dir / "m.yaml").string() +
                  ":58:68: error: driver 'crank_angle': a table driver is for spatial models "
                  "only (planar ones take a law of t)");
  }
}

TEST(TableDriver, AChangedTableChangesTheFingerprint) {
  const fs::path dir = fresh_dir("fingerprint");
  std::ofstream(dir / "m.yaml") << kModel;
  write_table(dir / "motion.csv", 0, 1, 11, [](double t) { return std::sin(t); });
  const std::uint64_t first = read_spatial_model((dir / "m.yaml").string()).common.description_hash;
  EXPECT_EQ(read_spatial_model((dir / "m.yaml").string()).common.description_hash, first);
  write_table(dir / "motion.csv", 0, 1, 11, [](double t) { return std::sin(t) + 1e-15 * t; });
  const std::uint64_t second =
      read_spatial_model((dir / "m.yaml").string()).common.description_hash;
  EXPECT_NE(second, first);
  // The same description with the law instead of the table hashes differently again.
  std::string law = test::replaced(kModel, "{table: motion.csv, column: theta}", "sin(t)");
  law += "step: {t0: 0, t1: 1}\n";
  std::ofstream(dir / "law.yaml") << law;
  EXPECT_NE(read_spatial_model((dir / "law.yaml").string()).common.description_hash, first);
}

// rsur with its crank law replaced by theta = w t + 0.3 sin(w t) (w = 2 rad/s), and the same
// model driven by a table of that law (2001 samples over its period, pi s): both solvers on the
// table against the numeric solver on the law.
TEST(TableDriver, RsurAlongATableOfItsOwnLawSweepsAsTheLawWithBothSolvers) {
  const fs::path dir = fresh_dir("rsur");
  const std::string original =
      test::file_text(std::string(MECHGEN_SOURCE_DIR) + "/models/rsur.yaml");
  const std::string law = test::replaced(original, "value: w*t}", "value: w*t + 0.3*sin(w*t)}");
  std::ofstream(dir / "law.yaml") << law;
  std::string table = test::replaced(law, "value: w*t + 0.3*sin(w*t)}",
                                     "value: {table: crank.csv, column: theta}}");
  table = test::replaced(table, "step: {t0: 0, t1: 2*pi/w, samples: 181}", "");
  std::ofstream(dir / "table.yaml") << table;
  write_table(dir / "crank.csv", 0, M_PI, 2001,
              [](double t) { return 2 * t + 0.3 * std::sin(2 * t); });
  const std::string samples = " --samples 181";
  std::string err;
  ASSERT_EQ(test::run_mechgen("sweep " + (dir / "law.yaml").string() + samples +
                                  " --solver numeric --out " + (dir / "law.csv").string(),
                              dir, err),
            0)
      << err;
  ASSERT_EQ(test::run_mechgen("sweep " + (dir / "table.yaml").string() + samples +
                                  " --solver numeric --out " + (dir / "numeric.csv").string(),
                              dir, err),
            0)
      << err;
  ASSERT_EQ(test::run_mechgen("sweep " + (dir / "table.yaml").string() + samples + " --cache " +
                                  (dir / "cache").string() + " --solver generated --out " +
                                  (dir / "generated.csv").string(),
                              dir, err),
            0)
      << err;
  const report::CsvTable expected = report::read_csv((dir / "law.csv").string());
  for (const char* name : {"numeric.csv", "generated.csv"}) {
    const report::CsvTable got = report::read_csv((dir / name).string());
    ASSERT_EQ(got.header, expected.header) << name;
    ASSERT_EQ(got.rows.size(), 181u) << name;
    ASSERT_EQ(expected.rows.size(), 181u);
    // Positions (t, joint coordinates .q and .qN, points' x, y, z) to 1e-9 absolute; every column
    // to a relative 1e-5 of its scale (sweep_column_compare.hpp: a reaction's at least 1e-3 of the
    // largest; the spline's q'' error, 3/8 h^2 |f''''| = 4.4e-6 rad/s^2 here, against q'' up to
    // 1.2 rad/s^2, bounds the accelerations and the efforts).
    double worst_q = 0;
    std::string where_q, where_rest;
    for (size_t c = 0; c < expected.header.size(); ++c) {
      const std::string& n = expected.header[c];
      const std::string field = n.substr(n.rfind('.') + 1);
      const bool position =
          n == "t" || field == "q" ||
          (field.size() == 2 && field[0] == 'q' && field[1] >= '1' && field[1] <= '9') ||
          field == "x" || field == "y" || field == "z";
      for (size_t r = 0; position && r < expected.rows.size(); ++r) {
        const double d = std::abs(got.rows[r][c] - expected.rows[r][c]);
        if (d > worst_q) worst_q = d, where_q = n;
      }
    }
    const double worst_rest =
        test::worst_column_difference(expected.header, expected.rows, got.rows, where_rest);
    EXPECT_LT(worst_q, 1e-9) << name << " " << where_q;
    EXPECT_LT(worst_rest, 1e-5) << name << " " << where_rest;
    std::cout << name << " against the law: positions " << worst_q << " (" << where_q
              << "), the rest relative " << worst_rest << " (" << where_rest << ")\n";
  }
  // The two solvers on the same table agree as they do on laws (the generated kernel gets the
  // spline's motion through its driven entry).
  {
    const report::CsvTable numeric = report::read_csv((dir / "numeric.csv").string());
    const report::CsvTable generated = report::read_csv((dir / "generated.csv").string());
    std::string where;
    const double worst =
        test::worst_column_difference(numeric.header, numeric.rows, generated.rows, where);
    EXPECT_LT(worst, 1e-9) << where;
    std::cout << "generated against numeric, both on the table: " << worst << " (" << where
              << ")\n";
  }
  // --mass-matrix: the kernel's mass_bias entry takes the same driven motion (M and h of theta,
  // h through q' only: equal to the law's to the spline's q' error).
  {
    std::vector<report::CsvTable> runs;
    for (const auto& [model, solver] : {std::pair{"law.yaml", "numeric"},
                                        {"table.yaml", "numeric"},
                                        {"table.yaml", "generated"}}) {
      ASSERT_EQ(
          test::run_mechgen("sweep " + (dir / model).string() +
                                " --samples 21 --mass-matrix --solver " + solver + " --cache " +
                                (dir / "cache").string() + " --out " + (dir / "mass.csv").string(),
                            dir, err),
          0)
          << err;
      runs.push_back(report::read_csv((dir / "mass.csv").string()));
    }
    const size_t columns = runs[0].header.size();
    ASSERT_EQ(runs[0].header[columns - 2], "M.theta.theta");
    ASSERT_EQ(runs[0].header[columns - 1], "h.theta");
    for (size_t c = columns - 2; c < columns; ++c) {
      double scale = 0;
      for (const auto& row : runs[0].rows) scale = std::max(scale, std::abs(row[c]));
      ASSERT_GT(scale, 0);
      for (size_t r = 0; r < 21; ++r)
        for (size_t k = 1; k < 3; ++k)
          EXPECT_NEAR(runs[k].rows[r][c], runs[0].rows[r][c], 1e-9 * scale)
              << runs[0].header[c] << " run " << k << " row " << r;
    }
  }
  // URDF and MJCF hold no trajectory: exporting the table model is an error at its table.
  EXPECT_NE(test::run_mechgen("export " + (dir / "table.yaml").string() + " --urdf " +
                                  (dir / "out.urdf").string(),
                              dir, err),
            0);
  EXPECT_NE(err.find("table.yaml:43:50: error: "), std::string::npos) << err;  // the mapping
  EXPECT_NE(err.find("driver 'theta': follows a table; the exported driver law is a number or a "
                     "law of t: export the model with a law"),
            std::string::npos)
      << err;
  // Outside the table's range: an error, with either solver.
  for (const char* solver : {"numeric", "generated"}) {
    EXPECT_NE(test::run_mechgen("sweep " + (dir / "table.yaml").string() + " --t1 4 --solver " +
                                    solver + " --cache " + (dir / "cache").string() + " --out " +
                                    (dir / "out.csv").string(),
                                dir, err),
              0);
    EXPECT_NE(err.find("is not within its table's [0, 3.1415926535897931] s"), std::string::npos)
        << err;
  }
}

}  // namespace
}  // namespace mechgen
