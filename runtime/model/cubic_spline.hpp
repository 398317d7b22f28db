// A driver's motion from a recorded trajectory (`value: {table: FILE.csv, column: NAME}`,
// docs/model_format.md "Table drivers"): the table read from its CSV file, and the cubic spline
// through its samples, evaluated exactly with its first and second derivatives.
//
// End conditions: not-a-knot (the third derivative is continuous at the second and the
// second-to-last knots). Unlike the natural spline (q'' = 0 at both ends, which bends a logged
// motion that starts or ends accelerating), it assumes nothing of the motion at the ends and
// reproduces any cubic polynomial exactly; it needs at least 4 samples. Outside the table's time
// range the spline is not extrapolated: evaluating there is an error naming the range.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/model.hpp"

namespace mechgen {

class CubicSpline {
 public:
  // Knots t (strictly increasing, at least 4) and values y (finite); throws std::invalid_argument
  // otherwise. `what` names the curve in the out-of-range error.
  CubicSpline(std::vector<double> t, std::vector<double> y, std::string what);

  // The value (derivative 0), or its first or second derivative at t; throws std::domain_error
  // outside [t_front, t_back] (within a relative 1e-12 of the span at either end: the end's
  // value).
  double operator()(double t, int derivative = 0) const;
  double front() const { return t_.front(); }
  double back() const { return t_.back(); }
  const std::vector<double>& knots() const { return t_; }
  const std::vector<double>& values() const { return y_; }

 private:
  std::vector<double> t_, y_, m_;  // m_: the second derivative at each knot
  std::string what_;
};

// A table driver's source, as the reader resolved it.
struct DriverTable {
  std::string file;         // the CSV file's path (relative ones to the model file's folder)
  std::string column;       // the driven value's column (the driver's SI unit: rad or m)
  std::string time_column;  // the time's column (s), `t` by default
  std::string content;      // the file's bytes (part of the model's fingerprint)
  std::shared_ptr<const CubicSpline> spline;
};

// Reads `column` and `time_column` of a CSV file (a header line of names, then one line of
// numbers per sample; blank lines and lines starting with '#' skipped) into a DriverTable. Every
// error (a missing file or column, fewer than 4 rows, times not strictly increasing, a value that
// is not a finite number) is a ModelError at `at` naming the file and, where there is one, its
// line.
DriverTable read_driver_table(const std::string& file, const std::string& column,
                              const std::string& time_column, const SourceLoc& at);

}  // namespace mechgen
