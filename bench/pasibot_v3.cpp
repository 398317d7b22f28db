// Compiled with -march=x86-64-v3 when the compiler takes it (bench/CMakeLists.txt defines
// MECHGEN_BENCH_V3 then); nothing here runs on a processor without AVX2 and FMA.
#include "pasibot_v3.hpp"

#include <cmath>
#include <limits>
#include <vector>

#if MECHGEN_BENCH_V3
// Compiled here, for this instruction set: not the baseline instances mechgen_kernels links.
#undef MECHGEN_LINKED_KERNELS
// The kernel in a namespace of its own: the same templates compiled with other flags must not
// share their (mangled) names with the baseline instantiations of mechgen_bench.cpp, or the
// linker would keep one of the two (the standard headers above are already included, so the
// kernel's own includes add nothing inside the namespace).
namespace mechgen_v3 {
#include "pasibot/pasibot.hpp"
}  // namespace mechgen_v3
#endif

namespace mechgen::bench::v3 {

#if MECHGEN_BENCH_V3
namespace {
namespace kernel = mechgen_v3::mechgen::gen::pasibot;
struct Samples {
  kernel::Params<double> p;
  kernel::Inputs<double> in;
  kernel::State<double> s{};
  std::vector<double> times;
  std::size_t k = 0;
  // evaluate_batch's blocks: inputs, driver storage, outputs (column-major), failure codes
  std::vector<double> block_t, storage, out, failure;
  std::size_t used = batch_block;
};
Samples& samples() {
  static Samples instance;
  return instance;
}
}  // namespace

bool available() {
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}

void prepare(const double* parameters, const double* times, std::size_t count) {
  Samples& m = samples();
  kernel::set_parameters(m.p, parameters);
  m.times.assign(times, times + count);
  m.k = 0;
  m.block_t.assign(batch_block, 0);
  m.storage.assign(kernel::batch_storage_per_sample * batch_block + 1, 0);
  m.out.assign(kernel::column_count * batch_block, 0);
  m.failure.assign(batch_block, 0);
  m.used = batch_block;
}

bool next_batch() {
  Samples& m = samples();
  if (m.used == batch_block) {
    for (double& t : m.block_t) {
      t = m.times[m.k];
      if (++m.k == m.times.size()) m.k = 0;
    }
    kernel::BatchInputs<double> batch;
    kernel::batch_driver_inputs(m.p, m.block_t.data(), static_cast<long>(batch_block),
                                m.storage.data(), batch);
    kernel::evaluate_batch(m.p, batch, static_cast<long>(batch_block), m.out.data(),
                           static_cast<long>(batch_block), m.failure.data());
    asm volatile("" : : "r"(m.out.data()) : "memory");
    m.used = 0;
  }
  return m.failure[m.used++] == 0;
}

double batch_output(int column, std::size_t i) {
  return samples().out[static_cast<std::size_t>(column) * batch_block + i];
}

bool next(bool kinematics_only, double* effort) {
  Samples& m = samples();
  kernel::driver_inputs(m.p, m.times[m.k], m.in);
  if (++m.k == m.times.size()) m.k = 0;
  const kernel::Status status =
      kinematics_only ? kernel::kinematics(m.p, m.in, m.s) : kernel::evaluate(m.p, m.in, m.s);
  // Keeps every output: the compiler may not drop what nobody reads.
  asm volatile("" : : "r"(&m.s) : "memory");
  *effort = m.s.drivers.theta8.effort;
  return status == kernel::Status::ok;
}
#else
bool available() {
  return false;
}
void prepare(const double*, const double*, std::size_t) {}
bool next_batch() {
  return false;
}
bool next(bool, double*) {
  return false;
}
#endif

}  // namespace mechgen::bench::v3
