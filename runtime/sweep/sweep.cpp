#include "sweep/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <thread>

#include <unistd.h>

#include "model/columns.hpp"
#include "model/value_checks.hpp"
#include "numeric/mass_bias.hpp"
#include "numeric/reference_solver.hpp"
#include "ondemand/kernel_resolver.hpp"
#include "report/atomic_output.hpp"
#include "sweep/compiled_kernel.hpp"
#include "sweep/parallel.hpp"

namespace mechgen {

namespace {

SourceLoc model_loc(const Model& model) {
  return {model.file, 0, 0};
}

std::string format_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

const char* kernel_status(int status) {
  switch (status) {
    case 1:
      return "unreachable";
    case 2:
      return "singular";
    case 3:
      return "non-finite result";
    default:
      return "unknown status";
  }
}

// What went wrong at one sample of a kernel sweep.
struct KernelFailure {
  size_t sample = 0;
  int status = 0;
  int group = -1;
};

// The sample times of sample_times(), computed when needed: a sweep of ranges keeps nothing per
// sample.
struct SampleTimes {
  double t0 = 0, t1 = 0;
  size_t n = 0;      // samples of the whole run
  size_t first = 0;  // this view's first sample (a shard's part)
  size_t count = n;  // samples in this view
  size_t size() const { return count; }
  double operator[](size_t i) const {
    const size_t j = first + i;
    return j == n - 1 && n > 1 ? t1
                               : t0 + (t1 - t0) * static_cast<double>(j) /
                                          static_cast<double>(std::max<size_t>(1, n - 1));
  }
  SampleTimes part(size_t from, size_t samples) const { return {t0, t1, n, first + from, samples}; }
};

// Samples per call of the batch entry: its column-major block (columns x kBlock doubles, 170 kB
// for PASIBOT) stays in the L2 cache (measured: 32 to 128 samples are within 10%).
constexpr size_t kBlock = 64;

// A thread's scratch for one block of the batch entry.
struct BlockBuffers {
  explicit BlockBuffers(const CompiledKernel& kernel)
      : out(static_cast<size_t>(kernel.column_count) * kBlock),
        t(kBlock),
        status(kBlock),
        group(kBlock) {}
  std::vector<double> out, t;
  std::vector<int> status, group;
};

// Evaluates samples [begin, end) block by block, handing each block to `use(first, n, out)`
// (samples first .. first + n, column c of sample first + k at out[c * n + k]); stops at the first
// failure and returns it (status 0: none); a failing block is not handed over.
template <class Use>
KernelFailure evaluate_blocks(const CompiledKernel& kernel, const std::vector<double>& parameters,
                              const SampleTimes& times, size_t begin, size_t end,
                              Progress* progress, Use&& use) {
  BlockBuffers buffers(kernel);
  for (size_t first = begin; first < end; first += kBlock) {
    const size_t n = std::min(kBlock, end - first);
    for (size_t k = 0; k < n; ++k) buffers.t[k] = times[first + k];
    kernel.evaluate_batch_double(parameters.data(), buffers.t.data(), static_cast<long>(n),
                                 buffers.out.data(), buffers.status.data(), buffers.group.data());
    for (size_t k = 0; k < n; ++k)
      if (buffers.status[k] != 0) return {first + k, buffers.status[k], buffers.group[k]};
    use(first, n, buffers.out.data());
    if (progress) progress->advance(n);
  }
  return {};
}

// Evaluates samples [begin, end) into rows; stops at the first failure and returns it.
KernelFailure evaluate_range(const CompiledKernel& kernel, const std::vector<double>& parameters,
                             const SampleTimes& times, size_t begin, size_t end, Progress* progress,
                             std::vector<std::vector<double>>& rows) {
  const size_t columns = static_cast<size_t>(kernel.column_count);
  return evaluate_blocks(kernel, parameters, times, begin, end, progress,
                         [&](size_t first, size_t n, const double* out) {
                           for (size_t k = 0; k < n; ++k) {
                             std::vector<double>& row = rows[first + k];
                             row.resize(columns);  // first touch by this thread
                             for (size_t c = 0; c < columns; ++c) row[c] = out[c * n + k];
                           }
                         });
}

// Appends the kernel's M (a before b) and h at each sample of [begin, end) to its row, in
// numeric::mass_bias_columns order; stops at the first failure and returns it.
KernelFailure append_mass_bias(const CompiledKernel& kernel, const std::vector<double>& parameters,
                               const SampleTimes& times, size_t begin, size_t end,
                               std::vector<std::vector<double>>& rows) {
  const size_t n = static_cast<size_t>(kernel.driver_count);
  std::vector<double> M(n * n), h(n);
  for (size_t i = begin; i < end; ++i) {
    int group = -1;
    const int status =
        kernel.mass_bias_double(parameters.data(), times[i], nullptr, M.data(), h.data(), &group);
    if (status != 0) return {i, status, group};
    for (size_t a = 0; a < n; ++a)
      for (size_t b = a; b < n; ++b) rows[i].push_back(M[a * n + b]);
    for (size_t a = 0; a < n; ++a) rows[i].push_back(h[a]);
  }
  return {};
}

// The threads a generated sweep of n samples uses.
int sweep_threads(const SweepOptions& options, size_t n) {
  int threads = options.threads;
  if (threads <= 0)
    threads = static_cast<int>(n) >= SweepOptions::parallel_threshold
                  ? std::max(1, static_cast<int>(std::thread::hardware_concurrency()))
                  : 1;
  return static_cast<int>(std::max<size_t>(1, std::min<size_t>(static_cast<size_t>(threads), n)));
}

// Runs task(k, begin, end) on `threads` contiguous chunks of [0, n), one thread each; a thread
// that cannot start or a task that throws is one exception here (sweep/parallel.hpp).
template <class Task>
void in_parallel(int threads, size_t n, Task&& task) {
  if (threads <= 1) {
    task(0, 0, n);
    return;
  }
  const size_t chunk = (n + static_cast<size_t>(threads) - 1) / static_cast<size_t>(threads);
  run_parallel(static_cast<size_t>(threads), [&](size_t k) {
    const size_t begin = std::min(n, k * chunk), end = std::min(n, begin + chunk);
    task(k, begin, end);
  });
}

// The sample (1-based, of `samples`) and its time, as every failure message names them.
std::string sample_text(size_t sample, size_t samples, double t) {
  return "sample " + std::to_string(sample + 1) + " of " + std::to_string(samples) +
         ", t = " + format_number(t);
}

[[noreturn]] void report_kernel_failure(const Model& model, const CompiledKernel& kernel,
                                        const SampleTimes& times, const KernelFailure& failure) {
  std::string message =
      "generated kernel: " + sample_text(failure.sample, times.size(), times[failure.sample]) +
      ": " + kernel_status(failure.status);
  if (failure.group >= 0 && failure.group < kernel.group_count)
    message += " in group " + std::string(kernel.group_names[failure.group]);
  message += failure.status == 1   ? " (the mechanism cannot assemble there with these parameters)"
             : failure.status == 3 ? " (the parameters or the motion are too large for double "
                                     "precision: an output overflows)"
                                   : " (the configuration is singular there)";
  throw ModelError(model_loc(model), message);
}

void sweep_generated(const Model& model, const SweepOptions& options, const SampleTimes& times,
                     SweepResult& result) {
  const CompiledKernel& kernel = generated_kernel(model);
  const size_t n = times.size();
  const int threads = sweep_threads(options, n);
  // Contiguous chunks, one per thread; each thread writes only its own rows.
  std::vector<KernelFailure> failures(static_cast<size_t>(threads));
  in_parallel(threads, n, [&](size_t k, size_t begin, size_t end) {
    failures[k] = evaluate_range(kernel, options.parameters, times, begin, end, options.progress,
                                 result.rows);
    if (options.mass_matrix && failures[k].status == 0)
      failures[k] = append_mass_bias(kernel, options.parameters, times, begin, end, result.rows);
  });
  // The earliest failing sample, as a sequential sweep would report it.
  for (const KernelFailure& failure : failures)
    if (failure.status != 0) report_kernel_failure(model, kernel, times, failure);
}

// What a numeric status means for the user, after its name.
const char* numeric_status_hint(numeric::Status status) {
  switch (status) {
    case numeric::Status::diverged:
      return " (Newton-Raphson found no configuration: the mechanism may not reach it with these "
             "parameters)";
    case numeric::Status::branch_jump:
      return " (the configuration jumped to another assembly branch: a dead point?)";
    case numeric::Status::singular_kinematics:
      return " (constraint Jacobian singular: velocities undetermined, a dead point)";
    case numeric::Status::singular_dynamics:
      return " (Newton-Euler system singular: the loads are statically indeterminate)";
    case numeric::Status::ok:
      break;
  }
  return "";
}

void sweep_numeric(const Model& model, const SweepOptions& options, const SampleTimes& times,
                   SweepResult& result) {
  numeric::ReferenceSolver solver(model, options.parameters);
  solver.assemble(times[0]);
  for (size_t i = 0; i < times.size(); ++i) {
    result.rows[i].assign(result.columns.size(), 0.0);
    numeric::Status status = solver.solve(times[i], result.rows[i]);
    numeric::MassBias mb;
    if (status == numeric::Status::ok && options.mass_matrix) {
      if (solver.mass_matrix_bias(times[i], mb.M, mb.h))
        numeric::append_mass_bias(mb, result.rows[i]);
      else
        status = numeric::Status::singular_dynamics;
    }
    if (status != numeric::Status::ok)
      throw ModelError(model_loc(model),
                       "numeric solver: " + sample_text(i, times.size(), times[i]) + ": " +
                           numeric::to_string(status) + numeric_status_hint(status));
    // Never a NaN or infinite row with exit 0: the first non-finite column is named.
    for (size_t c = 0; c < result.columns.size(); ++c)
      if (!std::isfinite(result.rows[i][c]))
        throw ModelError(model_loc(model),
                         "numeric solver: " + sample_text(i, times.size(), times[i]) +
                             ": non-finite result in column " + result.columns[c] +
                             " (the parameters or the motion are too large "
                             "for double precision)");
    if (options.progress) options.progress->advance(1);
  }
}

}  // namespace

SweepOptions default_sweep(const Model& model, const std::vector<double>& parameters) {
  SweepOptions options;
  options.parameters = parameters.empty() ? model.default_parameters() : parameters;
  // Run-time values (a grid value, a catalogue motor's mass) get the checks the file's get.
  if (!parameters.empty()) check_values(model, options.parameters);
  const GiNaC::exmap subs = model.substitutions(options.parameters);
  options.t0 = model.evaluate(model.step.t0, subs);
  options.t1 = model.evaluate(model.step.t1, subs);
  options.samples = model.step.samples;
  return options;
}

std::vector<double> sample_times(double t0, double t1, int samples) {
  const SampleTimes times{t0, t1, static_cast<size_t>(std::max(0, samples))};
  std::vector<double> values(times.size());
  for (size_t i = 0; i < times.size(); ++i) values[i] = times[i];
  return values;
}

namespace {

// run_sweep's checks of a request; fills in the default parameters.
SweepOptions checked(const Model& model, const SweepOptions& options_in) {
  SweepOptions options = options_in;
  if (options.parameters.empty()) options.parameters = model.default_parameters();
  const SourceLoc where = model_loc(model);
  if (options.parameters.size() != model.parameters.size())
    throw ModelError(where, "sweep: " + std::to_string(options.parameters.size()) +
                                " parameter values given, model '" + model.name + "' has " +
                                std::to_string(model.parameters.size()));
  if (options.samples < 1)
    throw ModelError(where,
                     "sweep: samples must be at least 1, got " + std::to_string(options.samples));
  if (options.threads > thread_limit())
    throw ModelError(where, "sweep: " + std::to_string(options.threads) +
                                " threads asked for, at most " + std::to_string(thread_limit()) +
                                " (4 x the hardware threads)");
  if (!std::isfinite(options.t0) || !std::isfinite(options.t1))
    throw ModelError(where, "sweep: t0 and t1 must be finite");
  if (options.solver != "generated" && options.solver != "numeric")
    throw ModelError(
        where, "sweep: unknown solver '" + options.solver + "' (expected generated or numeric)");
  return options;
}

void include(ColumnRanges& ranges, size_t c, double value) {
  ranges.min[c] = std::min(ranges.min[c], value);
  ranges.max[c] = std::max(ranges.max[c], value);
}

ColumnRanges empty_ranges(std::vector<std::string> columns) {
  ColumnRanges ranges;
  ranges.min.assign(columns.size(), std::numeric_limits<double>::infinity());
  ranges.max.assign(columns.size(), -std::numeric_limits<double>::infinity());
  ranges.columns = std::move(columns);
  return ranges;
}

}  // namespace

void check_table_memory(const Model& model, size_t samples, size_t columns) {
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page_size <= 0) return;
  const double available = 0.5 * static_cast<double>(pages) * static_cast<double>(page_size);
  const double needed =
      static_cast<double>(samples) *
      (static_cast<double>(columns) * sizeof(double) + sizeof(std::vector<double>));
  if (needed > available) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "a table of %zu rows needs %.3g GB, more than half of this machine's memory "
                  "(%.3g GB): use fewer samples or steps (a sweep's --summary keeps no table)",
                  samples, needed / 1e9, 2 * available / 1e9);
    throw ModelError(model_loc(model), text);
  }
}

