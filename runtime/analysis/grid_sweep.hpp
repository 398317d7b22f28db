// A grid of sweeps: one run of the model's step per value of one parameter (the seed's Figs. 10
// and 11: motor torque for several crank speeds, for several hip loads), gathered into one long
// table and one multi-series plot against normalised time.
#pragma once

#include <string>
#include <vector>

#include "model/model.hpp"
#include "report/svg_plot.hpp"
#include "sweep/sweep.hpp"

namespace mechgen {

struct GridOptions {
  std::string parameter;             // the model parameter that varies
  std::vector<double> values;        // one sweep per value, in this order
  std::vector<double> parameters;    // the other parameters (Model::parameters order); empty:
                                     // the defaults
  std::string solver = "generated";  // as SweepOptions::solver
  int samples = 0;                   // per run; 0: the model's step samples
  int threads = 0;                   // runs in parallel; 0: one per hardware thread
  Progress* progress = nullptr;      // told of every sample of every run; optional
};

struct GridRun {
  double value = 0;
  SweepOptions options;  // what was run: the model's step evaluated with this value
  SweepResult result;
};

struct GridResult {
  std::string parameter;
  std::string unit;  // the parameter's unit, may be empty
  std::vector<GridRun> runs;
};

// Each run is exactly run_sweep(model, default_sweep(model, p)) with p the parameters and the
// parameter set to the value, so a run of a grid equals a sweep with --set NAME=VALUE. The step
// (t0, t1) is evaluated per value: at w8 = 1 rad/s a step lasts pi s, at 5 rad/s pi/5 s.
// Throws ModelError for an unknown parameter, an empty grid or a run that fails (naming the
// value).
GridResult run_grid(const Model& model, const GridOptions& options);

// "NAME=V1,V2,..." -> the name and the values. Throws std::invalid_argument with a one-line
// message for a malformed text (no '=', an empty or non-numeric value).
std::pair<std::string, std::vector<double>> parse_grid_spec(const std::string& text);

// The long table: column 1 the grid parameter's value, column 2 "t_norm" = (t - t0) / (t1 - t0)
// (the seed's t/T, T the step's duration), then the sweep's columns; runs one after the other.
std::vector<std::string> grid_columns(const GridResult& grid);
// `first_line` (a shard's part_line, sweep/shard.hpp) goes before the header.
void write_grid_csv(const std::string& path, const GridResult& grid,
                    const std::string& first_line = "");

struct GridPlotOptions {
  std::string column;  // the sweep column plotted, e.g. "theta8.effort"
  std::string title, y_label;
  // The x axis: "t_norm" (t/T, default; steps of different duration compared phase by phase) or
  // "t" (seconds).
  std::string x = "t_norm";
};
// One series per value, labelled "NAME = VALUE UNIT". Throws std::invalid_argument for an unknown
// column.
report::PlotSpec grid_plot(const GridResult& grid, const GridPlotOptions& options);

}  // namespace mechgen
