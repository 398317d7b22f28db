#include "report/view_columns.hpp"

#include <stdexcept>

namespace mechgen::report {

namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

int view_column(const CsvTable& table, const std::string& name) {
  const int c = table.column(name);
  if (c < 0)
    throw std::invalid_argument((table.path.empty() ? "the sweep" : table.path) +
                                " has no column '" + name + "'");
  return c;
}

void add_table_columns(const CsvTable& table, bool spatial, const std::vector<std::string>& trace,
                       const std::vector<std::string>& plot, ViewScene& scene, int max_series) {
  const int t = view_column(table, "t");
  scene.times = table.values(t);
  for (const std::string& name : trace) {
    const int x = table.column(name + ".x"), y = table.column(name + ".y");
    const int z = spatial ? table.column(name + ".z") : -1;
    if (x < 0 || y < 0 || (spatial && z < 0))
      throw std::invalid_argument("--trace: no point '" + name + "' in " +
                                  (table.path.empty() ? "the sweep" : table.path) +
                                  " (it needs columns " + name + ".x, " + name + ".y" +
                                  (spatial ? ", " + name + ".z" : "") + ")");
    std::vector<Vec3> path;
    for (const std::vector<double>& row : table.rows)
      path.push_back({row[static_cast<size_t>(x)], row[static_cast<size_t>(y)],
                      z < 0 ? 0.0 : row[static_cast<size_t>(z)]});
    scene.traces.emplace_back(name, std::move(path));
  }
  std::vector<std::string> columns = plot;
  if (columns.empty()) {
    for (const char* tail : {".effort", ".torque"}) {
      for (const std::string& h : table.header)
        if (ends_with(h, tail)) columns.push_back(h);
      if (!columns.empty()) break;
    }
    if (static_cast<int>(columns.size()) > max_series) {
      scene.plot_note = "first " + std::to_string(max_series) + " of " +
                        std::to_string(columns.size()) + " columns; --plot to choose";
      columns.resize(static_cast<size_t>(max_series));
    }
  }
  for (const std::string& name : columns)
    scene.plot.push_back({name, table.values(view_column(table, name))});
}

}  // namespace mechgen::report
