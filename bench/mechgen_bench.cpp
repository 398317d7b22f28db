// mechgen_bench: the time of one sample (one instant of a model's default step: every position,
// velocity and acceleration, joint reaction and driver effort), computed several ways:
//   <model>/generated        evaluate<double>: the generated closed form, kinematics and dynamics
//   <model>/generated_float  the same kernel in float
//   <model>/generated_batch  the runtime's batch entry (evaluate_batch<double>, vectorised) over
//                            blocks of 64 samples
//   <model>/kinematics       kinematics<double> only
//   <model>/ne_system        ne_system<double> only: assembling the dense Newton-Euler A and b
//   <model>/dense_lu         kinematics + ne_system<double> + Eigen PartialPivLU solve of A x = b
//                            (the seed's approach, with exact kinematics)
//   <model>/dense_inverse    kinematics + ne_system<double> + A.inverse() * b (the seed's MATLAB)
//   <model>/numeric          ReferenceSolver::solve, continuing along the step
//   pasibot/generated_v3     evaluate<double> compiled for x86-64-v3 (AVX2, FMA), when the
//   pasibot/kinematics_v3    compiler and the processor have it (bench/pasibot_v3.cpp)
//   pasibot/generated_batch_v3  evaluate_batch<double> compiled the same way
//   leg6/numeric, leg6/kdl   the spatial reference solver against Orocos KDL: foot FK, Jacobian
//                            and inverse dynamics per sample (bench/spatial_bench.cpp)
// One benchmark iteration is one sample, so the reported time is the time per sample. The samples
// cycle through the model's default step (the numeric solver walks it forth and back, each sample
// next to the previous one), so successive calls never see the same input.
//
// Before timing anything, a sanity check aborts when the generated kernel, the dense LU solve, the
// explicit inverse and the numeric solver disagree on a driver effort by more than 1e-9 relative,
// so the benchmark never times a wrong answer.
//
//   mechgen_bench [Google Benchmark flags]      the benchmarks (filter: --benchmark_filter=REGEX)
//   mechgen_bench --instructions NAME N         N samples of the variant NAME, then exit (for
//                                               valgrind --tool=callgrind; subtract N = 0)
#include <benchmark/benchmark.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "chebyshev/chebyshev.hpp"
#include "model/columns.hpp"
#include "model/model.hpp"
#include "numeric/reference_solver.hpp"
#include "pasibot/pasibot.hpp"
#include "pasibot_v3.hpp"
#include "spatial_bench.hpp"
#include "sweep/compiled_kernel.hpp"

