// A plot of CSV columns against one column: what `mechgen plot` draws.
#pragma once

#include <string>
#include <vector>

#include "report/csv_table.hpp"
#include "report/svg_plot.hpp"

namespace mechgen::report {

// "[unit]" read off a sweep column's name (DESIGN.md's CSV contract): "t" -> "[s]",
// "<b>.vx" -> "[m/s]", "<j>.fx" -> "[N]", ... Empty when the name alone does not tell: a driver's
// q, qd, qdd and effort are an angle (rad, N m) or a length (m, N) depending on its kind.
std::string column_unit(const std::string& column);

struct ColumnPlotOptions {
  std::string x;               // column for the horizontal axis
  std::vector<std::string> y;  // one series per column
  // Empty: derived. Axis labels name the columns and their units when known ("time t [s]").
  std::string title, x_label, y_label;
  bool equal_scale = false;                  // one scale on both axes (x-y paths)
  std::vector<PlotSpec::Limit> limits = {};  // dashed lines at these y values (the plot's units)
};

// Stresses (every y column in [Pa], as mechgen loads --over-time writes them) are plotted in MPa,
// as `loads` prints them; `limits` are then in MPa too. Throws CsvError naming a missing column
// and the columns that exist.
PlotSpec column_plot(const CsvTable& table, const ColumnPlotOptions& options);

}  // namespace mechgen::report
