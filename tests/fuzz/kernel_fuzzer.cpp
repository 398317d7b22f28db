// libFuzzer target: the slider-crank's generated kernel (springs, a prismatic joint, applied loads;
// PASIBOT's kernel takes over ten minutes to compile under the fuzzer's sanitizers, and
// kernel_finite_test covers every model) on arbitrary finite parameters and inputs (the
// fuzzer's bytes read as doubles; non-finite ones skipped): when evaluate() says ok, every output
// is finite, and evaluate_batch agrees sample by sample. A violation aborts (a finding).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "slider_crank.hpp"

namespace k = mechgen::gen::slider_crank;

namespace {

// The next finite double from the input (0 when it runs out).
double next(const uint8_t*& data, size_t& size) {
  while (size >= sizeof(double)) {
    double value;
    std::memcpy(&value, data, sizeof value);
    data += sizeof value;
    size -= sizeof value;
    if (std::isfinite(value)) return value;
  }
  return 0;
}

void require(bool condition) {
  if (!condition) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  double values[k::parameter_count];
  k::Params<double> defaults;
  k::Params<double> p;
  // The first byte picks which parameters keep their defaults (more reachable configurations).
  const unsigned keep = size > 0 ? data[0] : 0;
  if (size > 0) ++data, --size;
  for (int i = 0; i < k::parameter_count; ++i) values[i] = next(data, size);
  k::set_parameters(p, values);
  if (keep & 1) {  // the defaults but the crank speed: mostly reachable configurations
    const double w = p.w;
    p = defaults;
    p.w = w;
  }
  const double t = next(data, size);
  k::Inputs<double> in;
  k::driver_inputs(p, t, in);
  k::State<double> s;
  double row[k::column_count];
  const k::Status status = k::evaluate(p, in, s);
  if (status == k::Status::ok) {
    k::to_columns(in, s, row);
    for (double v : row) require(std::isfinite(v));
  } else {
    require(s.failed_group >= 0 && s.failed_group < k::group_count);
  }
  double storage[k::batch_storage_per_sample], failure = 0;
  k::BatchInputs<double> batch;
  k::batch_driver_inputs(p, &t, 1, storage, batch);
  k::evaluate_batch(p, batch, 1, row, 1, &failure);
  if (failure == 0)
    for (double v : row) require(std::isfinite(v));
  return 0;
}
