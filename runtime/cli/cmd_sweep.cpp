// mechgen sweep: one run of a model over time -> the sweep CSV (DESIGN.md), or the range of every
// column (--summary); a shard of the run with --shard I/N.
#include <chrono>
#include <iostream>
#include <string>
#include <vector>

#include "cli/cmd_spatial.hpp"
#include "cli/command.hpp"
#include "cli/model_info.hpp"
#include "model/columns.hpp"
#include "model/model.hpp"
#include "model/spatial_model.hpp"
#include "report/atomic_output.hpp"
#include "report/column_plot.hpp"
#include "sweep/sweep.hpp"

namespace mechgen::cli {

namespace {

const char* const kSweepHelp =
    R"(usage: mechgen sweep MODEL.yaml [--solver generated|numeric] [--set NAME=VALUE]...
                     [--samples N] [--t0 T0] [--t1 T1] [--threads N] [--out FILE.csv] [--summary]
                     [--shard I/N] [--mass-matrix]

One run over time: every named quantity at N uniform samples from T0 to T1 inclusive (defaults:
the model's step, evaluated with the --set values), one CSV row per sample (the columns of README.md's
"Command line", 17 significant digits).
  --solver generated  the model's generated kernel (default): compiled into mechgen when it is
                      current, else generated, compiled and cached on first use (--cache DIR;
                      --max-kernel-mb MB, --compile-timeout S, --compile-memory-mb MB: its
                      compile budget, `mechgen --help`)
  --solver numeric    the reference solver
  --set NAME=VALUE    overrides a model parameter (repeatable); no regeneration needed
  --threads N         threads for the generated solver (default: all, for 20000 samples or more)
  --out FILE.csv      where to write the table (required unless --summary is given)
  --summary           print each column's minimum and maximum; without --out no table is kept
                      (10^6 PASIBOT samples in about 0.6 s on 2 cores)
  --shard I/N         only part I of N of the samples (with --out): the parts, joined by
                      `mechgen merge --out FILE PART...`, give this run's file byte for byte
  --mass-matrix       adds the mass matrix and bias in the drivers' coordinates (effort =
                      M qdd + h): columns M.<a>.<b> (a before b in model order, diagonal
                      included) and h.<a>, from either solver (the generated kernel's
                      mass_bias entry, or the numeric solver's unit accelerations)
A progress line (samples, rate, time left) is drawn on stderr when it is a terminal.
A sample the solver cannot evaluate (unreachable, singular, diverged) is an error naming t.
)";

int run_sweep_command(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  if (is_spatial_description(path)) return run_spatial_sweep(args);
  if (!args.has("--out") && !args.has("--summary"))
    throw UsageError("missing --out FILE.csv (or --summary)");
  const Model model = load_model(path);
  std::vector<double> parameters = model.default_parameters();
  apply_overrides(model, args.all("--set"), parameters);
  SweepOptions options = sweep_options(model, parameters, args);
  options.threads = args.integer("--threads", 0);
  if (options.threads < 0) throw UsageError("--threads must be at least 0");
  options.shard = shard_option(args);
  options.mass_matrix = args.has("--mass-matrix");
  if (!options.shard.whole() && (!args.has("--out") || args.has("--summary")))
    throw UsageError("--shard writes a part with --out FILE.csv (and no --summary)");

  if (args.has("--out")) {  // before computing a table that could not be written
    const auto [first, end] = shard_range(options.shard, static_cast<size_t>(options.samples));
    const size_t n = model.drivers.size(), extra = options.mass_matrix ? n * (n + 3) / 2 : 0;
    report::check_free_space(args.get("--out"),
                             expected_csv_bytes(end - first, column_names(model).size() + extra));
  }
  // The kernel first (a model not compiled in is built on its first use): not part of the timing.
  if (options.solver == "generated") generated_kernel(model);
  const auto start = std::chrono::steady_clock::now();
  // Summary only: the ranges are folded as the samples come, no table is kept.
  SweepResult result;
  ColumnRanges ranges;
  {
    const auto [first, end] = shard_range(options.shard, static_cast<size_t>(options.samples));
    Progress progress("sweep " + model.name, end - first);
    options.progress = &progress;
    ranges = args.has("--out") ? column_ranges(result = run_sweep(model, options))
                               : sweep_ranges(model, options);
  }
  const double elapsed = seconds_since(start);
  std::string line = "sweep " + model.name + ": " + options.solver + " solver, " +
                     std::to_string(options.samples) + " samples, t = " + number_text(options.t0) +
                     " .. " + number_text(options.t1) + " s, " +
                     std::to_string(ranges.columns.size()) + " columns, " +
                     fixed(elapsed * 1e3, 3) + " ms";
  if (args.has("--out")) {
    const std::string out = args.get("--out");
    g_current_file = out;
    write_csv(out, result, part_line(options.shard));
    if (!options.shard.whole())
      line += ", part " + std::to_string(options.shard.index) + "/" +
              std::to_string(options.shard.count) + " (" + std::to_string(result.rows.size()) +
              " rows)";
    line += " -> " + out;
  }
  std::cout << line << "\n";

  if (args.has("--summary")) {
    std::vector<std::vector<std::string>> rows{{"column", "min", "max", "unit"}};
    for (size_t c = 0; c < ranges.columns.size(); ++c)
      rows.push_back({ranges.columns[c], fixed(ranges.min[c], 8), fixed(ranges.max[c], 8),
                      report::column_unit(ranges.columns[c])});
    std::cout << table(rows, "  ");
  }
  return 0;
}

}  // namespace

Command sweep_command() {
  return {"sweep",
          "one run over time -> CSV",
          kSweepHelp,
          {{"--solver", "", true},
           {"--set", "", true, true},
           {"--samples", "", true},
           {"--t0", "", true},
           {"--t1", "", true},
           {"--threads", "", true},
           {"--out", "-o", true},
           {"--summary", "", false},
           {"--shard", "", true},
           {"--mass-matrix", "", false}},
          &run_sweep_command};
}

}  // namespace mechgen::cli
