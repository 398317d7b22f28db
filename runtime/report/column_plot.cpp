#include "report/column_plot.hpp"

#include <utility>

namespace mechgen::report {

std::string column_unit(const std::string& column) {
  if (column == "t") return "[s]";
  const auto dot = column.rfind('.');
  if (dot == std::string::npos) return "";
  const std::string field = column.substr(dot + 1);
  static const std::pair<const char*, const char*> kUnits[] = {
      {"x", "[m]"},     {"y", "[m]"},     {"th", "[rad]"},   {"vx", "[m/s]"},    {"vy", "[m/s]"},
      {"w", "[rad/s]"}, {"ax", "[m/s²]"}, {"ay", "[m/s²]"},  {"al", "[rad/s²]"}, {"fx", "[N]"},
      {"fy", "[N]"},    {"m", "[N m]"},   {"sigma", "[Pa]"}, {"tau", "[Pa]"},    {"N", "[N]"},
      {"V", "[N]"},     {"M", "[N m]"},
  };
  for (const auto& [name, unit] : kUnits) {
    if (field == name) return unit;
  }
  return "";
}

namespace {

std::string with_unit(const std::string& text, const std::string& unit) {
  return unit.empty() ? text : text + " " + unit;
}

}  // namespace

PlotSpec column_plot(const CsvTable& table, const ColumnPlotOptions& options) {
  PlotSpec spec;
  const int xc = table.require_column(options.x);
  const std::vector<double> x = table.values(xc);
  std::string names, common_unit;
  bool same_unit = true;
  for (std::size_t i = 0; i < options.y.size(); ++i) {
    const std::string& name = options.y[i];
    spec.series.push_back({name, x, table.values(table.require_column(name))});
    names += (i ? ", " : "") + name;
    const std::string unit = column_unit(name);
    if (i == 0) common_unit = unit;
    same_unit = same_unit && unit == common_unit;
  }
  spec.x_label = !options.x_label.empty() ? options.x_label
                 : options.x == "t"       ? "time t [s]"
                                          : with_unit(options.x, column_unit(options.x));
  // Stresses in MPa, as mechgen loads prints them.
  if (same_unit && common_unit == "[Pa]" && !spec.series.empty()) {
    for (Series& series : spec.series)
      for (double& y : series.y) y *= 1e-6;
    common_unit = "[MPa]";
  }
  spec.y_limits = options.limits;
  spec.y_label =
      !options.y_label.empty() ? options.y_label : with_unit(names, same_unit ? common_unit : "");
  spec.title = !options.title.empty() ? options.title : names + " over " + options.x;
  spec.equal_scale = options.equal_scale;
  // A walk (mechgen walk's `support` column) against time: each change of support foot marked.
  if (const int support = table.column("support"); support >= 0 && options.x == "t") {
    const std::vector<double> s = table.values(support);
    for (std::size_t i = 1; i < s.size(); ++i)
      if (s[i] != s[i - 1]) spec.x_marks.push_back(x[i]);
    spec.x_marks_label = "support change";
  }
  return spec;
}

}  // namespace mechgen::report
