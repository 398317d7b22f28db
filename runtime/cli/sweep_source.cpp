#include "cli/sweep_source.hpp"

#include "model/columns.hpp"
#include "report/csv_table.hpp"
#include "sweep/sweep.hpp"

namespace mechgen::cli {

const char* const kSweepSourceHelp =
    R"(  --csv FILE.csv      analyse this sweep (from mechgen sweep) instead of running one
  --solver generated|numeric   the solver of a fresh sweep (default generated)
  --samples N, --t0 T0, --t1 T1   a fresh sweep's samples and span (default: the model's step)
  --set NAME=VALUE    overrides a model parameter (repeatable); with --csv, give the values the
                      CSV was swept with (masses and lengths enter the analysis)
)";

std::vector<OptionSpec> sweep_source_options() {
  return {{"--csv", "", true}, {"--solver", "", true}, {"--samples", "", true},
          {"--t0", "", true},  {"--t1", "", true},     {"--set", "", true, true}};
}

SweepSource sweep_source(const Model& model, const Args& args) {
  SweepSource source;
  source.parameters = model.default_parameters();
  apply_overrides(model, args.all("--set"), source.parameters);
  if (args.has("--csv")) {
    for (const char* option : {"--solver", "--samples", "--t0", "--t1"})
      if (args.has(option))
        throw UsageError(std::string(option) + " applies to a fresh sweep, not to --csv");
    const std::string path = args.get("--csv");
    g_current_file = path;
    report::CsvTable table = report::read_csv(path);
    if (table.header != column_names(model))
      throw report::CsvError(path + ": the columns are not those of a sweep of model '" +
                             model.name + "' (" + model.file + ")");
    source.columns = std::move(table.header);
    source.rows = std::move(table.rows);
    source.label = path;
    return source;
  }
  const SweepOptions options = sweep_options(model, source.parameters, args);
  SweepResult result = run_sweep(model, options);
  source.columns = std::move(result.columns);
  source.rows = std::move(result.rows);
  source.label = options.solver + " solver, " + std::to_string(options.samples) + " samples";
  return source;
}

}  // namespace mechgen::cli