namespace mechgen::bench {
namespace {

// One generated kernel's namespace as a type, so the variants below are templates over models.
#define MECHGEN_BENCH_KERNEL(NS)                                                           \
  struct NS##_kernel {                                                                     \
    static constexpr const char* name = #NS;                                               \
    static constexpr int parameter_count = gen::NS::parameter_count;                       \
    static constexpr int column_count = gen::NS::column_count;                             \
    static constexpr const char* const* column_names = gen::NS::column_names;              \
    static constexpr int ne_size = gen::NS::ne_size;                                       \
    static constexpr const char* const* ne_unknowns = gen::NS::ne_unknowns;                \
    template <class T>                                                                     \
    using Params = gen::NS::Params<T>;                                                     \
    template <class T>                                                                     \
    using Inputs = gen::NS::Inputs<T>;                                                     \
    template <class T>                                                                     \
    using State = gen::NS::State<T>;                                                       \
    template <class T>                                                                     \
    static void set_parameters(Params<T>& p, const T* values) {                            \
      gen::NS::set_parameters(p, values);                                                  \
    }                                                                                      \
    template <class T>                                                                     \
    static void driver_inputs(const Params<T>& p, T t, Inputs<T>& in) {                    \
      gen::NS::driver_inputs(p, t, in);                                                    \
    }                                                                                      \
    template <class T>                                                                     \
    static bool evaluate(const Params<T>& p, const Inputs<T>& in, State<T>& s) {           \
      return gen::NS::evaluate(p, in, s) == gen::NS::Status::ok;                           \
    }                                                                                      \
    template <class T>                                                                     \
    static bool kinematics(const Params<T>& p, const Inputs<T>& in, State<T>& s) {         \
      return gen::NS::kinematics(p, in, s) == gen::NS::Status::ok;                         \
    }                                                                                      \
    template <class T>                                                                     \
    static bool ne_system(const Params<T>& p, const Inputs<T>& in, T* A, T* b) {           \
      return gen::NS::ne_system(p, in, A, b) == gen::NS::Status::ok;                       \
    }                                                                                      \
    template <class T>                                                                     \
    static void to_columns(const Inputs<T>& in, const State<T>& s, T* row) {               \
      gen::NS::to_columns(in, s, row);                                                     \
    }                                                                                      \
    static constexpr int batch_storage_per_sample = gen::NS::batch_storage_per_sample;     \
    template <class T>                                                                     \
    static void evaluate_batch(const Params<T>& p, const T* t, long n, T* storage, T* out, \
                               T* failure) {                                               \
      gen::NS::BatchInputs<T> batch;                                                       \
      gen::NS::batch_driver_inputs(p, t, n, storage, batch);                               \
      gen::NS::evaluate_batch(p, batch, n, out, n, failure);                               \
    }                                                                                      \
  };

MECHGEN_BENCH_KERNEL(pasibot)
MECHGEN_BENCH_KERNEL(chebyshev)
#undef MECHGEN_BENCH_KERNEL

[[noreturn]] void fail(const std::string& message) {
  std::fprintf(stderr, "mechgen_bench: %s\n", message.c_str());
  std::exit(EXIT_FAILURE);
}

// A model description with its default parameters and the sample times of its default step.
struct ModelData {
  Model model;
  std::vector<double> parameters;
  std::vector<double> times;
};

// Read once per model, on first use.
const ModelData& model_data(const std::string& name) {
  static std::map<std::string, std::unique_ptr<ModelData>> cache;
  std::unique_ptr<ModelData>& data = cache[name];
  if (!data) {
    data = std::make_unique<ModelData>();
    data->model = read_model(std::string(MECHGEN_SOURCE_DIR) + "/models/" + name + ".yaml");
    data->parameters = data->model.default_parameters();
    const GiNaC::exmap subs = data->model.substitutions(data->parameters);
    const double t0 = data->model.evaluate(data->model.step.t0, subs);
    const double t1 = data->model.evaluate(data->model.step.t1, subs);
    const int samples = data->model.step.samples;
    if (samples < 2) fail(name + ": the default step needs at least 2 samples");
    for (int i = 0; i < samples; ++i) data->times.push_back(t0 + (t1 - t0) * i / (samples - 1));
  }
  return *data;
}

template <class K, class T>
typename K::template Params<T> kernel_parameters(const ModelData& m) {
  if (static_cast<int>(m.parameters.size()) != K::parameter_count)
    fail(std::string(K::name) + ": the model and its generated kernel have different parameters");
  std::vector<T> values(m.parameters.begin(), m.parameters.end());
  typename K::template Params<T> p;
  K::set_parameters(p, values.data());
  return p;
}

// The generated kernel: evaluate (kinematics and dynamics) or kinematics only, in T.
template <class K, class T, bool kinematics_only = false>
class Generated {
 public:
  explicit Generated(const ModelData& m)
      : p_(kernel_parameters<K, T>(m)), times_(m.times.begin(), m.times.end()) {}

  bool at(std::size_t k) {
    K::driver_inputs(p_, times_[k], in_);
    bool ok;
    if constexpr (kinematics_only) {
      ok = K::kinematics(p_, in_, s_);
    } else {
      ok = K::evaluate(p_, in_, s_);
    }
    benchmark::DoNotOptimize(s_);
    return ok;
  }
  bool next() {
    const bool ok = at(k_);
    if (++k_ == times_.size()) k_ = 0;
    return ok;
  }
  // The CSV row of the last sample.
  void columns(T* row) const { K::to_columns(in_, s_, row); }
  std::size_t size() const { return times_.size(); }

