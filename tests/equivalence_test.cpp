// Every compiled kernel against the generic numeric reference solver, column by column, over
// whole steps: at the default parameters, at chosen overrides, and at random geometry, mass and
// speed perturbations that still assemble. The two share nothing but the model reader.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "model/columns.hpp"
#include "model/model.hpp"
#include "numeric/reference_solver.hpp"
#include "plate_crank/plate_crank.hpp"
#include "sweep/compiled_kernel.hpp"

namespace mechgen {
namespace {

constexpr double kTolerance = 1e-9;  // relative to the column's magnitude over the step

Model load(const std::string& name) {
  return read_model(std::string(MECHGEN_SOURCE_DIR) + "/models/" + name + ".yaml");
}

struct Comparison {
  double worst = 0;  // largest |generated - numeric| / column scale
  std::string where;
};

// Runs both solvers over the model's step with `parameters`; false when the numeric solver does
// not assemble (a perturbation outside the mechanism's range).
bool compare(const Model& model, const std::vector<double>& parameters, int samples,
             Comparison& result) {
  const CompiledKernel* kernel = find_compiled_kernel(model.name);
  if (!kernel) {
    ADD_FAILURE() << "no compiled kernel for " << model.name;
    return false;
  }
  const GiNaC::exmap subs = model.substitutions(parameters);
  const double t0 = model.evaluate(model.step.t0, subs), t1 = model.evaluate(model.step.t1, subs);
  numeric::ReferenceSolver solver(model, parameters);
  try {
    solver.assemble(t0);
  } catch (const ModelError&) {
    return false;
  }
  const std::vector<std::string> names = column_names(model);
  std::vector<std::vector<double>> reference, generated;
  for (int i = 0; i < samples; ++i) {
    const double t = t0 + (t1 - t0) * i / (samples - 1);
    std::vector<double> row(names.size()), kernel_row(names.size());
    numeric::Status status;
    try {
      status = solver.solve(t, row);
    } catch (const ModelError&) {
      return false;  // the driver motion leaves its domain (e.g. acos of more than 1)
    }
    EXPECT_EQ(status, numeric::Status::ok) << model.name << " numeric at t=" << t;
    int failed = -1;
    const int kernel_status =
        kernel->evaluate_double(parameters.data(), t, kernel_row.data(), &failed);
    EXPECT_EQ(kernel_status, 0) << model.name << " kernel at t=" << t << " group " << failed;
    if (status != numeric::Status::ok || kernel_status != 0) return true;
    reference.push_back(row);
    generated.push_back(kernel_row);
  }
  // Relative to the column's magnitude over the step; a column that stays near zero (a point on the
  // ground line, a body that barely turns) is compared against 1 % of the largest column of its
  // kind (same suffix: .y, .al, .fx, ...), since relative error means nothing at zero.
  auto suffix = [](const std::string& name) { return name.substr(name.rfind('.') + 1); };
  std::map<std::string, double> kind_scale;
  for (size_t c = 0; c < names.size(); ++c)
    for (const auto& row : reference)
      kind_scale[suffix(names[c])] = std::max(kind_scale[suffix(names[c])], std::abs(row[c]));
  for (size_t c = 0; c < names.size(); ++c) {
    double scale = std::max(1e-300, 0.01 * kind_scale[suffix(names[c])]);
    for (const auto& row : reference) scale = std::max(scale, std::abs(row[c]));
    const bool angle = names[c].size() > 3 && names[c].substr(names[c].size() - 3) == ".th";
    for (size_t r = 0; r < reference.size(); ++r) {
      double diff = generated[r][c] - reference[r][c];
      if (angle) diff = std::remainder(diff, 2 * M_PI);
      const double relative = std::abs(diff) / (angle ? 1.0 : scale);
      if (!(relative <= result.worst)) {
        result.worst = std::isnan(relative) ? INFINITY : relative;
        result.where = names[c] + " at t=" + std::to_string(reference[r][0]);
      }
    }
  }
  return true;
}

class Equivalence : public ::testing::TestWithParam<std::string> {};

TEST_P(Equivalence, DefaultParameters) {
  const Model model = load(GetParam());
  Comparison c;
  ASSERT_TRUE(compare(model, model.default_parameters(), 61, c));
  EXPECT_LE(c.worst, kTolerance) << c.where;
}

// Each parameter scaled by 0.8 and 1.25 in turn (geometry, masses, speeds, loads), where the
// mechanism still assembles.
TEST_P(Equivalence, EachParameterChanged) {
  const Model model = load(GetParam());
  int compared = 0;
  for (size_t i = 0; i < model.parameters.size(); ++i) {
    for (double factor : {0.8, 1.25}) {
      std::vector<double> p = model.default_parameters();
      p[i] = p[i] == 0 ? 1.0 : p[i] * factor;
      Comparison c;
      if (!compare(model, p, 21, c)) continue;
      ++compared;
      EXPECT_LE(c.worst, kTolerance)
          << model.parameters[i].name << " x" << factor << ": " << c.where;
    }
  }
  EXPECT_GE(compared, static_cast<int>(model.parameters.size()));
}

// Random perturbations of every parameter at once, up to 5 %.
TEST_P(Equivalence, RandomPerturbations) {
  const Model model = load(GetParam());
  std::mt19937 random(12345);
  std::uniform_real_distribution<double> factor(0.95, 1.05);
  int compared = 0;
  for (int draw = 0; draw < 20; ++draw) {
    std::vector<double> p = model.default_parameters();
    for (double& v : p) v *= factor(random);
    Comparison c;
    if (!compare(model, p, 21, c)) continue;
    ++compared;
    EXPECT_LE(c.worst, kTolerance) << "draw " << draw << ": " << c.where;
  }
  EXPECT_GE(compared, 4);
}

// plate_crank's coupler point C = (cx, cy) = e (cos phi, sin phi) in the coupler frame is derived:
// --set e=0.05 moves it in the kernel (whose Params has e, not cx) exactly as in the solver, and
// both equal P + R(th) (cx, cy) computed here from the set value.
TEST(DerivedParameters, SetOfABaseParameterMovesThemInTheKernel) {
  const Model model = load("plate_crank");
  ASSERT_GE(model.derived_index("cx"), 0);
  ASSERT_LT(model.parameter_index("cx"), 0);  // not a run-time value of its own
  const CompiledKernel* kernel = find_compiled_kernel("plate_crank");
  ASSERT_NE(kernel, nullptr);
  ASSERT_EQ(kernel->parameter_count, static_cast<int>(model.parameters.size()));
  std::vector<double> p = model.default_parameters();
  apply_overrides(model, {"e=0.05"}, p);
  const std::vector<std::string> names = column_names(model);
  auto col = [&](const std::string& n) {
    return static_cast<size_t>(std::find(names.begin(), names.end(), n) - names.begin());
  };
  numeric::ReferenceSolver solver(model, p);
  solver.assemble(0);
  std::vector<double> row(names.size()), kernel_row(names.size());
  for (const double t : {0.0, 0.3, 0.7}) {
    ASSERT_EQ(solver.solve(t, row), numeric::Status::ok);
    int failed = -1;
    ASSERT_EQ(kernel->evaluate_double(p.data(), t, kernel_row.data(), &failed), 0);
    const double th = row[col("coupler.th")], phi = M_PI / 3;
    const double cx = 0.05 * std::cos(phi), cy = 0.05 * std::sin(phi);
    const double x = row[col("P.x")] + std::cos(th) * cx - std::sin(th) * cy;
    const double y = row[col("P.y")] + std::sin(th) * cx + std::cos(th) * cy;
    EXPECT_NEAR(row[col("C.x")], x, 1e-14);
    EXPECT_NEAR(row[col("C.y")], y, 1e-14);
    EXPECT_NEAR(kernel_row[col("C.x")], x, 1e-12);
    EXPECT_NEAR(kernel_row[col("C.y")], y, 1e-12);
    // The plate's centre of mass, (P + M + C) / 3, moves with C too.
    const double gx = (row[col("P.x")] + row[col("M.x")] + x) / 3;
    EXPECT_NEAR(kernel_row[col("coupler.x")], gx, 1e-12);
  }
}

// The header a user embeds: Params holds e and phi, and computes cx() = e cos(phi), cy(), r();
// the kernel places C with the same values.
TEST(DerivedParameters, KernelParamsComputeThem) {
  namespace k = mechgen::gen::plate_crank;
  k::Params<double> p;
  EXPECT_DOUBLE_EQ(p.cx(), 0.04 * std::cos(M_PI / 3));
  p.e = 0.05;
  p.c = 0.06;
  EXPECT_DOUBLE_EQ(p.cx(), 0.05 * std::cos(M_PI / 3));
  EXPECT_DOUBLE_EQ(p.cy(), 0.05 * std::sin(M_PI / 3));
  EXPECT_DOUBLE_EQ(p.r(), 0.03);
  k::Inputs<double> in;
  k::driver_inputs(p, 0.2, in);
  k::State<double> s;
  ASSERT_EQ(k::evaluate(p, in, s), k::Status::ok);
  const auto& coupler = s.bodies.coupler;
  EXPECT_NEAR(s.points.C.x, s.points.P.x + coupler.cos_th * p.cx() - coupler.sin_th * p.cy(),
              1e-15);
  EXPECT_NEAR(s.points.C.y, s.points.P.y + coupler.sin_th * p.cx() + coupler.cos_th * p.cy(),
              1e-15);
  k::Params<float> f;
  EXPECT_FLOAT_EQ(f.r(), 0.025f);
}

INSTANTIATE_TEST_SUITE_P(ShippedModels, Equivalence,
                         ::testing::Values("chebyshev", "slider_crank", "leg3", "pasibot",
                                           "cylinder_leg", "quick_return", "assur_triad",
                                           "inverted_slider", "plate_crank"));

}  // namespace
}  // namespace mechgen
