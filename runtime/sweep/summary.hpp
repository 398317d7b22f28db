// What `mechgen summary` reports about a sweep table: per driver its peak and RMS effort and its
// mean power, the travel and height variation of one body, and the largest joint force.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "model/model.hpp"
#include "report/csv_table.hpp"

namespace mechgen {

// Time average of v(t) over [t.front(), t.back()] by the trapezoidal rule; the plain mean of the
// samples when t spans no time (a single sample, or equal times).
double time_average(const std::vector<double>& t, const std::vector<double>& v);
// sqrt(time_average(t, v^2)).
double time_rms(const std::vector<double>& t, const std::vector<double>& v);

struct DriverSummary {
  std::string name;
  std::string kind;           // "angle", "length", or "" when unknown (no model given)
  double peak_effort = 0;     // the effort of largest magnitude (signed)
  double peak_time = 0;       // when it occurs
  double rms_effort = 0;      // time_rms of the effort
  bool has_power = false;     // the table has <d>.qd
  double mean_power = 0;      // time average of effort * qd (W): work over the run / duration
  double mean_abs_power = 0;  // time average of |effort * qd| (W): what a motor that cannot
                              // recover energy supplies on average
  double peak_power = 0;      // the power of largest magnitude (signed)
  double work = 0;            // integral of effort * qd dt over the run (J)
};

struct BodySummary {
  std::string name;
  double x_start = 0, x_end = 0;
  double travel = 0;                        // x_end - x_start
  double y_min = 0, y_max = 0, y_mean = 0;  // y_mean: time average
  double height_variation = 0;              // y_max - y_min
  double relative_variation = 0;  // height_variation / |y_mean| * 100 (%); NaN when y_mean is 0
};

struct JointPeak {
  std::string name;
  double force = 0;  // largest |(fx, fy)| over the run
  double time = 0;
};

struct SweepSummary {
  std::string path;
  size_t samples = 0;
  double t0 = 0, t1 = 0;  // NaN when the table has no column t
  std::vector<DriverSummary> drivers;
  std::optional<BodySummary> body;
  std::optional<JointPeak> joint;
};

struct SummaryOptions {
  // The body whose travel is reported; empty: "l13" when the table has it, else the first body.
  std::string body;
  // When given, driver kinds (for units) come from it.
  const Model* model = nullptr;
};

// Drivers are the columns "<d>.effort"; bodies the names with ".x" and ".y" and ".th" columns;
// joints the names with ".fx" and ".fy". Throws report::CsvError for an empty table or a body
// that is not in it.
SweepSummary summarize(const report::CsvTable& table, const SummaryOptions& options = {});

// The short aligned table `mechgen summary` prints, with units.
std::string format_summary(const SweepSummary& summary);

}  // namespace mechgen
