// Where the analysis commands (loads, zmp) get their sweep: a CSV written by `mechgen sweep`
// (--csv FILE) or a fresh run of the model (--solver, --samples, --t0, --t1); --set applies to
// both (a CSV does not record its parameters: give the --set values it was swept with).
#pragma once

#include <string>
#include <vector>

#include "cli/command.hpp"
#include "model/model.hpp"

namespace mechgen::cli {

struct SweepSource {
  std::vector<double> parameters;
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::string label;  // "out/pasibot_step.csv" or "generated solver, 181 samples"
};

// The options sweep_source() reads, for a Command's option list.
std::vector<OptionSpec> sweep_source_options();
// Help text lines for those options.
extern const char* const kSweepSourceHelp;

// Throws UsageError for bad options, report::CsvError for a CSV that is not a sweep of the model.
SweepSource sweep_source(const Model& model, const Args& args);

}  // namespace mechgen::cli