 private:
  typename K::template Params<T> p_;
  typename K::template Inputs<T> in_;
  typename K::template State<T> s_{};
  std::vector<T> times_;
  std::size_t k_ = 0;
};

// The batch entry the sweeps use (CompiledKernel::evaluate_batch_double: evaluate_batch in its
// AVX-512F, AVX2 or baseline clone, driver inputs included): blocks of kBatch consecutive
// samples of the step, one block every kBatch calls of next(), so that the time per call is the
// time per sample.
template <class K>
class GeneratedBatch {
 public:
  static constexpr long kBatch = 64;

  explicit GeneratedBatch(const ModelData& m)
      : kernel_(compiled(K::name)),
        parameters_(m.parameters),
        times_(m.times),
        t_(kBatch),
        out_(static_cast<std::size_t>(K::column_count * kBatch)),
        status_(kBatch),
        group_(kBatch) {}

  bool next() {
    if (used_ == kBatch) {
      for (long i = 0; i < kBatch; ++i) {
        t_[static_cast<std::size_t>(i)] = times_[k_];
        if (++k_ == times_.size()) k_ = 0;
      }
      kernel_.evaluate_batch_double(parameters_.data(), t_.data(), kBatch, out_.data(),
                                    status_.data(), group_.data());
      benchmark::DoNotOptimize(out_.data());
      benchmark::ClobberMemory();
      used_ = 0;
    }
    return status_[static_cast<std::size_t>(used_++)] == 0;
  }

 private:
  static const CompiledKernel& compiled(const std::string& model) {
    const CompiledKernel* kernel = find_compiled_kernel(model);
    if (!kernel) fail(model + ": no compiled kernel");
    return *kernel;
  }
  const CompiledKernel& kernel_;
  std::vector<double> parameters_, times_, t_, out_;
  std::vector<int> status_, group_;
  std::size_t k_ = 0;
  long used_ = kBatch;
};

enum class Solve { none, lu, inverse };

// The dense Newton-Euler system from the generated ne_system. Solve::none times its assembly
// alone; lu and inverse add the kinematics (every output the generated evaluate gives) and the
// dense solve.
template <class K, Solve method>
class Dense {
 public:
  static constexpr int n = K::ne_size;

  explicit Dense(const ModelData& m)
      : p_(kernel_parameters<K, double>(m)),
        times_(m.times),
        a_(n, n),
        b_(n),
        x_(n),
        inverse_(n, n),
        lu_(n) {}

  bool at(std::size_t k) {
    K::driver_inputs(p_, times_[k], in_);
    bool ok = true;
    if constexpr (method != Solve::none) {
      ok = K::kinematics(p_, in_, s_);
      benchmark::DoNotOptimize(s_);
    }
    ok = K::ne_system(p_, in_, a_.data(), b_.data()) && ok;
    if constexpr (method == Solve::lu) {
      lu_.compute(a_);
      x_ = lu_.solve(b_);
    } else if constexpr (method == Solve::inverse) {
      inverse_ = a_.inverse();
      x_.noalias() = inverse_ * b_;
    }
    benchmark::DoNotOptimize(a_);
    benchmark::DoNotOptimize(b_);
    benchmark::DoNotOptimize(x_);
    benchmark::ClobberMemory();
    return ok;
  }
  bool next() {
    const bool ok = at(k_);
    if (++k_ == times_.size()) k_ = 0;
    return ok;
  }
  const Eigen::VectorXd& solution() const { return x_; }

 private:
  typename K::template Params<double> p_;
  typename K::template Inputs<double> in_;
  typename K::template State<double> s_{};
  std::vector<double> times_;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>
      a_;  // as ne_system fills it
  Eigen::VectorXd b_, x_;
  Eigen::MatrixXd inverse_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  std::size_t k_ = 0;
};

// The numeric reference solver, assembled at the start of the step, then walking the step forth
// and back so that every sample continues from its neighbour.
template <class K>
class Numeric {
 public:
  explicit Numeric(const ModelData& m)
      : solver_(m.model, m.parameters), times_(m.times), row_(column_names(m.model).size()) {
    solver_.assemble(times_[0]);
  }

