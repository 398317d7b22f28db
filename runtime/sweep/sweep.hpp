// One run of a model over time: every named quantity of ../../../shared/DESIGN.md's CSV contract
// at uniformly spaced samples, from the compiled kernel (default) or the numeric reference solver.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "model/model.hpp"
#include "sweep/compiled_kernel.hpp"
#include "sweep/progress.hpp"
#include "sweep/shard.hpp"

namespace mechgen {

struct SweepOptions {
  std::string solver = "generated";  // "generated" (compiled kernel) or "numeric"
  std::vector<double> parameters;    // Model::parameters order; empty: the defaults
  double t0 = 0, t1 = 0;             // inclusive
  int samples = 2;                   // >= 1; one sample evaluates t0 only
  // Threads for the generated solver: 0 picks one per hardware thread when samples is large
  // (>= parallel_threshold), else 1. The numeric solver is sequential (each sample continues
  // from the previous configuration).
  int threads = 0;
  static constexpr int parallel_threshold = 20000;
  // Told of every sample done (may be shared by several sweeps, e.g. a grid's runs); optional.
  Progress* progress = nullptr;
  // Only this shard's samples (sweep/shard.hpp); sweep_ranges takes whole runs only.
  Shard shard;
  // Issue 22: append the mass matrix and bias in the drivers' coordinates
  // (numeric::mass_bias_columns) to every row: the numeric solver's mass_matrix_bias, or the
  // generated kernel's mass_bias entry (CompiledKernel::mass_bias_double). sweep_ranges then
  // keeps the table (run_sweep).
  bool mass_matrix = false;
};

struct SweepResult {
  std::vector<std::string> columns;       // column_names(model) (+ mass_bias_columns)
  std::vector<std::vector<double>> rows;  // one per sample, each as long as columns
};

// The generated kernel of the model as it is described now (ondemand/kernel_resolver.hpp): the
// compiled-in one when its fingerprint is the description's, else one built on demand and cached.
// Throws ModelError (naming the model file) when there is none: never a kernel of another
// description, never the numeric solver instead.
const CompiledKernel& generated_kernel(const Model& model);

// The sweep options a model describes: its step with the given (or default) parameters. Given
// parameters go through the model's value checks first (model/value_checks.hpp: ModelError).
SweepOptions default_sweep(const Model& model, const std::vector<double>& parameters = {});

// Throws ModelError for a bad request (unknown solver, wrong parameter count, samples < 1, no
// kernel to be had: see generated_kernel) and for a sample the solver
// cannot evaluate: the message names t, the status and, for a kernel, the failing group. Never
// returns a NaN row.
SweepResult run_sweep(const Model& model, const SweepOptions& options);

// The smallest and largest value of every column over a sweep.
struct ColumnRanges {
  std::vector<std::string> columns;  // column_names(model)
  std::vector<double> min, max;      // one per column
  size_t samples = 0;
};

// run_sweep's ranges without keeping the table: the generated solver evaluates blocks of samples
// through the kernel's vectorised batch entry on `threads` threads, each folding its samples into
// its own ranges (memory independent of the sample count). Same errors as run_sweep.
ColumnRanges sweep_ranges(const Model& model, const SweepOptions& options);
// The ranges of a table already computed.
ColumnRanges column_ranges(const SweepResult& result);

// A table of `samples` rows of `columns` doubles that would not fit in half of this machine's
// memory is a ModelError up front (naming the size), not a std::bad_alloc or the OOM killer after
// minutes; run_sweep and walk check their tables with it.
void check_table_memory(const Model& model, size_t samples, size_t columns);

// The sample times: t0 + (t1 - t0) * i / (samples - 1), the last exactly t1.
std::vector<double> sample_times(double t0, double t1, int samples);

// Header and rows, comma separated, every number with 17 significant digits ("%.17g"), so
// reading the file back gives the same doubles; `first_line` (a shard's part_line) before the
// header. Throws std::runtime_error when it cannot write.
void write_csv(const std::string& path, const SweepResult& result,
               const std::string& first_line = "");

// About how many bytes write_csv writes for `rows` rows of `columns` numbers (22 per number: most
// "%.17g" numbers take 18 to 24 characters and a separator), to compare with the free space
// (report::check_free_space) before a run computes them.
std::uint64_t expected_csv_bytes(std::uint64_t rows, std::uint64_t columns);

}  // namespace mechgen
