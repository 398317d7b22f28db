// libFuzzer target: the generated kernel of rsur (a closed spatial chain: five unrolled Newton
// steps from a warm start, Davies' rates, driver effort and every joint reaction through N_s
// transposed) on arbitrary finite parameters, time and warm start (the fuzzer's bytes read as
// doubles; non-finite ones skipped): when evaluate() says ok, every output is finite (reactions
// included), and a failure names a group. A violation aborts (a finding).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "rsur.hpp"

namespace k = mechgen::gen::rsur;

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
  // The first byte: bit 0 keeps the default parameters but the crank speed, bit 1 keeps the
  // assembly as the warm start (mostly reachable configurations either way).
  const unsigned keep = size > 0 ? data[0] : 0;
  if (size > 0) ++data, --size;
  double values[k::parameter_count];
  for (int i = 0; i < k::parameter_count; ++i) values[i] = next(data, size);
  k::Params<double> p;
  k::set_parameters(p, values);
  if (keep & 1) {
    const double w = p.w;
    p = k::Params<double>{};
    p.w = w;
  }
  k::State<double> s;
  // rsur's loop is in closed form: the warm start is its angles' (unwinding).
  constexpr int angles = sizeof s.closure.w / sizeof s.closure.w[0];
  if (!(keep & 2))
    for (int i = 0; i < angles; ++i) s.closure.w[i] = next(data, size);
  const double t = next(data, size);
  k::Inputs<double> in;
  k::driver_inputs(p, t, in);
  double row[k::column_count];
  if (k::evaluate(p, in, s) == k::Status::ok) {
    k::to_columns(in, s, row);
    for (double v : row) require(std::isfinite(v));
  } else {
    require(s.failed_group >= 0 && s.failed_group < k::group_count);
  }
  return 0;
}