  bool next() {
    const long last = static_cast<long>(times_.size()) - 1;
    if (k_ + direction_ < 0 || k_ + direction_ > last) direction_ = -direction_;
    k_ += direction_;
    const numeric::Status status = solver_.solve(times_[k_], row_);
    benchmark::DoNotOptimize(row_);
    benchmark::ClobberMemory();
    return status == numeric::Status::ok;
  }
  long index() const { return k_; }
  const std::vector<double>& row() const { return row_; }

 private:
  numeric::ReferenceSolver solver_;
  std::vector<double> times_;
  std::vector<double> row_;
  long k_ = 0, direction_ = 1;
};

// Generated, dense LU, dense inverse and numeric must agree on every driver effort, at the sample
// where the effort is largest, to 1e-9 relative; the float kernel is only reported.
template <class K>
void sanity_check(const ModelData& m) {
  constexpr double tolerance = 1e-9;
  const std::string model = K::name;
  const std::vector<std::string> numeric_columns = column_names(m.model);
  auto find = [&](const char* const* names, int count, const std::string& what) {
    const int i = static_cast<int>(std::find(names, names + count, what) - names);
    if (i == count) fail(model + ": no column or unknown named " + what);
    return i;
  };

  const std::size_t samples = m.times.size();
  Generated<K, double> generated(m);
  Generated<K, float> generated_float(m);
  std::vector<double> row(K::column_count);
  std::vector<float> row_float(K::column_count);
  for (int unknown = 0; unknown < K::ne_size; ++unknown) {
    const std::string name = K::ne_unknowns[unknown];
    if (name.size() < 7 || name.substr(name.size() - 7) != ".effort") continue;
    const int column = find(K::column_names, K::column_count, name);
    const int numeric_column = static_cast<int>(
        std::find(numeric_columns.begin(), numeric_columns.end(), name) - numeric_columns.begin());
    if (numeric_column == static_cast<int>(numeric_columns.size()))
      fail(model + ": the numeric solver has no column " + name);

    // The largest effort over the step (after t0), and the float kernel's worst deviation from
    // double.
    std::size_t probe = 0;
    double largest = -1, float_deviation = 0;
    std::vector<double> effort(samples);
    for (std::size_t k = 0; k < samples; ++k) {
      if (!generated.at(k) || !generated_float.at(k))
        fail(model + "/generated: evaluation failed at t=" + std::to_string(m.times[k]));
      generated.columns(row.data());
      generated_float.columns(row_float.data());
      effort[k] = row[column];
      float_deviation = std::max(float_deviation, std::abs(row_float[column] - effort[k]));
      if (k > 0 && std::abs(effort[k]) > largest) {  // past t0: the numeric solver steps to it
        largest = std::abs(effort[k]);
        probe = k;
      }
    }
    if (!(largest > 0)) fail(model + ": " + name + " is zero over the whole step");

    Dense<K, Solve::lu> lu(m);
    Dense<K, Solve::inverse> inverse(m);
    Numeric<K> solver(m);
    if (!lu.at(probe) || !inverse.at(probe)) fail(model + "/dense: ne_system failed");
    bool numeric_ok = true;
    while (solver.index() != static_cast<long>(probe)) numeric_ok = solver.next() && numeric_ok;
    if (!numeric_ok) fail(model + "/numeric: the reference solver failed along the step");

    const double reference = effort[probe];
    std::fprintf(stderr, "sanity %s: %s at t=%.6g: generated %.15g", model.c_str(), name.c_str(),
                 m.times[probe], reference);
    const std::pair<const char*, double> others[] = {
        {"dense_lu", lu.solution()[unknown]},
        {"dense_inverse", inverse.solution()[unknown]},
        {"numeric", solver.row()[numeric_column]},
    };
    std::string problems;
    for (const auto& [variant, value] : others) {
      const double relative = std::abs(value - reference) / largest;
      std::fprintf(stderr, ", %s %+.1e", variant, relative);
      if (!(relative <= tolerance))
        problems += " " + std::string(variant) + " differs from generated by " +
                    std::to_string(relative) + " relative;";
    }
    std::fprintf(stderr, "; float deviates by up to %.1e relative\n", float_deviation / largest);
    if (!problems.empty()) fail("sanity check failed: " + model + " " + name + ":" + problems);
  }
}

// PASIBOT compiled for x86-64-v3 (bench/pasibot_v3.cpp): a sample at a time along the step.
template <bool kinematics_only>
class GeneratedV3 {
 public:
  explicit GeneratedV3(const ModelData& m) {
    v3::prepare(m.parameters.data(), m.times.data(), m.times.size());
  }
  bool next() {
    double effort;
    return v3::next(kinematics_only, &effort);
  }
};

// PASIBOT's evaluate_batch compiled for x86-64-v3, per sample (blocks of 64, like GeneratedBatch).
class GeneratedBatchV3 {
 public:
  explicit GeneratedBatchV3(const ModelData& m) {
    v3::prepare(m.parameters.data(), m.times.data(), m.times.size());
  }
  bool next() { return v3::next_batch(); }
};

// The x86-64-v3 build's driver effort against the baseline kernel's at every sample of the step:
// the same expressions, contracted into fused multiply-adds, so equal to rounding.
void sanity_check_v3(const ModelData& m) {
  if (!v3::available()) return;
  Generated<pasibot_kernel, double> generated(m);
  v3::prepare(m.parameters.data(), m.times.data(), m.times.size());
  std::vector<double> row(pasibot_kernel::column_count);
  const int column = static_cast<int>(
      std::find(pasibot_kernel::column_names,
                pasibot_kernel::column_names + pasibot_kernel::column_count, "theta8.effort") -
      pasibot_kernel::column_names);
  if (column == pasibot_kernel::column_count) fail("pasibot: no column theta8.effort");
  double largest = 0, deviation = 0;
  for (std::size_t k = 0; k < m.times.size(); ++k) {
    double effort = 0;
    if (!generated.at(k) || !v3::next(false, &effort))
      fail("pasibot/generated_v3: evaluation failed at t=" + std::to_string(m.times[k]));
    generated.columns(row.data());
    largest = std::max(largest, std::abs(row[static_cast<std::size_t>(column)]));
    deviation = std::max(deviation, std::abs(effort - row[static_cast<std::size_t>(column)]));
  }
  // The batch build: the first block of the step against the baseline kernel.
  v3::prepare(m.parameters.data(), m.times.data(), m.times.size());
  double batch_deviation = 0;
  for (std::size_t i = 0; i < v3::batch_block; ++i) {
    if (!v3::next_batch() || !generated.at(i % m.times.size()))
      fail("pasibot/generated_batch_v3: evaluation failed");
    generated.columns(row.data());
    batch_deviation = std::max(batch_deviation, std::abs(v3::batch_output(column, i) -
                                                         row[static_cast<std::size_t>(column)]));
  }
  std::fprintf(stderr,
               "sanity pasibot: generated_v3 deviates by up to %.1e relative, "
               "generated_batch_v3 by %.1e\n",
               deviation / largest, batch_deviation / largest);
  deviation = std::max(deviation, batch_deviation);
  constexpr double tolerance = 1e-9;  // relative to the largest effort, as sanity_check
  if (!(deviation <= tolerance * largest))
    fail("sanity check failed: pasibot/generated_v3 differs from generated by " +
         std::to_string(deviation / largest) + " relative");
}

void sanity_check(const std::string& model) {
  if (model == "pasibot") sanity_check<pasibot_kernel>(model_data(model));
  if (model == "pasibot") sanity_check_v3(model_data(model));
  if (model == "chebyshev") sanity_check<chebyshev_kernel>(model_data(model));
}

// A variant, constructed on first use and kept (the numeric solver continues along its step from
// one benchmark run to the next).
struct Entry {
  std::string name;
  std::string model;
  std::function<void(benchmark::State&)> benchmark;
  std::function<bool(long)> run;  // n samples; false when one failed
};

template <class V>
Entry make_entry(const std::string& model, const std::string& variant) {
  auto holder = std::make_shared<std::unique_ptr<V>>();
  auto get = [holder, model]() -> V& {
    if (!*holder) *holder = std::make_unique<V>(model_data(model));
    return **holder;
  };
  Entry e;
  e.name = model + "/" + variant;
  e.model = model;
  e.benchmark = [get](benchmark::State& state) {
    V& v = get();
    bool ok = true;
    for (auto _ : state) ok = v.next() && ok;
    state.SetItemsProcessed(state.iterations());
    if (!ok) state.SkipWithError("a sample failed");
  };
  e.run = [get](long n) {
    V& v = get();
    bool ok = true;
    for (long i = 0; i < n; ++i) ok = v.next() && ok;
    return ok;
  };
  return e;
}

template <class K>
void add_entries(std::vector<Entry>& entries) {
  const std::string m = K::name;
  entries.push_back(make_entry<Generated<K, double>>(m, "generated"));
  entries.push_back(make_entry<Generated<K, float>>(m, "generated_float"));
  entries.push_back(make_entry<GeneratedBatch<K>>(m, "generated_batch"));
  entries.push_back(make_entry<Generated<K, double, true>>(m, "kinematics"));
  entries.push_back(make_entry<Dense<K, Solve::none>>(m, "ne_system"));
  entries.push_back(make_entry<Dense<K, Solve::lu>>(m, "dense_lu"));
  entries.push_back(make_entry<Dense<K, Solve::inverse>>(m, "dense_inverse"));
  entries.push_back(make_entry<Numeric<K>>(m, "numeric"));
}

std::vector<Entry> all_entries() {
  std::vector<Entry> entries;
  add_entries<pasibot_kernel>(entries);
  if (v3::available()) {
    entries.push_back(make_entry<GeneratedV3<false>>("pasibot", "generated_v3"));
    entries.push_back(make_entry<GeneratedV3<true>>("pasibot", "kinematics_v3"));
    entries.push_back(make_entry<GeneratedBatchV3>("pasibot", "generated_batch_v3"));
  }
  add_entries<chebyshev_kernel>(entries);
  return entries;
}

// mechgen_bench --instructions NAME N
int instructions(int argc, char** argv) {
  if (argc != 4) fail("usage: mechgen_bench --instructions MODEL/VARIANT SAMPLES");
  const std::string name = argv[2];
  char* end = nullptr;
  const long n = std::strtol(argv[3], &end, 10);
  if (*argv[3] == '\0' || *end != '\0' || n < 0) fail(std::string("bad sample count ") + argv[3]);
  for (const Entry& e : all_entries()) {
    if (e.name != name) continue;
    sanity_check(e.model);
    if (!e.run(n)) fail(name + ": a sample failed");
    return EXIT_SUCCESS;
  }
  fail("no variant named " + name);
}

int run(int argc, char** argv) {
  if (argc >= 2 && std::string(argv[1]) == "--instructions") return instructions(argc, argv);
  const std::vector<Entry> entries = all_entries();
  for (const Entry& e : entries)
    benchmark::RegisterBenchmark(e.name.c_str(), e.benchmark)->Unit(benchmark::kNanosecond);
  register_spatial_benchmarks();  // leg6/numeric, leg6/kdl
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return EXIT_FAILURE;
  sanity_check("pasibot");
  sanity_check("chebyshev");
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return EXIT_SUCCESS;
}

}  // namespace
}  // namespace mechgen::bench

int main(int argc, char** argv) {
  try {
    return mechgen::bench::run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mechgen_bench: %s\n", e.what());
    return EXIT_FAILURE;
  }
}
