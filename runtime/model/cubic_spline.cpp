// The not-a-knot cubic spline and the CSV tables of table drivers (cubic_spline.hpp).
#include "model/cubic_spline.hpp"

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace mechgen {

CubicSpline::CubicSpline(std::vector<double> t, std::vector<double> y, std::string what)
    : t_(std::move(t)), y_(std::move(y)), what_(std::move(what)) {
  const size_t n = t_.size();
  if (n != y_.size()) throw std::invalid_argument("as many times as values are needed");
  if (n < 4) throw std::invalid_argument("a cubic spline needs at least 4 samples");
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(t_[i]) || !std::isfinite(y_[i]))
      throw std::invalid_argument("a sample is not a finite number");
    if (i > 0 && !(t_[i] > t_[i - 1]))
      throw std::invalid_argument("the times are not strictly increasing");
  }
  // Unknowns: the second derivatives M_i. Interior knots: continuity of the first derivative;
  // the first and last rows: not-a-knot, M's slope the same on the first two (last two) intervals.
  std::vector<double> h(n - 1);
  for (size_t i = 0; i + 1 < n; ++i) h[i] = t_[i + 1] - t_[i];
  using Triplet = Eigen::Triplet<double>;
  std::vector<Triplet> a;
  Eigen::VectorXd r = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
  auto at = [&](size_t row, size_t col, double v) {
    a.emplace_back(static_cast<int>(row), static_cast<int>(col), v);
  };
  at(0, 0, -h[1]), at(0, 1, h[0] + h[1]), at(0, 2, -h[0]);
  for (size_t i = 1; i + 1 < n; ++i) {
    at(i, i - 1, h[i - 1]), at(i, i, 2 * (h[i - 1] + h[i])), at(i, i + 1, h[i]);
    r[static_cast<Eigen::Index>(i)] =
        6 * ((y_[i + 1] - y_[i]) / h[i] - (y_[i] - y_[i - 1]) / h[i - 1]);
  }
  at(n - 1, n - 3, -h[n - 2]), at(n - 1, n - 2, h[n - 3] + h[n - 2]), at(n - 1, n - 1, -h[n - 3]);
  Eigen::SparseMatrix<double> A(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  A.setFromTriplets(a.begin(), a.end());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
  lu.compute(A);
  if (lu.info() != Eigen::Success) throw std::invalid_argument("the spline's system is singular");
  const Eigen::VectorXd m = lu.solve(r);
  m_.assign(m.data(), m.data() + m.size());
}

double CubicSpline::operator()(double t, int derivative) const {
  const double span = t_.back() - t_.front(), slack = 1e-12 * span;
  if (!(t >= t_.front() - slack && t <= t_.back() + slack)) {
    std::ostringstream m;
    m.precision(17);
    m << what_ << ": t = " << t << " s is outside the table's time range [" << t_.front() << ", "
      << t_.back() << "] s (a table is not extrapolated)";
    throw std::domain_error(m.str());
  }
  t = std::clamp(t, t_.front(), t_.back());
  const auto upper = std::upper_bound(t_.begin(), t_.end(), t);
  const size_t i = std::min(static_cast<size_t>(std::max<std::ptrdiff_t>(upper - t_.begin(), 1)),
                            t_.size() - 1) -
                   1;
  const double h = t_[i + 1] - t_[i], a = t_[i + 1] - t, b = t - t_[i];
  const double m0 = m_[i], m1 = m_[i + 1];
  const double c0 = y_[i] / h - m0 * h / 6, c1 = y_[i + 1] / h - m1 * h / 6;
  switch (derivative) {
    case 0:
      return (m0 * a * a * a + m1 * b * b * b) / (6 * h) + c0 * a + c1 * b;
    case 1:
      return (m1 * b * b - m0 * a * a) / (2 * h) + c1 - c0;
    default:
      return (m0 * a + m1 * b) / h;
  }
}

namespace {

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) {
    const size_t b = field.find_first_not_of(" \t\r\"");
    const size_t e = field.find_last_not_of(" \t\r\"");
    out.push_back(b == std::string::npos ? "" : field.substr(b, e - b + 1));
  }
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

}  // namespace

DriverTable read_driver_table(const std::string& file, const std::string& column,
                              const std::string& time_column, const SourceLoc& at) {
  DriverTable table{file, column, time_column, "", nullptr};
  const std::string what = "table '" + file + "'";
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw ModelError(at, what +
                             ": cannot open the file (a relative path is read from the "
                             "model file's folder)");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  table.content = bytes.str();
  std::istringstream lines(table.content);
  std::string line;
  int number = 0;
  std::vector<std::string> header;
  std::vector<double> t, y;
  size_t ti = 0, yi = 0;
  auto where = [&] { return what + " line " + std::to_string(number); };
  while (std::getline(lines, line)) {
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    const std::vector<std::string> fields = split_csv(line);
    if (header.empty()) {
      header = fields;
      auto find = [&](const std::string& name, const char* role) {
        const auto it = std::find(header.begin(), header.end(), name);
        if (it == header.end())
          throw ModelError(
              at, where() + ": no column '" + name + "' (" + role + ") in the header line");
        return static_cast<size_t>(it - header.begin());
      };
      ti = find(time_column, "the time, s");
      yi = find(column, "the driver's value");
      continue;
    }
    if (fields.size() != header.size())
      throw ModelError(at, where() + ": " + std::to_string(fields.size()) +
                               " fields, the header has " + std::to_string(header.size()));
    auto value = [&](size_t k) {
      const std::string& s = fields[k];
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(s.c_str(), &end);
      if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v) || errno == ERANGE)
        throw ModelError(
            at, where() + ": column '" + header[k] + "' holds '" + s + "', not a finite number");
      return v;
    };
    t.push_back(value(ti));
    y.push_back(value(yi));
    if (t.size() > 1 && !(t.back() > t[t.size() - 2]))
      throw ModelError(at, where() + ": the times are not strictly increasing (" + fields[ti] +
                               " s after the previous row's)");
  }
  if (header.empty()) throw ModelError(at, what + ": the file is empty (expected a header line)");
  if (t.size() < 4)
    throw ModelError(at, what + ": " + std::to_string(t.size()) +
                             " rows; a cubic spline needs at least 4 samples");
  table.spline = std::make_shared<const CubicSpline>(
      std::move(t), std::move(y), "table '" + file + "' column '" + column + "'");
  return table;
}

}  // namespace mechgen
