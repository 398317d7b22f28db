// The generated spatial kernel of seed 003's leg (generated/lecture_leg/lecture_leg.hpp, the
// forward kinematics the walking example calls) against the numeric reference solver: every CSV
// column of the model's own motion, at the default and at changed run-time parameters, in double
// (1e-9 of each column's scale); the float kernel to 1e-5 of each quantity's largest magnitude.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "lecture_leg/lecture_leg.hpp"
#include "model/spatial_model.hpp"
#include "spatial/spatial_sweep.hpp"

namespace {

namespace k = mechgen::gen::lecture_leg;

// The header's columns along the model's own motion at the sweep's sample times.
template <class T>
std::vector<std::vector<double>> kernel_rows(const std::vector<double>& parameters,
                                             const mechgen::spatial::SpatialSweepResult& numeric) {
  std::vector<T> values(parameters.begin(), parameters.end());
  k::Params<T> p;
  k::set_parameters(p, values.data());
  std::vector<std::vector<double>> rows;
  for (const auto& reference : numeric.rows) {
    k::Inputs<T> in;
    k::driver_inputs(p, static_cast<T>(reference[0]), in);
    k::State<T> s;
    EXPECT_EQ(k::evaluate(p, in, s), k::Status::ok) << "t = " << reference[0];
    T row[k::column_count];
    k::to_columns(in, s, row);
    rows.emplace_back(row, row + k::column_count);
  }
  return rows;
}

// The quantity a column holds, by its suffix after the last '.': moments (mx, my, mz) and driver
// efforts (every driver here turns a revolute joint) share one, N m.
std::string quantity(const std::string& column) {
  const std::string suffix = column.substr(column.rfind('.') + 1);
  const bool moment = suffix == "effort" || (suffix.size() == 2 && suffix[0] == 'm');
  return moment ? "moment" : suffix;
}

// Largest relative difference; a column's scale is its largest magnitude, at least `floor` times
// the largest magnitude among columns of the same quantity, so that a quantity zero by the
// structure (every reaction moment of this planar leg: zero but for rounding) is judged against
// its peers: 1e-3 in double; 1 in float (float rounding is relative to the largest of its kind).
double worst_difference(const mechgen::spatial::SpatialSweepResult& numeric,
                        const std::vector<std::vector<double>>& rows, double floor,
                        std::string& where) {
  std::vector<double> scale(numeric.columns.size(), 0);
  std::map<std::string, double> peers;
  for (size_t c = 0; c < numeric.columns.size(); ++c) {
    for (const auto& row : numeric.rows) scale[c] = std::max(scale[c], std::abs(row[c]));
    peers[quantity(numeric.columns[c])] = std::max(peers[quantity(numeric.columns[c])], scale[c]);
  }
  double worst = 0;
  for (size_t c = 0; c < numeric.columns.size(); ++c) {
    const double s = std::max({scale[c], floor * peers[quantity(numeric.columns[c])], 1e-300});
    for (size_t r = 0; r < rows.size(); ++r) {
      const double e = std::abs(rows[r][c] - numeric.rows[r][c]) / s;
      if (e > worst)
        worst = e, where = numeric.columns[c] + " at t = " + std::to_string(rows[r][0]);
    }
  }
  return worst;
}

TEST(LectureLegKernel, EveryColumnEqualsTheNumericSolver) {
  const mechgen::SpatialModel model =
      mechgen::read_spatial_model(MECHGEN_SOURCE_DIR "/models/lecture_leg.yaml");
  ASSERT_EQ(k::parameter_count, static_cast<int>(model.common.parameters.size()));
  std::vector<double> changed = model.common.default_parameters();
  for (size_t i = 0; i < changed.size(); ++i) changed[i] *= 1.0 + 0.1 * static_cast<double>(i + 1);
  for (const std::vector<double>& parameters : {model.common.default_parameters(), changed}) {
    mechgen::spatial::SpatialSweepOptions options =
        mechgen::spatial::default_spatial_sweep(model, parameters);
    options.samples = 41;
    const mechgen::spatial::SpatialSweepResult numeric =
        mechgen::spatial::run_spatial_sweep(model, options);
    ASSERT_EQ(numeric.columns,
              std::vector<std::string>(k::column_names, k::column_names + k::column_count));
    std::string where;
    const double worst =
        worst_difference(numeric, kernel_rows<double>(parameters, numeric), 1e-3, where);
    EXPECT_LT(worst, 1e-9) << where;
    std::string where_float;
    const double worst_float =
        worst_difference(numeric, kernel_rows<float>(parameters, numeric), 1, where_float);
    EXPECT_LT(worst_float, 1e-5) << where_float;
    std::cout << "lecture_leg kernel against the numeric solver, 41 samples: double worst " << worst
              << " (" << where << "), float worst " << worst_float << " (" << where_float << ")\n";
  }
}

}  // namespace
