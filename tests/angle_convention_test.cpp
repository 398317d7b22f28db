// Body angles as the README promises: the numeric solver reports them in (-pi, pi], as the
// kernels do, so the two agree row by row without a 2 pi difference (chebyshev's full crank turn
// used to differ in 270 of 361 rows); an assembly hint equal to the driver's angle modulo 2 pi
// assembles the same configuration.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "model/columns.hpp"
#include "model/model.hpp"
#include "model/spatial_model.hpp"
#include "numeric/reference_solver.hpp"
#include "sweep/compiled_kernel.hpp"

namespace mechgen {
namespace {

std::string file_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<size_t> angle_columns(const Model& model) {
  const std::vector<std::string> names = column_names(model);
  std::vector<size_t> columns;
  for (size_t c = 0; c < names.size(); ++c)
    if (names[c].size() > 3 && names[c].substr(names[c].size() - 3) == ".th") columns.push_back(c);
  return columns;
}

// Every .th column of every sample of the model's step, numeric solver.
std::vector<std::vector<double>> numeric_angles(const Model& model, int samples) {
  const std::vector<double> parameters = model.default_parameters();
  const GiNaC::exmap subs = model.substitutions(parameters);
  const double t0 = model.evaluate(model.step.t0, subs), t1 = model.evaluate(model.step.t1, subs);
  numeric::ReferenceSolver solver(model, parameters);
  solver.assemble(t0);
  std::vector<std::vector<double>> rows;
  std::vector<double> row(column_names(model).size());
  for (int i = 0; i < samples; ++i) {
    const double t = t0 + (t1 - t0) * i / (samples - 1);
    if (solver.solve(t, row) != numeric::Status::ok) break;
    std::vector<double> angles{t};
    for (size_t c : angle_columns(model)) angles.push_back(row[c]);
    rows.push_back(angles);
  }
  return rows;
}

TEST(AngleConvention, NumericSolverReportsBodyAnglesInMinusPiToPi) {
  int models = 0;
  for (const auto& entry : std::filesystem::directory_iterator(MECHGEN_SOURCE_DIR "/models")) {
    // Planar models (a spatial one's orientation is a quaternion: spatial_kinematics_test.cpp).
    if (entry.path().extension() != ".yaml" || is_spatial_description(entry.path())) continue;
    const Model model = read_model(entry.path().string());
    const auto rows = numeric_angles(model, 91);
    EXPECT_GE(rows.size(), 2u) << model.name;
    for (const auto& row : rows)
      for (size_t c = 1; c < row.size(); ++c)
        EXPECT_TRUE(row[c] > -M_PI && row[c] <= M_PI)
            << model.name << " angle " << row[c] << " at t=" << row[0];
    ++models;
  }
  EXPECT_GE(models, 8);
}

// Chebyshev over its full crank turn: the crank passes pi, the coupler and rocker swing; every row
// of every angle equals the kernel's (an atan2) without reduction modulo 2 pi.
TEST(AngleConvention, ChebyshevFullTurnRowsEqualTheKernels) {
  const Model model = read_model(MECHGEN_SOURCE_DIR "/models/chebyshev.yaml");
  const CompiledKernel* kernel = find_compiled_kernel("chebyshev");
  ASSERT_NE(kernel, nullptr);
  const std::vector<double> parameters = model.default_parameters();
  const auto rows = numeric_angles(model, model.step.samples);
  ASSERT_EQ(rows.size(), 361u);
  const std::vector<size_t> columns = angle_columns(model);
  std::vector<double> kernel_row(column_names(model).size());
  int differing = 0, beyond_pi = 0;
  for (const auto& row : rows) {
    int failed = -1;
    ASSERT_EQ(kernel->evaluate_double(parameters.data(), row[0], kernel_row.data(), &failed), 0);
    for (size_t i = 0; i < columns.size(); ++i) {
      if (std::abs(kernel_row[columns[i]] - row[i + 1]) > 1e-9) ++differing;
      if (std::abs(row[i + 1]) > 3) ++beyond_pi;  // near +-pi: the wrap is exercised
    }
  }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(beyond_pi, 10);
}

// The crank is driven at pi/2 + w t: a hint of 5 pi/2 or -3 pi/2 is the same angle.
TEST(AngleConvention, HintEqualToTheDriverModulo2PiAssembles) {
  const std::string text = file_text(MECHGEN_SOURCE_DIR "/models/chebyshev.yaml");
  const std::string hint = "    assembly: pi/2\n  - name: coupler";
  ASSERT_NE(text.find(hint), std::string::npos);
  const Model reference = read_model_text(text, "chebyshev.yaml");
  numeric::ReferenceSolver expected(reference, reference.default_parameters());
  expected.assemble(0);
  for (const std::string turned : {"5*pi/2", "-3*pi/2", "pi/2 + 4*pi"}) {
    std::string changed = text;
    changed.replace(changed.find(hint), hint.size(),
                    "    assembly: " + turned + "\n  - name: coupler");
    const Model model = read_model_text(changed, "chebyshev.yaml");
    numeric::ReferenceSolver solver(model, model.default_parameters());
    try {
      solver.assemble(0);
    } catch (const ModelError& e) {
      ADD_FAILURE() << "crank hint " << turned << ": " << e.what();
      continue;
    }
    for (size_t b = 0; b < model.bodies.size(); ++b) {
      EXPECT_NEAR(solver.poses()[b].x, expected.poses()[b].x, 1e-12) << turned;
      EXPECT_NEAR(solver.poses()[b].y, expected.poses()[b].y, 1e-12) << turned;
      EXPECT_NEAR(std::remainder(solver.poses()[b].th - expected.poses()[b].th, 2 * M_PI), 0, 1e-12)
          << turned << " body " << model.bodies[b].name;
    }
  }
}

}  // namespace
}  // namespace mechgen
