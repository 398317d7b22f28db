// Parallel robots written from the literature (issue 27): the 6-UPS Stewart platform as inverse
// kinematics (models/stewart.yaml, its platform pose-driven) is planned in closed form, every leg
// a cylinder between two known bodies (item 4: the pose driver's virtual chain makes the platform
// known whatever the spanning tree would take); its kernel, built on demand, equals the numeric
// solver on every column, and each leg's length equals |P_i(t) - B_i| computed here from the
// prescribed pose. Clavel's Delta robot (models/delta.yaml) written with plain spherical-spherical
// parallelogram rods is accepted (item 7: each rod's idle spin held, `check` says so), its plate
// centre equals the intersection of three spheres solved here, and the couple that holds each
// rod's spin is zero.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "ondemand_test_support.hpp"
#include "report/csv_table.hpp"
#include "sweep_column_compare.hpp"

namespace mechgen {
namespace {

namespace fs = std::filesystem;

using Vec = std::array<double, 3>;

// `mechgen arguments` with stdout and stderr kept in `out`; returns the exit code.
int mechgen(const std::string& arguments, const fs::path& dir, std::string& out) {
  const std::string command =
      std::string(MECHGEN_BINARY) + " " + arguments + " >" + (dir / "out.txt").string() + " 2>&1";
  const int status = std::system(command.c_str());
  out = test::file_text(dir / "out.txt");
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

size_t column(const report::CsvTable& table, const std::string& name) {
  const auto at = std::find(table.header.begin(), table.header.end(), name);
  EXPECT_NE(at, table.header.end()) << name;
  return static_cast<size_t>(at - table.header.begin());
}

Vec rotate(const Vec& axis_angles, const Vec& p) {
  // R = Rz(a) Ry(b) Rx(c) (the pose driver's rotations in the order z, y, x).
  const double a = axis_angles[0], b = axis_angles[1], c = axis_angles[2];
  const Vec x{p[0], std::cos(c) * p[1] - std::sin(c) * p[2],
              std::sin(c) * p[1] + std::cos(c) * p[2]};
  const Vec y{std::cos(b) * x[0] + std::sin(b) * x[2], x[1],
              -std::sin(b) * x[0] + std::cos(b) * x[2]};
  return {std::cos(a) * y[0] - std::sin(a) * y[1], std::sin(a) * y[0] + std::cos(a) * y[1], y[2]};
}

double distance(const Vec& a, const Vec& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

TEST(ParallelRobots, StewartInverseKinematicsIsClosedFormEqualToNumericAndLegLengths) {
  const fs::path dir = test::fresh_dir("mechgen_parallel", "stewart");
  const std::string model = std::string(MECHGEN_SOURCE_DIR) + "/models/stewart.yaml";
  std::string out;
  ASSERT_EQ(mechgen("check " + model, dir, out), 0) << out;
  EXPECT_NE(out.find("36 secondary coordinates (36 in closed form, 0 by Newton-Raphson)"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("every circuit in closed form, no Newton"), std::string::npos) << out;
  for (int i = 1; i <= 6; ++i)
    EXPECT_NE(
        out.find("closed form, link 'barrel" + std::to_string(i) + "' + 'rod" + std::to_string(i) +
                 "' (length of 'leg" + std::to_string(i) + "') between known 'base' and 'top'"),
        std::string::npos)
        << out;
  const std::string sweep = "sweep " + model + " --samples 81";
  ASSERT_EQ(mechgen(sweep + " --solver numeric --out " + (dir / "num.csv").string(), dir, out), 0)
      << out;
  const report::CsvTable numeric = report::read_csv((dir / "num.csv").string());
  ASSERT_EQ(numeric.rows.size(), 81u);
  std::vector<const report::CsvTable*> tables{&numeric};
  // The generated kernel: a 3 MB header to compile on first use (about a minute), in the Release
  // build only (the sanitizer build checks the plan and the numeric leg lengths).
  report::CsvTable generated;
  if (!test::kSanitizerBuild) {
    ASSERT_EQ(mechgen("generate " + model + " -o " + (dir / "kernel").string(), dir, out), 0)
        << out;
    EXPECT_NE(test::file_text(dir / "kernel" / "stewart.hpp")
                  .find("every circuit in closed form, no Newton"),
              std::string::npos);
    ASSERT_EQ(mechgen(sweep + " --cache " + (dir / "cache").string() + " --out " +
                          (dir / "gen.csv").string(),
                      dir, out),
              0)
        << out;
    generated = report::read_csv((dir / "gen.csv").string());
    ASSERT_EQ(generated.header, numeric.header);
    ASSERT_EQ(generated.rows.size(), 81u);
    std::string where;
    const double worst =
        test::worst_column_difference(numeric.header, numeric.rows, generated.rows, where);
    EXPECT_LT(worst, 1e-9) << where;
    std::cout << "stewart, generated (closed form) against numeric: worst " << worst << " ("
              << where << ")\n";
    tables.push_back(&generated);
  }

  // The model's geometry, written out here (models/stewart.yaml's parameters).
  const double pi = std::acos(-1.0), r_b = 0.5, r_p = 0.3, alpha = 20 * pi / 180,
               beta = 40 * pi / 180, h0 = 0.6, ax = 0.05, ay = 0.04, az = 0.05, g1 = 0.15, g2 = 0.1,
               w = 2;
  const std::array<double, 6> base{-alpha / 2,
                                   alpha / 2,
                                   2 * pi / 3 - alpha / 2,
                                   2 * pi / 3 + alpha / 2,
                                   4 * pi / 3 - alpha / 2,
                                   4 * pi / 3 + alpha / 2};
  const std::array<double, 6> top{-pi / 3 + beta / 2, pi / 3 - beta / 2, pi / 3 + beta / 2,
                                  pi - beta / 2,      pi + beta / 2,     5 * pi / 3 - beta / 2};
  double worst_length = 0, worst_centre = 0, shortest = 1e9, longest = 0;
  for (const report::CsvTable* table : tables)
    for (const auto& row : table->rows) {
      const double t = row[column(*table, "t")];
      const Vec centre{ax * std::sin(w * t), ay * std::sin(2 * w * t), h0 + az * std::sin(w * t)};
      const Vec angles{g1 * std::sin(w * t), g2 * std::sin(2 * w * t), g2 * std::sin(w * t)};
      worst_centre = std::max({worst_centre, std::abs(row[column(*table, "C.x")] - centre[0]),
                               std::abs(row[column(*table, "C.y")] - centre[1]),
                               std::abs(row[column(*table, "C.z")] - centre[2])});
      for (size_t i = 0; i < 6; ++i) {
        const Vec B{r_b * std::cos(base[i]), r_b * std::sin(base[i]), 0};
        const Vec p{r_p * std::cos(top[i]), r_p * std::sin(top[i]), 0};
        const Vec turned = rotate(angles, p);
        const Vec P{centre[0] + turned[0], centre[1] + turned[1], centre[2] + turned[2]};
        const double reference = distance(B, {p[0], p[1], h0});
        const double length = reference + row[column(*table, "leg" + std::to_string(i + 1) + ".q")];
        worst_length = std::max(worst_length, std::abs(length - distance(B, P)));
        shortest = std::min(shortest, length);
        longest = std::max(longest, length);
      }
    }
  EXPECT_LT(worst_centre, 1e-12);
  EXPECT_LT(worst_length, 1e-12);
  EXPECT_GT(longest - shortest, 0.05);  // the legs really move
  std::cout << "stewart leg lengths " << shortest << " to " << longest
            << " m, against |P_i - B_i|: worst " << worst_length << " m\n";
  fs::remove_all(dir);
}

Vec minus(const Vec& a, const Vec& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dot(const Vec& a, const Vec& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// The point at distance l from c1, c2 and c3 with the lower z (the Delta's plate hangs below).
Vec three_spheres(const Vec& c1, const Vec& c2, const Vec& c3, double l) {
  const Vec e = minus(c2, c1), f = minus(c3, c1);
  // p0 = c1 + x e + y f in the centres' plane, equidistant from the three: 2 e.(p0 - c1) = |e|^2
  // and 2 f.(p0 - c1) = |f|^2.
  const double ee = dot(e, e), ef = dot(e, f), ff = dot(f, f), det = ee * ff - ef * ef;
  const double x = (ee * ff - ff * ef) / (2 * det), y = (ff * ee - ee * ef) / (2 * det);
  const Vec p0{c1[0] + x * e[0] + y * f[0], c1[1] + x * e[1] + y * f[1],
               c1[2] + x * e[2] + y * f[2]};
  const Vec n = cross(e, f);
  const double nn = dot(n, n), r2 = dot(minus(p0, c1), minus(p0, c1));
  const double s = std::sqrt((l * l - r2) / nn);
  const Vec up{p0[0] + s * n[0], p0[1] + s * n[1], p0[2] + s * n[2]};
  const Vec down{p0[0] - s * n[0], p0[1] - s * n[1], p0[2] - s * n[2]};
  return up[2] < down[2] ? up : down;
}

TEST(ParallelRobots, DeltaWithSphericalRodsHoldsTheirSpinsAndMatchesThreeSpheres) {
  const fs::path dir = test::fresh_dir("mechgen_parallel", "delta");
  const std::string model = std::string(MECHGEN_SOURCE_DIR) + "/models/delta.yaml";
  std::string out;
  // `check` plans the Delta's kernel (a few seconds of symbolic work): the plain build only.
  if (!test::kSanitizerBuild) {
    ASSERT_EQ(mechgen("check " + model, dir, out), 0) << out;
    for (const char* rod : {"1a", "1b", "2a", "2b", "3a", "3b"})
      EXPECT_NE(out.find(std::string("note: link 'rod") + rod +
                         "' between spherical joints 'elbow" + rod + "' and 'wrist" + rod +
                         "': its spin about the line through them is idle; fixed"),
                std::string::npos)
          << out;
    // The plate by three spheres, then every rod between known bodies: no Newton.
    EXPECT_NE(out.find("platform 'plate' keeps its orientation (parallelogram rods from 'arm1', "
                       "'arm2', 'arm3'): its position from the intersection of three spheres"),
              std::string::npos)
        << out;
    EXPECT_NE(out.find("every circuit in closed form, no Newton"), std::string::npos) << out;
  }
  const std::string sweep = "sweep " + model + " --samples 61";
  ASSERT_EQ(mechgen(sweep + " --solver numeric --out " + (dir / "num.csv").string(), dir, out), 0)
      << out;
  const report::CsvTable numeric = report::read_csv((dir / "num.csv").string());
  ASSERT_EQ(numeric.rows.size(), 61u);
  std::vector<const report::CsvTable*> tables{&numeric};
  // The generated kernel (1.25 MB: about half a minute to compile on first use), in the Release
  // build only: equal to the numeric solver's Newton-Raphson on every column.
  report::CsvTable generated;
  if (!test::kSanitizerBuild) {
    ASSERT_EQ(mechgen(sweep + " --cache " + (dir / "cache").string() + " --out " +
                          (dir / "gen.csv").string(),
                      dir, out),
              0)
        << out;
    generated = report::read_csv((dir / "gen.csv").string());
    ASSERT_EQ(generated.header, numeric.header);
    ASSERT_EQ(generated.rows.size(), 61u);
    std::string where;
    const double worst =
        test::worst_column_difference(numeric.header, numeric.rows, generated.rows, where);
    EXPECT_LT(worst, 1e-9) << where;
    std::cout << "delta, generated (three spheres) against numeric: worst " << worst << " ("
              << where << ")\n";
    tables.push_back(&generated);
  }
  // The model's geometry (models/delta.yaml's parameters).
  const double pi = std::acos(-1.0), R = 0.2, r = 0.05, La = 0.3, l = 0.8;
  double worst_centre = 0, worst_couple = 0, largest_couple = 0, lowest = 0, highest = -1;
  for (const report::CsvTable* table : tables)
    for (const auto& row : table->rows) {
      std::array<Vec, 3> centres;
      for (size_t i = 0; i < 3; ++i) {
        const double phi = 2 * pi * static_cast<double>(i) / 3;
        const double theta = row[column(*table, "theta" + std::to_string(i + 1) + ".q")];
        // The elbow of an arm turned down by theta, minus the plate's joint offset r u_i.
        centres[i] = {(R + La * std::cos(theta) - r) * std::cos(phi),
                      (R + La * std::cos(theta) - r) * std::sin(phi), -La * std::sin(theta)};
      }
      const Vec C = three_spheres(centres[0], centres[1], centres[2], l);
      const Vec swept{row[column(*table, "C.x")], row[column(*table, "C.y")],
                      row[column(*table, "C.z")]};
      worst_centre = std::max(worst_centre, distance(C, swept));
      lowest = std::min(lowest, C[2]);
      highest = std::max(highest, C[2]);
      // Each wrist's couple on the plate about its rod's line (the line from the elbow centre E_i
      // to the plate joint: C + r u_i - E_i, as for the mid-rod of the parallelogram).
      for (size_t i = 0; i < 3; ++i) {
        const Vec u = minus(C, centres[i]);
        for (const char side : {'a', 'b'}) {
          const std::string j = "wrist" + std::to_string(i + 1) + side;
          const Vec M{row[column(*table, j + ".mx")], row[column(*table, j + ".my")],
                      row[column(*table, j + ".mz")]};
          worst_couple = std::max(worst_couple, std::abs(dot(M, u)) / l);
          largest_couple = std::max(largest_couple, std::sqrt(dot(M, M)));
        }
      }
    }
  EXPECT_LT(worst_centre, 1e-12);
  EXPECT_GT(highest - lowest, 0.05);  // the plate really moves
  EXPECT_LT(worst_couple, 1e-12);
  std::cout << "delta plate centre against three spheres: worst " << worst_centre << " m (z from "
            << lowest << " to " << highest << " m); couple about the rods' lines " << worst_couple
            << " N m (largest wrist couple " << largest_couple << " N m)\n";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mechgen
