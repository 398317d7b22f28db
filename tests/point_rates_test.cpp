// Issue 27 item 6: the named points' velocity and acceleration columns (planar `<p>.vx, .vy, .ax,
// .ay`; spatial `<p>.vx .. .az`), appended after the original columns. Checked against the time
// derivatives of the points' own position columns (central differences of a fine sweep: an
// expectation that shares no code with either solver), in the numeric solver and in the generated
// kernel, planar (the Chebyshev four-bar) and spatial (the serial leg6, the closed RSUR loop).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "model/model.hpp"
#include "model/spatial_model.hpp"
#include "ondemand/kernel_resolver.hpp"
#include "spatial/spatial_kernel_sweep.hpp"
#include "spatial/spatial_sweep.hpp"
#include "sweep/sweep.hpp"

namespace mechgen {
namespace {

struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  double dt = 0;

  size_t index(const std::string& name) const {
    const auto it = std::find(columns.begin(), columns.end(), name);
    EXPECT_NE(it, columns.end()) << "no column " << name;
    return static_cast<size_t>(it - columns.begin());
  }
};

// Largest difference between column `rate` and the five-point central difference of column `of`
// (error of order dt^4; interior samples).
double derivative_error(const Table& t, const std::string& of, const std::string& rate) {
  const size_t a = t.index(of), b = t.index(rate);
  double worst = 0;
  for (size_t i = 2; i + 2 < t.rows.size(); ++i) {
    const auto x = [&](size_t k) { return t.rows[k][a]; };
    const double fd = (x(i - 2) - 8 * x(i - 1) + 8 * x(i + 1) - x(i + 2)) / (12 * t.dt);
    worst = std::max(worst, std::abs(fd - t.rows[i][b]));
  }
  return worst;
}

// The largest magnitude of the point's `field` columns over every axis and sample: a scale for the
// point's rate (an axis along which the point does not move has none of its own).
double scale(const Table& t, const std::string& point, const std::string& field,
             const std::vector<std::string>& axes) {
  double s = 1e-6;  // SI: a point at rest (on the ground) has only round-off
  for (const std::string& x : axes) {
    const size_t c = t.index(point + "." + field + x);
    for (const std::vector<double>& row : t.rows) s = std::max(s, std::abs(row[c]));
  }
  return s;
}

// Every named point's rates are the derivatives of its position (the velocity of the position
// and the acceleration of the velocity), axis by axis, to 1e-7 of the point's speed and
// acceleration over the run.
void expect_point_rates(const Table& t, const std::vector<std::string>& points,
                        const std::vector<std::string>& axes, const std::string& label) {
  ASSERT_FALSE(points.empty());
  for (const std::string& p : points) {
    const double v = scale(t, p, "v", axes), a = scale(t, p, "a", axes);
    for (const std::string& x : axes) {
      EXPECT_LT(derivative_error(t, p + "." + x, p + ".v" + x), 1e-7 * v) << label << " " << p << x;
      EXPECT_LT(derivative_error(t, p + ".v" + x, p + ".a" + x), 1e-7 * a)
          << label << " " << p << x;
    }
  }
}

// The rate columns are the last ones, in point order, and nowhere else: the original columns keep
// their positions.
void expect_appended(const std::vector<std::string>& columns,
                     const std::vector<std::string>& points,
                     const std::vector<std::string>& fields) {
  std::vector<std::string> rates;
  for (const std::string& p : points)
    for (const std::string& f : fields) rates.push_back(p + "." + f);
  ASSERT_GT(columns.size(), rates.size());
  const auto tail = columns.end() - static_cast<std::ptrdiff_t>(rates.size());
  EXPECT_EQ(std::vector<std::string>(tail, columns.end()), rates);
  for (auto c = columns.begin(); c != tail; ++c)
    EXPECT_EQ(std::find(rates.begin(), rates.end(), *c), rates.end()) << *c;
}

TEST(PointRates, PlanarColumnsAreTheDerivativesOfThePositions) {
  const Model model = read_model(MECHGEN_SOURCE_DIR "/models/chebyshev.yaml");
  std::vector<std::string> points;
  for (const auto& [point, body] : model.named_points()) points.push_back(point);
  SweepOptions o = default_sweep(model);
  o.samples = 2001;
  for (const std::string solver : {"numeric", "generated"}) {
    o.solver = solver;
    const SweepResult r = run_sweep(model, o);
    const Table t{r.columns, r.rows, (o.t1 - o.t0) / (o.samples - 1)};
    expect_point_rates(t, points, {"x", "y"}, solver);
    expect_appended(r.columns, points, {"vx", "vy", "ax", "ay"});
    // Before them, the original columns: the last joint's force last.
    const std::string& last = r.columns[r.columns.size() - 4 * points.size() - 1];
    EXPECT_EQ(last.substr(0, last.rfind('.')), model.joints.back().name);
  }
}

void spatial_case(const std::string& name) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/" + name + ".yaml");
  std::vector<std::string> points;
  for (const auto& [point, body] : model.named_points()) points.push_back(point);
  spatial::SpatialSweepOptions o = spatial::default_spatial_sweep(model);
  o.samples = 1001;
  const double dt = (o.t1 - o.t0) / (o.samples - 1);
  const spatial::SpatialSweepResult numeric = spatial::run_spatial_sweep(model, o);
  const spatial::SpatialSweepResult generated =
      spatial::run_spatial_kernel_sweep(model, o, ondemand::kernel_for(model));
  for (const auto* r : {&numeric, &generated}) {
    const Table t{r->columns, r->rows, dt};
    expect_point_rates(t, points, {"x", "y", "z"}, name + (r == &numeric ? " numeric" : " kernel"));
    expect_appended(r->columns, points, {"vx", "vy", "vz", "ax", "ay", "az"});
  }
  // And the two solvers agree on them sample by sample.
  for (size_t i = 0; i < numeric.rows.size(); i += 50)
    for (const std::string& p : points)
      for (const char* f : {".vx", ".vy", ".vz", ".ax", ".ay", ".az"}) {
        const Table t{numeric.columns, numeric.rows, dt};
        const size_t c = t.index(p + f);
        EXPECT_NEAR(generated.rows[i][c], numeric.rows[i][c],
                    1e-9 * std::max(1.0, std::abs(numeric.rows[i][c])))
            << name << " " << p << f << " sample " << i;
      }
}

TEST(PointRates, SpatialSerialColumnsAreTheDerivativesOfThePositions) {
  spatial_case("leg6");
}

TEST(PointRates, SpatialClosedLoopColumnsAreTheDerivativesOfThePositions) {
  spatial_case("rsur");
}

}  // namespace
}  // namespace mechgen
