// The parts of a view that come from a sweep table alone, planar or spatial: the times, the traced
// points' paths (columns P.x, P.y and, spatial, P.z) and the plotted columns.
#pragma once

#include <string>
#include <vector>

#include "report/csv_table.hpp"
#include "report/view_scene.hpp"

namespace mechgen::report {

// Fills scene.times, scene.traces and scene.plot from `table`. `trace` names points (or any
// prefix with .x/.y[/.z] columns, such as a gait's com); a missing one throws std::invalid_argument
// naming the columns that would do. `plot` names columns; empty: every driver effort (.effort),
// else every joint torque (.torque), at most `max_series` of them (scene.plot_note says so).
void add_table_columns(const CsvTable& table, bool spatial, const std::vector<std::string>& trace,
                       const std::vector<std::string>& plot, ViewScene& scene, int max_series = 8);

// Column `name` of `table`, or std::invalid_argument naming the table and the column.
int view_column(const CsvTable& table, const std::string& name);

}  // namespace mechgen::report