ColumnRanges column_ranges(const SweepResult& result) {
  ColumnRanges ranges = empty_ranges(result.columns);
  ranges.samples = result.rows.size();
  for (const std::vector<double>& row : result.rows)
    for (size_t c = 0; c < row.size(); ++c) include(ranges, c, row[c]);
  return ranges;
}

ColumnRanges sweep_ranges(const Model& model, const SweepOptions& options_in) {
  const SweepOptions options = checked(model, options_in);
  if (!options.shard.whole())
    throw ModelError(model_loc(model), "sweep: the ranges of a shard are not those of the run");
  if (options.solver != "generated" || options.mass_matrix)
    return column_ranges(run_sweep(model, options));
  const CompiledKernel& kernel = generated_kernel(model);
  const SampleTimes times{options.t0, options.t1, static_cast<size_t>(options.samples)};
  const size_t n = times.size(), columns = static_cast<size_t>(kernel.column_count);
  const int threads = sweep_threads(options, n);
  // Each thread folds its chunk into its own ranges; they are merged at the end.
  std::vector<ColumnRanges> partial(static_cast<size_t>(threads),
                                    empty_ranges(column_names(model)));
  std::vector<KernelFailure> failures(static_cast<size_t>(threads));
  in_parallel(threads, n, [&](size_t k, size_t begin, size_t end) {
    ColumnRanges& mine = partial[k];
    failures[k] = evaluate_blocks(kernel, options.parameters, times, begin, end, options.progress,
                                  [&](size_t, size_t n, const double* out) {
                                    // A column's samples are contiguous: this loop vectorises.
                                    for (size_t c = 0; c < columns; ++c) {
                                      double lo = mine.min[c], hi = mine.max[c];
                                      for (size_t k = 0; k < n; ++k) {
                                        lo = std::min(lo, out[c * n + k]);
                                        hi = std::max(hi, out[c * n + k]);
                                      }
                                      mine.min[c] = lo;
                                      mine.max[c] = hi;
                                    }
                                  });
  });
  for (const KernelFailure& failure : failures)
    if (failure.status != 0) report_kernel_failure(model, kernel, times, failure);
  ColumnRanges ranges = empty_ranges(column_names(model));
  ranges.samples = n;
  for (const ColumnRanges& part : partial)
    for (size_t c = 0; c < columns; ++c) {
      include(ranges, c, part.min[c]);
      include(ranges, c, part.max[c]);
    }
  return ranges;
}

