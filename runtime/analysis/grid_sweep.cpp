#include "analysis/grid_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "report/atomic_output.hpp"
#include "sweep/parallel.hpp"

namespace mechgen {

namespace {

std::string short_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

std::string exact_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

size_t parameter_index(const Model& model, const std::string& name) {
  for (size_t i = 0; i < model.parameters.size(); ++i)
    if (model.parameters[i].name == name) return i;
  std::string known;
  if (const int d = model.derived_index(name); d >= 0) {
    for (const std::string& u : model.derived[static_cast<size_t>(d)].uses)
      known += (known.empty() ? "" : ", ") + u;
    throw ModelError({model.file, 0, 0}, "grid: parameter '" + name + "' is derived (" + name +
                                             " = " +
                                             model.derived[static_cast<size_t>(d)].value.text +
                                             "); vary what it depends on: " + known);
  }
  for (const Parameter& p : model.parameters) known += (known.empty() ? "" : ", ") + p.name;
  throw ModelError({model.file, 0, 0}, "grid: no parameter '" + name + "' in model '" + model.name +
                                           "' (parameters: " + known + ")");
}

// The same error with "grid NAME = VALUE: " in front of its message, at the same location.
ModelError with_value(const ModelError& error, const std::string& parameter, double value) {
  const std::string what = error.what();
  const auto split = what.find(": error: ");
  return ModelError(error.where(), "grid " + parameter + " = " + short_number(value) + ": " +
                                       (split == what.npos ? what : what.substr(split + 9)));
}

}  // namespace

GridResult run_grid(const Model& model, const GridOptions& options) {
  const size_t index = parameter_index(model, options.parameter);
  if (options.values.empty())
    throw ModelError({model.file, 0, 0}, "grid: no values for '" + options.parameter + "'");
  std::vector<double> base =
      options.parameters.empty() ? model.default_parameters() : options.parameters;

  GridResult grid;
  grid.parameter = options.parameter;
  grid.unit = model.parameters[index].unit;
  grid.runs.resize(options.values.size());
  for (size_t k = 0; k < options.values.size(); ++k) {
    std::vector<double> parameters = base;
    parameters[index] = options.values[k];
    GridRun& run = grid.runs[k];
    run.value = options.values[k];
    try {
      run.options = default_sweep(model, parameters);
    } catch (const ModelError& error) {
      throw with_value(error, options.parameter, run.value);
    }
    run.options.solver = options.solver;
    if (options.samples > 0) run.options.samples = options.samples;
    run.options.threads = 1;  // the runs are the parallel unit
    run.options.progress = options.progress;
  }

  // Runs are independent (each its own solver or a pure kernel call): a pool of threads takes
  // them in turn; the first failure, in grid order, is rethrown with the value it belongs to.
  // The numeric solver copies and substitutes the model's GiNaC expressions, whose reference
  // counts are not atomic: its runs share the Model, so they go one at a time.
  if (options.threads > thread_limit())
    throw ModelError({model.file, 0, 0},
                     "grid: " + std::to_string(options.threads) + " threads asked for, at most " +
                         std::to_string(thread_limit()) + " (4 x the hardware threads)");
  const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
  const size_t threads =
      options.solver != "generated"
          ? 1
          : std::min<size_t>(grid.runs.size(),
                             options.threads > 0 ? static_cast<size_t>(options.threads) : hardware);
  std::vector<std::exception_ptr> errors(grid.runs.size());
  std::mutex next_lock;
  size_t next = 0;
  auto worker = [&] {
    for (;;) {
      size_t k = 0;
      {
        const std::lock_guard<std::mutex> hold(next_lock);
        if (next >= grid.runs.size()) return;
        k = next++;
      }
      try {
        grid.runs[k].result = run_sweep(model, grid.runs[k].options);
      } catch (...) {
        errors[k] = std::current_exception();
      }
    }
  };
  run_parallel(threads, [&](size_t) { worker(); });  // a thread that cannot start: one error

  for (size_t k = 0; k < errors.size(); ++k) {
    if (!errors[k]) continue;
    try {
      std::rethrow_exception(errors[k]);
    } catch (const ModelError& error) {
      throw with_value(error, options.parameter, options.values[k]);
    } catch (const std::exception& error) {
      throw with_value(ModelError({model.file, 0, 0}, error.what()), options.parameter,
                       options.values[k]);
    }
  }
  return grid;
}

std::pair<std::string, std::vector<double>> parse_grid_spec(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw std::invalid_argument("expected NAME=V1,V2,..., got '" + text + "'");
  std::pair<std::string, std::vector<double>> spec{text.substr(0, eq), {}};
  std::string rest = text.substr(eq + 1);
  size_t start = 0;
  for (;;) {
    const size_t comma = rest.find(',', start);
    const std::string word =
        rest.substr(start, comma == std::string::npos ? rest.npos : comma - start);
    size_t used = 0;
    double value = 0;
    try {
      value = std::stod(word, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (word.empty() || used != word.size() || !std::isfinite(value))
      throw std::invalid_argument("'" + word + "' in '" + text + "' is not a number");
    spec.second.push_back(value);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return spec;
}

std::vector<std::string> grid_columns(const GridResult& grid) {
  std::vector<std::string> columns{grid.parameter, "t_norm"};
  if (!grid.runs.empty())
    columns.insert(columns.end(), grid.runs.front().result.columns.begin(),
                   grid.runs.front().result.columns.end());
  return columns;
}

namespace {

// (t - t0) / (t1 - t0); 0 for a run that spans no time.
double normalised_time(const GridRun& run, double t) {
  const double span = run.options.t1 - run.options.t0;
  return span != 0 ? (t - run.options.t0) / span : 0.0;
}

int column_of(const std::vector<std::string>& columns, const std::string& name) {
  const auto it = std::find(columns.begin(), columns.end(), name);
  return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
}

}  // namespace

void write_grid_csv(const std::string& path, const GridResult& grid,
                    const std::string& first_line) {
  const std::vector<std::string> columns = grid_columns(grid);
  std::string text = first_line;
  for (size_t c = 0; c < columns.size(); ++c) text += (c ? "," : "") + columns[c];
  text += "\n";
  for (const GridRun& run : grid.runs) {
    const int t_column = column_of(run.result.columns, "t");
    for (const std::vector<double>& row : run.result.rows) {
      const double t = t_column >= 0 ? row[static_cast<size_t>(t_column)] : 0.0;
      text += exact_number(run.value) + "," + exact_number(normalised_time(run, t));
      for (double v : row) text += "," + exact_number(v);
      text += "\n";
    }
  }
  report::write_file_atomically(path, text);
}

report::PlotSpec grid_plot(const GridResult& grid, const GridPlotOptions& options) {
  report::PlotSpec spec;
  spec.title = options.title;
  spec.y_label = options.y_label.empty() ? options.column : options.y_label;
  spec.x_label = options.x == "t" ? "time t [s]" : "normalised time t/T (T: the step's duration)";
  for (const GridRun& run : grid.runs) {
    const int t_column = column_of(run.result.columns, "t");
    const int y_column = column_of(run.result.columns, options.column);
    if (y_column < 0 || t_column < 0)
      throw std::invalid_argument("grid plot: no column '" +
                                  (y_column < 0 ? options.column : std::string("t")) +
                                  "' in the sweep");
    report::Series series;
    series.label = grid.parameter + " = " + short_number(run.value) +
                   (grid.unit.empty() ? "" : " " + grid.unit);
    for (const std::vector<double>& row : run.result.rows) {
      const double t = row[static_cast<size_t>(t_column)];
      series.x.push_back(options.x == "t" ? t : normalised_time(run, t));
      series.y.push_back(row[static_cast<size_t>(y_column)]);
    }
    spec.series.push_back(std::move(series));
  }
  return spec;
}

}  // namespace mechgen
