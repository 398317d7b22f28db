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
  std::string kind;            // "angle", "length", or "" when unknown
  bool kind_inferred = false;  // kind read from the columns (no model given): see summarize()
  double peak_effort = 0;      // the effort of largest magnitude (signed)
  double peak_time = 0;        // when it occurs
  double rms_effort = 0;       // time_rms of the effort
  bool has_power = false;      // the table has <d>.qd
  double mean_power = 0;       // time average of effort * qd (W): work over the run / duration
  double mean_abs_power = 0;   // time average of |effort * qd| (W): what a motor that cannot
                               // recover energy supplies on average
  double peak_power = 0;       // the power of largest magnitude (signed)
  double work = 0;             // integral of effort * qd dt over the run (J)
};

struct BodySummary {
  std::string name;
  bool point = false;  // a named point (no <name>.th column), not a body's centre of mass
  double x_start = 0, x_end = 0;
  double travel = 0;                        // x_end - x_start
  double y_min = 0, y_max = 0, y_mean = 0;  // y_mean: time average
  double height_variation = 0;              // y_max - y_min
  // height_variation / |y_mean| * 100 (%); NaN when |y_mean| is not above height_variation
  // (a path around y = 0: the ratio would mean nothing)
  double relative_variation = 0;
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
  // The body (or named point) whose travel is reported. Empty: "l13" when the table has it, else
  // the first body, and only when the run travels (its net x travel exceeds its height
  // variation, as a walking hip's does): a mechanism turning on the spot gets no gait figures.
  std::string body;
  // When given, driver kinds (for units) come from it.
  const Model* model = nullptr;
};

// Drivers are the columns "<d>.effort"; bodies the names with ".x" and ".y" and ".th" columns;
// joints the names with ".fx" and ".fy". Without a model a driver's kind is read from the
// columns: an angle driver's q equals the difference of two body angles (or one body's angle,
// against the ground) modulo 2 pi at every sample; a length driver's does not. Throws
// report::CsvError for an empty table or a body that is not in it.
SweepSummary summarize(const report::CsvTable& table, const SummaryOptions& options = {});

// The short aligned table `mechgen summary` prints, with units.
std::string format_summary(const SweepSummary& summary);

}  // namespace mechgen