SweepResult run_sweep(const Model& model, const SweepOptions& options_in) {
  const SweepOptions options = checked(model, options_in);
  SweepResult result;
  result.columns = column_names(model);
  if (options.mass_matrix) {
    std::vector<std::string> drivers;
    for (const Driver& d : model.drivers) drivers.push_back(d.name);
    for (std::string& c : numeric::mass_bias_columns(drivers)) result.columns.push_back(c);
  }
  const SampleTimes all{options.t0, options.t1, static_cast<size_t>(options.samples)};
  // A shard's samples: a generated sample stands alone, but the numeric solver follows the
  // mechanism from t0 (each sample starts from the previous configuration), so a numeric shard
  // runs from the first sample and keeps its own rows: the same bits as the whole run.
  const auto [begin, end] = shard_range(options.shard, all.size());
  if (begin == end) return result;
  const size_t first = options.solver == "generated" ? begin : 0;
  const size_t skip = begin - first;
  const SampleTimes times = all.part(first, end - first);
  check_table_memory(model, times.size(), result.columns.size());
  result.rows.resize(times.size());  // each row is sized by the thread that fills it
  if (options.solver == "generated")
    sweep_generated(model, options, times, result);
  else
    sweep_numeric(model, options, times, result);
  result.rows.erase(result.rows.begin(), result.rows.begin() + static_cast<long>(skip));
  return result;
}

void write_csv(const std::string& path, const SweepResult& result, const std::string& first_line) {
  // A killed write leaves the previous file intact; a table larger than the free space is refused.
  report::AtomicOutput output(path, expected_csv_bytes(result.rows.size(), result.columns.size()));
  std::ostream& out = output.stream();
  out << first_line;
  for (size_t i = 0; i < result.columns.size(); ++i) out << (i ? "," : "") << result.columns[i];
  out << '\n';
  char number[32];
  for (const std::vector<double>& row : result.rows) {
    for (size_t i = 0; i < row.size(); ++i) {
      std::snprintf(number, sizeof number, "%s%.17g", i ? "," : "", row[i]);
      out << number;
    }
    out << '\n';
  }
  output.commit();
}

std::uint64_t expected_csv_bytes(std::uint64_t rows, std::uint64_t columns) {
  return (rows + 1) * columns * 22;
}

const CompiledKernel& generated_kernel(const Model& model) {
  try {
    return ondemand::kernel_for(model);
  } catch (const ModelError&) {
    throw;
  } catch (const std::exception& error) {
    throw ModelError(model_loc(model), error.what());
  }
}

}  // namespace mechgen
