// evaluate_batch against evaluate, sample by sample: every output column to 1e-12 (relative to
// the column's largest magnitude over the sweep) and every failure status and group, on a
// PASIBOT sweep over two crank turns and on a slider-crank sweep that leaves its reachable range.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "pasibot/pasibot.hpp"
#include "slider_crank/slider_crank.hpp"

namespace {

namespace pb = mechgen::gen::pasibot;
namespace sc = mechgen::gen::slider_crank;

// A kernel's namespace constants; its functions are found by argument-dependent lookup.
struct PasibotKernel {
  static constexpr int columns = pb::column_count, storage = pb::batch_storage_per_sample;
  using Inputs = pb::Inputs<double>;
  using State = pb::State<double>;
  using Batch = pb::BatchInputs<double>;
  static pb::Status status(double failure) { return pb::batch_status(failure); }
  static int group(double failure) { return pb::batch_failed_group(failure); }
};
struct SliderCrankKernel {
  static constexpr int columns = sc::column_count, storage = sc::batch_storage_per_sample;
  using Inputs = sc::Inputs<double>;
  using State = sc::State<double>;
  using Batch = sc::BatchInputs<double>;
  static sc::Status status(double failure) { return sc::batch_status(failure); }
  static int group(double failure) { return sc::batch_failed_group(failure); }
};

struct Comparison {
  double worst = 0;           // largest |batch - scalar| / the column's largest |scalar|
  int mismatched_status = 0;  // samples whose status or failed group differ
  int failed = 0;             // samples that failed (in the scalar entry)
};

template <class K, class Params>
Comparison compare(const Params& p, const std::vector<double>& times) {
  const long n = static_cast<long>(times.size());
  const size_t columns = static_cast<size_t>(K::columns), samples = times.size();
  std::vector<double> storage(static_cast<size_t>(K::storage) * samples);
  std::vector<double> out(columns * samples), failure(samples);
  typename K::Batch batch;
  batch_driver_inputs(p, times.data(), n, storage.data(), batch);
  evaluate_batch(p, batch, n, out.data(), n, failure.data());

  Comparison result;
  std::vector<double> rows(columns * samples), scale(columns, 0.0);
  std::vector<bool> ok(samples);
  for (size_t i = 0; i < samples; ++i) {
    typename K::Inputs in;
    driver_inputs(p, times[i], in);
    typename K::State s;
    const auto status = evaluate(p, in, s);
    if (status != K::status(failure[i]) ||
        (static_cast<int>(status) != 0 && s.failed_group != K::group(failure[i])))
      ++result.mismatched_status;
    ok[i] = static_cast<int>(status) == 0;
    if (!ok[i]) {
      ++result.failed;
      continue;
    }
    to_columns(in, s, &rows[i * columns]);
    for (size_t c = 0; c < columns; ++c)
      scale[c] = std::max(scale[c], std::abs(rows[i * columns + c]));
  }
  for (size_t i = 0; i < samples; ++i) {
    if (!ok[i]) continue;
    for (size_t c = 0; c < columns; ++c) {
      const double deviation = std::abs(out[c * samples + i] - rows[i * columns + c]);
      result.worst = std::max(result.worst, deviation / std::max(scale[c], 1e-300));
    }
  }
  return result;
}

TEST(KernelBatch, PasibotBatchEqualsScalarOverTwoTurns) {
  const pb::Params<double> p;
  std::vector<double> times;
  const double period = 2 * M_PI / p.w8;
  for (int i = 0; i < 1001; ++i) times.push_back(2 * period * i / 1000);  // odd n: a remainder
  const Comparison r = compare<PasibotKernel>(p, times);
  EXPECT_EQ(r.failed, 0);
  EXPECT_EQ(r.mismatched_status, 0);
  EXPECT_LE(r.worst, 1e-12);
}

// r = 1.2 L: the rod reaches the slider's line only while |r sin| < L, so part of the turn fails;
// the batch reports the same status and group there and the same values elsewhere.
TEST(KernelBatch, SliderCrankFailuresMatchScalar) {
  sc::Params<double> p;
  p.r = 1.2 * p.L;
  std::vector<double> times;
  const double period = 2 * M_PI / p.w;
  for (int i = 0; i < 257; ++i) times.push_back(period * i / 256);
  const Comparison r = compare<SliderCrankKernel>(p, times);
  EXPECT_GT(r.failed, 10);
  EXPECT_LT(r.failed, 257);
  EXPECT_EQ(r.mismatched_status, 0);
  EXPECT_LE(r.worst, 1e-12);
}

// A non-finite driver input fails the sample as unreachable in the "inputs" stage, as evaluate()
// does.
TEST(KernelBatch, NonFiniteInputIsUnreachable) {
  const pb::Params<double> p;
  const double t[2] = {0.1, 0.2};
  double storage[2 * pb::batch_storage_per_sample], failure[2];
  std::vector<double> out(2 * pb::column_count);
  pb::BatchInputs<double> batch;
  pb::batch_driver_inputs(p, t, 2, storage, batch);
  storage[1] = std::nan("");  // theta8 of the second sample
  pb::evaluate_batch(p, batch, 2, out.data(), 2, failure);
  EXPECT_EQ(failure[0], 0.0);
  EXPECT_EQ(pb::batch_status(failure[1]), pb::Status::unreachable);
  ASSERT_GE(pb::batch_failed_group(failure[1]), 0);
  EXPECT_STREQ(pb::group_names[pb::batch_failed_group(failure[1])], "inputs");
  pb::Inputs<double> in;
  pb::driver_inputs(p, 0.2, in);
  in.theta8 = std::nan("");
  pb::State<double> s;
  EXPECT_EQ(pb::evaluate(p, in, s), pb::Status::unreachable);
  EXPECT_STREQ(pb::group_names[s.failed_group], "inputs");
}

// Finite inputs whose outputs overflow (a crank speed of 1e200 rad/s): non_finite, naming the
// first stage that overflows, in evaluate() and evaluate_batch alike (ok before, with NaN out).
TEST(KernelBatch, OverflowIsNonFiniteNamingTheStage) {
  pb::Params<double> p;
  p.w8 = 1e200;
  const double t[2] = {0.0, 0.2};  // at t = 0 the crank angle is pi/2: only the rates overflow
  double storage[2 * pb::batch_storage_per_sample], failure[2];
  std::vector<double> out(2 * pb::column_count);
  pb::BatchInputs<double> batch;
  pb::batch_driver_inputs(p, t, 2, storage, batch);
  pb::evaluate_batch(p, batch, 2, out.data(), 2, failure);
  pb::Inputs<double> in;
  pb::driver_inputs(p, t[0], in);
  pb::State<double> s;
  ASSERT_EQ(pb::evaluate(p, in, s), pb::Status::non_finite);
  EXPECT_STREQ(pb::group_names[s.failed_group], "rates");  // w^2 terms overflow first
  EXPECT_EQ(pb::batch_status(failure[0]), pb::Status::non_finite);
  EXPECT_EQ(pb::batch_failed_group(failure[0]), s.failed_group);
  EXPECT_EQ(pb::kinematics(p, in, s), pb::Status::non_finite);
  std::vector<double> A(pb::ne_size * pb::ne_size), b(pb::ne_size);
  EXPECT_EQ(pb::ne_system(p, in, A.data(), b.data()), pb::Status::non_finite);
}

// The kernels' own atan2, sin and cos against the C library: within 2e-16 absolute for the angle
// (atan2 in [-pi, pi]) and for sin, cos of |x| up to 1e6 rad, and the C library's quadrant and
// sign conventions on the axes.
TEST(KernelMath, AgreesWithTheCLibrary) {
  namespace d = pb::detail;
  double worst_atan2 = 0, worst_sincos = 0;
  for (int i = 0; i < 20000; ++i) {
    const double angle = -M_PI + 2 * M_PI * (i + 0.5) / 20000;
    for (double radius : {1e-3, 1.0, 7e4}) {
      const double y = radius * std::sin(angle), x = radius * std::cos(angle);
      worst_atan2 = std::max(worst_atan2, std::abs(d::atan2(y, x) - std::atan2(y, x)));
    }
    for (double scale : {1.0, 1e3, 1e6}) {
      const double x = scale * angle;
      double s = 0, c = 0;
      d::sincos(x, s, c);
      worst_sincos = std::max({worst_sincos, std::abs(s - std::sin(x)), std::abs(c - std::cos(x))});
    }
  }
  EXPECT_LE(worst_atan2, 4.5e-16);  // two ulp of pi
  EXPECT_LE(worst_sincos, 2.3e-16);
  EXPECT_GT(worst_atan2 + worst_sincos, 0.0);  // really another implementation
  for (const auto& [y, x] : std::vector<std::pair<double, double>>{{0.0, 1.0},
                                                                   {-0.0, 1.0},
                                                                   {0.0, -1.0},
                                                                   {-0.0, -1.0},
                                                                   {1.0, 0.0},
                                                                   {-1.0, 0.0},
                                                                   {1.0, 1.0},
                                                                   {-1.0, -1.0},
                                                                   {0.0, 0.0},
                                                                   {2.0, -2.0}})
    EXPECT_EQ(d::atan2(y, x), std::atan2(y, x)) << y << ", " << x;
}

}  // namespace
