#include "sweep/summary.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

namespace mechgen {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

bool ends_with(const std::string& text, const std::string& suffix) {
  return text.size() > suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Index of the sample of largest magnitude (the first of equals); NaN samples are skipped.
size_t peak_index(const std::vector<double>& v) {
  size_t best = 0;
  double best_abs = -1;
  for (size_t i = 0; i < v.size(); ++i)
    if (std::abs(v[i]) > best_abs) best_abs = std::abs(v[i]), best = i;
  return best;
}

// The time axis: column t, or the sample index when there is none.
std::vector<double> time_axis(const report::CsvTable& table) {
  const int t = table.column("t");
  if (t >= 0) return table.values(t);
  std::vector<double> index(table.rows.size());
  for (size_t i = 0; i < index.size(); ++i) index[i] = static_cast<double>(i);
  return index;
}

std::string driver_kind(const Model* model, const std::string& driver) {
  if (!model) return "";
  for (const Driver& d : model->drivers)
    if (d.name == driver) return to_string(d.kind);
  return "";
}

// Without a model: "angle" when q is, at every sample, th_b - th_a (modulo 2 pi) for two of the
// table's bodies or the ground (angle 0); "length" when it is not; "" when the table cannot tell
// (no body angles, fewer than two samples, or no q column).
std::string driver_kind_from_columns(const report::CsvTable& table, const std::string& driver) {
  const int q = table.column(driver + ".q");
  if (q < 0 || table.rows.size() < 2) return "";
  std::vector<std::vector<double>> angles{std::vector<double>(table.rows.size(), 0.0)};  // ground
  for (const std::string& column : table.header)
    if (ends_with(column, ".th")) angles.push_back(table.values(table.column(column)));
  if (angles.size() < 2) return "";
  const std::vector<double> qs = table.values(q);
  for (size_t a = 0; a < angles.size(); ++a)
    for (size_t b = 0; b < angles.size(); ++b) {
      if (a == b) continue;
      bool equal = true;
      for (size_t i = 0; i < qs.size() && equal; ++i)
        equal = std::abs(std::remainder(qs[i] - (angles[b][i] - angles[a][i]), 2 * M_PI)) < 1e-7;
      if (equal) return "angle";
    }
  return "length";
}

std::string default_body(const report::CsvTable& table) {
  if (table.column("l13.x") >= 0 && table.column("l13.y") >= 0) return "l13";
  for (const std::string& column : table.header) {
    if (!ends_with(column, ".th")) continue;
    const std::string name = column.substr(0, column.size() - 3);
    if (table.column(name + ".x") >= 0 && table.column(name + ".y") >= 0) return name;
  }
  return "";
}

}  // namespace

double time_average(const std::vector<double>& t, const std::vector<double>& v) {
  if (v.empty()) return nan;
  const double span = t.back() - t.front();
  if (t.size() != v.size() || v.size() < 2 || !(span != 0)) {
    double sum = 0;
    for (double x : v) sum += x;
    return sum / static_cast<double>(v.size());
  }
  double integral = 0;
  for (size_t i = 1; i < v.size(); ++i) integral += 0.5 * (v[i] + v[i - 1]) * (t[i] - t[i - 1]);
  return integral / span;
}

double time_rms(const std::vector<double>& t, const std::vector<double>& v) {
  std::vector<double> squares(v.size());
  for (size_t i = 0; i < v.size(); ++i) squares[i] = v[i] * v[i];
  return std::sqrt(time_average(t, squares));
}

SweepSummary summarize(const report::CsvTable& table, const SummaryOptions& options) {
  if (table.rows.empty()) throw report::CsvError(table.path + ":0: no samples to summarise");
  SweepSummary s;
  s.path = table.path;
  s.samples = table.rows.size();
  const std::vector<double> t = time_axis(table);
  const bool has_t = table.column("t") >= 0;
  s.t0 = has_t ? t.front() : nan;
  s.t1 = has_t ? t.back() : nan;

  for (const std::string& column : table.header) {
    if (!ends_with(column, ".effort")) continue;
    DriverSummary d;
    d.name = column.substr(0, column.size() - 7);
    d.kind = driver_kind(options.model, d.name);
    if (!options.model) {
      d.kind = driver_kind_from_columns(table, d.name);
      d.kind_inferred = !d.kind.empty();
    }
    const std::vector<double> effort = table.values(table.column(column));
    const size_t peak = peak_index(effort);
    d.peak_effort = effort[peak];
    d.peak_time = t[peak];
    d.rms_effort = time_rms(t, effort);
    const int qd = table.column(d.name + ".qd");
    if (qd >= 0) {
      const std::vector<double> rate = table.values(qd);
      std::vector<double> power(effort.size());
      for (size_t i = 0; i < power.size(); ++i) power[i] = effort[i] * rate[i];
      d.has_power = true;
      d.mean_power = time_average(t, power);
      std::vector<double> magnitude(power.size());
      for (size_t i = 0; i < power.size(); ++i) magnitude[i] = std::abs(power[i]);
      d.mean_abs_power = time_average(t, magnitude);
      d.peak_power = power[peak_index(power)];
      d.work = has_t ? d.mean_power * (t.back() - t.front()) : nan;
    }
    s.drivers.push_back(d);
  }

  const std::string body = options.body.empty() ? default_body(table) : options.body;
  if (!body.empty()) {
    const int x = table.column(body + ".x"), y = table.column(body + ".y");
    if (x < 0 || y < 0)
      throw report::CsvError(table.path + ":1: no columns '" + body + ".x' and '" + body +
                             ".y' (is '" + body + "' a moving body of this model?)");
    BodySummary b;
    b.name = body;
    b.point = table.column(body + ".th") < 0;
    const std::vector<double> xs = table.values(x), ys = table.values(y);
    b.x_start = xs.front();
    b.x_end = xs.back();
    b.travel = b.x_end - b.x_start;
    b.y_min = b.y_max = ys.front();
    for (double v : ys) b.y_min = std::min(b.y_min, v), b.y_max = std::max(b.y_max, v);
    b.y_mean = time_average(t, ys);
    b.height_variation = b.y_max - b.y_min;
    b.relative_variation = std::abs(b.y_mean) > b.height_variation
                               ? b.height_variation / std::abs(b.y_mean) * 100
                               : nan;
    if (!options.body.empty() || std::abs(b.travel) > b.height_variation) s.body = b;
  }

  for (const std::string& column : table.header) {
    if (!ends_with(column, ".fx")) continue;
    const std::string name = column.substr(0, column.size() - 3);
    const int fy = table.column(name + ".fy");
    if (fy < 0) continue;
    const std::vector<double> fxs = table.values(table.column(column)), fys = table.values(fy);
    for (size_t i = 0; i < fxs.size(); ++i) {
      const double f = std::hypot(fxs[i], fys[i]);
      if (!s.joint || f > s.joint->force) s.joint = JointPeak{name, f, t[i]};
    }
  }
  return s;
}

std::string format_summary(const SweepSummary& s) {
  std::string out;
  char line[256];
  auto row = [&](const std::string& label, double value, const char* unit,
                 const std::string& note = "") {
    std::snprintf(line, sizeof line, "  %-26s %13.6g  %-5s %s", label.c_str(), value, unit,
                  note.c_str());
    std::string text = line;
    while (!text.empty() && text.back() == ' ') text.pop_back();
    out += text + "\n";
  };
  auto at = [](double t) {
    char text[64];
    std::snprintf(text, sizeof text, "at t = %.4g s", t);
    return std::string(text);
  };

  if (std::isnan(s.t0))
    std::snprintf(line, sizeof line, "%s: %zu samples (no column t: times are sample indices)\n",
                  s.path.c_str(), s.samples);
  else
    std::snprintf(line, sizeof line, "%s: %zu samples, t = %.6g .. %.6g s\n", s.path.c_str(),
                  s.samples, s.t0, s.t1);
  out += line;
  out += "(RMS and means are time averages, trapezoidal rule in t)\n";

  for (const DriverSummary& d : s.drivers) {
    const char* effort_unit = d.kind == "angle" ? "N m" : d.kind == "length" ? "N" : "N m|N";
    out += "driver " + d.name +
           (d.kind.empty()
                ? ""
                : " (" + d.kind + (d.kind_inferred ? ", read from the columns" : "") + ")") +
           "\n";
    row("peak effort", d.peak_effort, effort_unit, at(d.peak_time));
    row("RMS effort", d.rms_effort, effort_unit);
    if (d.has_power) {
      row("mean power", d.mean_power, "W", "(effort x qd)");
      row("mean |power|", d.mean_abs_power, "W");
      row("peak power", d.peak_power, "W");
      if (!std::isnan(d.work)) row("work over the run", d.work, "J");
    }
  }
  if (s.body) {
    const BodySummary& b = *s.body;
    char note[96];
    out += (b.point ? "point " + b.name : "body " + b.name + " (centre of mass)") + "\n";
    std::snprintf(note, sizeof note, "(x %.6g -> %.6g m)", b.x_start, b.x_end);
    row("travel x (end - start)", b.travel, "m", note);
    std::snprintf(note, sizeof note, "(y %.6g .. %.6g m)", b.y_min, b.y_max);
    row("height variation y", b.height_variation, "m", note);
    row("mean height y", b.y_mean, "m");
    if (!std::isnan(b.relative_variation))
      row("height variation / mean", b.relative_variation, "%");
  }
  if (s.joint) {
    out += "joints\n";
    row("peak force |(fx, fy)|", s.joint->force, "N",
        "joint " + s.joint->name + " " + at(s.joint->time));
  }
  return out;
}

}  // namespace mechgen
