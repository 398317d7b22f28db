// mechgen grid: one sweep of the model's step per value of a parameter -> one long CSV and a
// multi-series plot (the seed's Figs. 10 and 11).
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/grid_sweep.hpp"
#include "cli/command.hpp"
#include "cli/model_info.hpp"
#include "model/columns.hpp"
#include "report/atomic_output.hpp"
#include "report/column_plot.hpp"
#include "report/svg_plot.hpp"
#include "sweep/summary.hpp"

namespace mechgen::cli {

namespace {

const char* const kGridHelp =
    R"(usage: mechgen grid MODEL.yaml --grid NAME=V1,V2,... --out FILE.csv [--plot FILE.svg]
                    [--y COLUMN] [--x t_norm|t] [--title TEXT] [--ylabel TEXT]
                    [--set NAME=VALUE]... [--solver generated|numeric] [--samples N] [--threads N]
                    [--shard I/N]

One sweep of the model's step per value of parameter NAME, each exactly what
`mechgen sweep MODEL.yaml --set NAME=VALUE` computes (the step's t0 and t1 are evaluated with the
value: at w8 = 5 rad/s a PASIBOT step lasts pi/5 s). With the generated kernel the runs go in
parallel; the numeric solver runs them one after the other.
  --grid NAME=V1,...  the parameter and its values
  --out FILE.csv      one long table: column NAME (the value), t_norm = (t - t0)/(t1 - t0) (the
                      seed's t/T), then the sweep's columns; the runs one after the other
  --plot FILE.svg     one series per value of --y against --x
  --y COLUMN          the plotted column (default: the first driver's effort, the motor torque)
  --x t_norm|t        normalised time (default: steps of different duration compared phase by
                      phase, as the seed's Fig. 10) or time in seconds
  --set, --solver, --samples: as for mechgen sweep; --threads N: runs at once (default: all cores)
  --shard I/N         only part I of N of the values (their runs whole): `mechgen merge --out
                      FILE.csv PART...` joins the parts into this grid's file, byte for byte
A progress line (samples, rate, time left) is drawn on stderr when it is a terminal.
Prints, per value, the step's duration and the peak and RMS of the plotted column.
)";

// "[unit]" of a sweep column; a driver's effort is a torque or a force depending on its kind.
std::string unit_of(const Model& model, const std::string& column) {
  for (const Driver& d : model.drivers)
    if (column == d.name + ".effort") return d.kind == DriverKind::angle ? "[N m]" : "[N]";
  return report::column_unit(column);
}

int run_grid_command(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  if (!args.has("--grid")) throw UsageError("missing --grid NAME=V1,V2,...");
  if (!args.has("--out")) throw UsageError("missing --out FILE.csv");
  GridOptions options;
  try {
    std::tie(options.parameter, options.values) = parse_grid_spec(args.get("--grid"));
  } catch (const std::invalid_argument& error) {
    throw UsageError(std::string("--grid: ") + error.what());
  }
  options.solver = solver_option(args);
  options.samples = args.integer("--samples", 0);
  if (args.has("--samples") && options.samples < 1)
    throw UsageError("--samples must be at least 1");
  options.threads = args.integer("--threads", 0);
  if (options.threads < 0) throw UsageError("--threads must be at least 0");
  GridPlotOptions plot;
  plot.x = args.get("--x", "t_norm");
  if (plot.x != "t_norm" && plot.x != "t")
    throw UsageError("--x: expected t_norm or t, got '" + plot.x + "'");

  const Shard shard = shard_option(args);
  const auto [first, end] = shard_range(shard, options.values.size());
  if (first == end)
    throw UsageError("--shard " + args.get("--shard") + ": no value of the " +
                     std::to_string(options.values.size()) +
                     " falls in it (use N <= " + std::to_string(options.values.size()) + ")");
  options.values = {options.values.begin() + static_cast<long>(first),
                    options.values.begin() + static_cast<long>(end)};

  const Model model = load_model(path);
  options.parameters = model.default_parameters();
  apply_overrides(model, args.all("--set"), options.parameters);
  if (model.drivers.empty() && !args.has("--y"))
    throw UsageError("the model has no driver: name the plotted column with --y");
  plot.column =
      args.get("--y", model.drivers.empty() ? "" : model.drivers.front().name + ".effort");
  const std::vector<std::string> columns = column_names(model);
  if (std::find(columns.begin(), columns.end(), plot.column) == columns.end())
    throw UsageError("--y: no column '" + plot.column + "' in the sweep of " + model.name);

  // The kernel first (a model not compiled in is built on its first use): not part of the timing.
  if (options.solver == "generated") generated_kernel(model);
  const auto start = std::chrono::steady_clock::now();
  GridResult grid;
  {
    const size_t samples =
        static_cast<size_t>(options.samples > 0 ? options.samples : model.step.samples);
    Progress progress("grid " + model.name, options.values.size() * samples);
    options.progress = &progress;
    grid = run_grid(model, options);
  }
  const double elapsed = seconds_since(start);

  const std::string out = args.get("--out");
  g_current_file = out;
  write_grid_csv(out, grid, part_line(shard));
  std::cout << "grid " << model.name << ": " << options.parameter << " = " << grid.runs.size()
            << " values, " << options.solver << " solver, " << grid.runs.front().result.rows.size()
            << " samples each, " << fixed(elapsed * 1e3, 3) << " ms -> " << out << "\n";

  std::vector<std::vector<std::string>> rows{
      {options.parameter + (grid.unit.empty() ? "" : " [" + grid.unit + "]"), "step [s]",
       "peak " + plot.column, "RMS " + plot.column}};
  for (const GridRun& run : grid.runs) {
    const auto& run_columns = run.result.columns;
    const auto y = std::find(run_columns.begin(), run_columns.end(), plot.column);
    const auto t = std::find(run_columns.begin(), run_columns.end(), "t");
    if (y == run_columns.end() || t == run_columns.end())  // checked above; a kernel/model mismatch
      throw std::runtime_error("no column '" + plot.column + "' or 't' in the sweep");
    std::vector<double> ts, ys;
    for (const auto& row : run.result.rows) {
      ts.push_back(row[static_cast<size_t>(t - run_columns.begin())]);
      ys.push_back(row[static_cast<size_t>(y - run_columns.begin())]);
    }
    double peak = 0;
    for (double v : ys)
      if (std::abs(v) > std::abs(peak)) peak = v;
    rows.push_back({fixed(run.value), fixed(run.options.t1 - run.options.t0, 4), fixed(peak, 4),
                    fixed(time_rms(ts, ys), 4)});
  }
  std::cout << table(rows, "  ");

  if (args.has("--plot")) {
    plot.title = args.get("--title");
    plot.y_label = args.get("--ylabel", plot.column + " " + unit_of(model, plot.column));
    const std::string svg_path = args.get("--plot");
    g_current_file = svg_path;
    report::write_file_atomically(svg_path, report::render_svg(grid_plot(grid, plot)));
    std::cout << "plot: " << grid.runs.size() << " series of " << plot.column << " -> " << svg_path
              << "\n";
  }
  return 0;
}

}  // namespace

Command grid_command() {
  return {"grid",
          "one sweep per value of a parameter -> long CSV and multi-series plot",
          kGridHelp,
          {{"--grid", "", true},
           {"--set", "", true, true},
           {"--solver", "", true},
           {"--samples", "", true},
           {"--threads", "", true},
           {"--out", "-o", true},
           {"--plot", "", true},
           {"--y", "", true},
           {"--x", "", true},
           {"--title", "", true},
           {"--ylabel", "", true},
           {"--shard", "", true}},
          &run_grid_command};
}

}  // namespace mechgen::cli
