// Walking PASIBOT over several steps (runtime/analysis/walking.hpp), checked against the numeric
// reference solver over one step, against the solver driven by the same ramp, against the work-
// energy balance, and against the seed's stride and hip-height claims.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "analysis/walking.hpp"
#include "model/columns.hpp"
#include "model/spatial_model.hpp"
#include "model/support_model.hpp"
#include "sweep/compiled_kernel.hpp"
#include "sweep/sweep.hpp"

namespace {

using mechgen::Model;
using mechgen::analysis::walk;
using mechgen::analysis::WalkOptions;
using mechgen::analysis::WalkResult;

const Model& pasibot() {
  static const Model model = mechgen::read_model(MECHGEN_SOURCE_DIR "/models/pasibot.yaml");
  return model;
}

double l8() {
  return pasibot().parameters[static_cast<size_t>(pasibot().parameter_index("l8"))].value;
}

size_t col(const WalkResult& w, const std::string& name) {
  const int c = w.column(name);
  EXPECT_GE(c, 0) << name;
  return static_cast<size_t>(std::max(c, 0));
}

// The one-step sweep of the numeric reference solver: the independent expectation.
const mechgen::SweepResult& numeric_step() {
  static const mechgen::SweepResult result = [] {
    mechgen::SweepOptions options = mechgen::default_sweep(pasibot());
    options.solver = "numeric";
    return mechgen::run_sweep(pasibot(), options);
  }();
  return result;
}

double peak_torque() {
  const auto& s = numeric_step();
  const size_t e = static_cast<size_t>(
      std::find(s.columns.begin(), s.columns.end(), "theta8.effort") - s.columns.begin());
  double peak = 0;
  for (const auto& row : s.rows) peak = std::max(peak, std::abs(row[e]));
  return peak;
}

// With a ramp of one step's time T, the walk's q after the ramp is q0 + W (t - T/2): at the
// sample times t = i T / 180 the phase within a step falls on the one-step sweep's samples,
// shifted by 90.
TEST(Walking, SteadyTorqueOfEveryStepEqualsTheOneStepSweepShifted) {
  WalkOptions options;
  options.steps = 5;
  const double step_time = std::numbers::pi / 2;  // pi / w8 at the default w8 = 2 rad/s
  options.ramp = step_time;
  const WalkResult w = walk(pasibot(), options);
  ASSERT_NEAR(w.step_time, step_time, 1e-12);
  const auto& s = numeric_step();
  const size_t se = static_cast<size_t>(
      std::find(s.columns.begin(), s.columns.end(), "theta8.effort") - s.columns.begin());
  const size_t t = col(w, "t"), q = col(w, "theta8.q"), e = col(w, "theta8.effort");
  const double samples = static_cast<double>(s.rows.size() - 1);
  int compared = 0;
  std::vector<int> steps_seen(5, 0);
  for (const auto& row : w.rows) {
    if (row[t] < options.ramp) continue;
    const double k = row[col(w, "step")];
    const double index =
        (row[q] - std::numbers::pi / 2 - k * w.step_angle) / w.step_angle * samples;
    const long j = std::lround(index);
    ASSERT_NEAR(index, static_cast<double>(j), 1e-6) << "t = " << row[t];
    EXPECT_NEAR(row[e], s.rows[static_cast<size_t>(j)][se], 1e-9 * peak_torque())
        << "t = " << row[t] << ", step " << row[col(w, "step")];
    ++steps_seen[static_cast<size_t>(row[col(w, "step")])];
    ++compared;
  }
  EXPECT_GT(compared, 4 * 180);
  for (int k = 1; k < 5; ++k) EXPECT_GE(steps_seen[static_cast<size_t>(k)], 180) << k;
}

// The joint forces too: in an even step every joint carries what it carries in the one-step
// sweep of the numeric solver at the same phase; in an odd step (legs swapped) what its mirror
// carries there. The pairs are PASIBOT's names, written out by hand (support leg, flying leg).
TEST(Walking, SteadyJointForcesAreTheOneStepSweepsWithTheLegsSwappedEveryOtherStep) {
  WalkOptions options;
  options.steps = 4;
  const double step_time = std::numbers::pi / 2;
  options.ramp = step_time;
  const WalkResult w = walk(pasibot(), options);
  const auto& s = numeric_step();
  auto sweep_col = [&](const std::string& name) {
    const auto it = std::find(s.columns.begin(), s.columns.end(), name);
    EXPECT_NE(it, s.columns.end()) << name;
    return static_cast<size_t>(it - s.columns.begin());
  };
  const std::vector<std::pair<std::string, std::string>> pairs = {
      {"A_13_8", "A_13_8"},     {"B_13_9", "B_13_9p"},     {"P_8_7", "Pp_8_7p"},
      {"M_9_7", "Mp_9p_7p"},    {"C_7_3", "Cp_7p_3p"},     {"D_13_6", "D_13_6p"},
      {"S_13_10", "Sp_13_10p"}, {"R_12_11", "Rp_12p_11p"}, {"E_2_1", "Ep_2p_1p"},
      {"F_11_1", "Fp_11p_1p"}};
  double scale = 0;
  for (const auto& row : s.rows)
    for (const auto& [a, b] : pairs) scale = std::max(scale, std::abs(row[sweep_col(a + ".fx")]));
  const size_t t = col(w, "t"), q = col(w, "theta8.q");
  const double samples = static_cast<double>(s.rows.size() - 1);
  int compared = 0;
  for (const auto& row : w.rows) {
    if (row[t] < options.ramp) continue;
    const int k = static_cast<int>(row[col(w, "step")]);
    const long j =
        std::lround((row[q] - std::numbers::pi / 2 - k * w.step_angle) / w.step_angle * samples);
    const auto& expected = s.rows[static_cast<size_t>(j)];
    for (const auto& [support, flying] : pairs)
      for (int side = 0; side < 2; ++side) {
        const std::string& name = side == 0 ? support : flying;
        const std::string& source = k % 2 == 0 ? name : (side == 0 ? flying : support);
        for (const char* c : {".fx", ".fy"})
          EXPECT_NEAR(row[col(w, name + c)], expected[sweep_col(source + c)], 1e-9 * scale)
              << name << c << " at t = " << row[t] << ", step " << k;
      }
    ++compared;
  }
  EXPECT_GT(compared, 3 * 180);
}

// During the ramp the kernel, fed (q, qd, qdd) directly, agrees with the numeric reference
// solver driven by the same ramp written as the model's own driver expression.
TEST(Walking, RampTorqueEqualsTheNumericSolverDrivenByTheSameRamp) {
  WalkOptions options;
  options.steps = 1;
  options.ramp = 1.2;
  const WalkResult w = walk(pasibot(), options);

  Model ramped = pasibot();
  mechgen::Driver& driver = ramped.drivers.front();
  const GiNaC::symbol& t = ramped.t;
  const GiNaC::symbol& w8 =
      ramped.parameters[static_cast<size_t>(ramped.parameter_index("w8"))].symbol;
  const GiNaC::ex u = t / options.ramp;
  driver.value.ex = GiNaC::Pi / 2 + w8 * options.ramp *
                                        (GiNaC::numeric(5, 2) * GiNaC::pow(u, 4) -
                                         3 * GiNaC::pow(u, 5) + GiNaC::pow(u, 6));
  driver.value_d = driver.value.ex.diff(t);
  driver.value_dd = driver.value_d.diff(t);
  // The numeric solver on the walk's own sample times (i T / 180) up to the end of the ramp.
  const double dt = w.step_time / 180;
  const int n = static_cast<int>(std::floor(options.ramp / dt));
  mechgen::SweepOptions sweep = mechgen::default_sweep(ramped);
  sweep.solver = "numeric";
  sweep.t0 = 0;
  sweep.t1 = n * dt;
  sweep.samples = n + 1;
  const mechgen::SweepResult numeric = mechgen::run_sweep(ramped, sweep);
  const size_t ne = static_cast<size_t>(
      std::find(numeric.columns.begin(), numeric.columns.end(), "theta8.effort") -
      numeric.columns.begin());
  const size_t nq = ne - 3;
  const size_t wt = col(w, "t"), wq = col(w, "theta8.q"), we = col(w, "theta8.effort");
  int compared = 0;
  for (size_t i = 0; i < numeric.rows.size(); ++i) {
    const auto& nrow = numeric.rows[i];
    const auto& row = w.rows[i];
    ASSERT_NEAR(row[wt], nrow[0], 1e-12);
    // The solver's driver motion is the walk's ramp, exactly.
    const mechgen::analysis::DriverMotion m =
        mechgen::analysis::ramped_motion(std::numbers::pi / 2, 2.0, options.ramp, nrow[0]);
    EXPECT_NEAR(nrow[nq], m.q, 1e-12);
    EXPECT_NEAR(nrow[nq + 1], m.qd, 1e-12);
    EXPECT_NEAR(nrow[nq + 2], m.qdd, 1e-12);
    EXPECT_NEAR(row[wq], m.q, 1e-12);
    EXPECT_NEAR(row[we], nrow[ne], 1e-9 * peak_torque()) << "t = " << nrow[0];
    ++compared;
  }
  EXPECT_GT(compared, 130);
}

// During the ramp the torque differs from the steady torque at the same crank angle (the
// acceleration of the links costs torque), the difference vanishes as the speed settles, and the
// work of the motor equals the change of kinetic and potential energy (no losses in the model).
TEST(Walking, RampTorqueDiffersThenSettlesAndBalancesTheEnergy) {
  WalkOptions options;
  options.steps = 2;
  options.ramp = 0.8;
  options.samples_per_step = 1801;
  const WalkResult w = walk(pasibot(), options);
  WalkOptions steady = options;
  steady.ramp = 0;
  const WalkResult s = walk(pasibot(), steady);
  const size_t t = col(w, "t"), q = col(w, "theta8.q"), qd = col(w, "theta8.qd"),
               e = col(w, "theta8.effort");

  // Steady torque at the walk's crank angle and support foot: the steady walk interpolated at
  // time (q - q0) / W, on the same step (at a support change the two feet give two torques).
  const size_t step = col(w, "step");
  auto steady_torque = [&](double angle, double k) {
    const double ts = (angle - std::numbers::pi / 2) / s.speed;
    const auto found = std::lower_bound(
        s.rows.begin(), s.rows.end(), ts,
        [&](const auto& row, double v) { return row[step] < k || (row[step] == k && row[t] < v); });
    auto it = found;
    if (it == s.rows.end() || (*it)[step] != k) --it;  // past the step's last sample: its last
    const auto& b = *it;
    const bool first_of_step = it == s.rows.begin() || (*(it - 1))[step] != k;
    const auto& a = *(first_of_step ? it : it - 1);
    const double f = b[t] > a[t] ? (ts - a[t]) / (b[t] - a[t]) : 0;
    return a[e] + f * (b[e] - a[e]);
  };
  double largest = 0, at_end = 0;
  for (const auto& row : w.rows) {
    const double diff = std::abs(row[e] - steady_torque(row[q], row[step]));
    if (row[t] < options.ramp) largest = std::max(largest, diff);
    if (row[t] >= options.ramp * 0.98 && row[t] <= options.ramp) at_end = std::max(at_end, diff);
    if (row[t] >= options.ramp) {
      EXPECT_NEAR(diff, 0, 1e-5 * peak_torque()) << row[t];
    }
  }
  EXPECT_GT(largest, 0.05 * peak_torque());
  EXPECT_LT(at_end, 0.02 * largest);

  // Work-energy balance over the ramp (Simpson's rule on the finely sampled motor power).
  const Model& m = pasibot();
  const GiNaC::exmap subs = m.substitutions(m.default_parameters());
  auto energy = [&](const std::vector<double>& row) {
    double total = 0;
    for (const mechgen::Body& body : m.bodies) {
      if (body.ground) continue;  // the support foot: at rest on the floor
      const double mass = m.evaluate(body.mass.mass, subs);
      const double inertia = m.evaluate(body.mass.inertia, subs);
      const size_t b = col(w, body.name + ".x");
      total += 0.5 * mass * (row[b + 3] * row[b + 3] + row[b + 4] * row[b + 4]) +
               0.5 * inertia * row[b + 5] * row[b + 5] + mass * 9.81 * row[b + 1];
    }
    return total;
  };
  std::vector<const std::vector<double>*> ramp_rows;
  for (const auto& row : w.rows)
    if (row[t] <= options.ramp + 1e-12) ramp_rows.push_back(&row);
  // Simpson needs an even number of equal intervals: stop at the last such sample.
  if (ramp_rows.size() % 2 == 0) ramp_rows.pop_back();
  ASSERT_GE(ramp_rows.size(), 101u);
  const double h = (*ramp_rows[1])[t] - (*ramp_rows[0])[t];
  double work = 0, absolute = 0;
  for (size_t i = 0; i < ramp_rows.size(); ++i) {
    const double weight = i == 0 || i + 1 == ramp_rows.size() ? 1 : i % 2 ? 4 : 2;
    const double power = (*ramp_rows[i])[e] * (*ramp_rows[i])[qd];
    work += weight * power * h / 3;
    absolute += weight * std::abs(power) * h / 3;
  }
  const double change = energy(*ramp_rows.back()) - energy(*ramp_rows.front());
  EXPECT_NEAR(work, change, 1e-6 * absolute) << "work " << work << " J, |work| " << absolute;
}

// At each support change the hip's world position, angle and velocity are the same for the
// old support foot and the new one.
TEST(Walking, HipWorldTrajectoryIsContinuousAcrossSupportChanges) {
  WalkOptions options;
  options.steps = 4;
  options.ramp = 2.0;  // the first change falls inside the ramp, the others after it
  const WalkResult w = walk(pasibot(), options);
  const size_t t = col(w, "t"), step = col(w, "step"), hip = col(w, "l13.x");
  int changes = 0;
  double speed = 0;
  for (const auto& row : w.rows) speed = std::max(speed, std::hypot(row[hip + 3], row[hip + 4]));
  for (size_t i = 1; i < w.rows.size(); ++i) {
    const auto &a = w.rows[i - 1], &b = w.rows[i];
    if (b[step] == a[step]) continue;
    ++changes;
    EXPECT_EQ(a[t], b[t]);
    EXPECT_NEAR(a[hip], b[hip], 1e-12) << "x at change " << changes;
    EXPECT_NEAR(a[hip + 1], b[hip + 1], 1e-12) << "y at change " << changes;
    EXPECT_NEAR(std::remainder(a[hip + 2] - b[hip + 2], 2 * std::numbers::pi), 0, 1e-12);
    EXPECT_NEAR(a[hip + 3], b[hip + 3], 1e-9 * speed) << "vx at change " << changes;
    EXPECT_NEAR(a[hip + 4], b[hip + 4], 1e-9 * speed) << "vy at change " << changes;
    // The new support foot is where the old flying foot landed: at rest, level, on the floor.
    const size_t foot = col(w, (static_cast<int>(b[step]) % 2 ? "l1p" : "l1") + std::string(".x"));
    EXPECT_NEAR(a[foot + 1], b[foot + 1], 1e-12);
    EXPECT_NEAR(a[foot + 2], 0, 1e-12);
    EXPECT_NEAR(std::hypot(a[foot + 3], a[foot + 4]), 0, 1e-9 * speed);
  }
  EXPECT_EQ(changes, 3);
}

// Seed: the stride is 8 l8 per step, and the hip height varies by less than 0.5 % over a support
// phase (tests/kernel_test.cpp checks neither).
TEST(Walking, StrideIsEightCrankLengthsAndTheHipStaysLevel) {
  WalkOptions options;
  options.steps = 4;
  const WalkResult w = walk(pasibot(), options);
  const double stride = 8 * l8();
  for (size_t k = 0; k < w.support_x.size(); ++k)
    EXPECT_NEAR(w.support_x[k], static_cast<double>(k) * stride, 1e-12);
  const size_t step = col(w, "step"), ax = col(w, "A.x"), ay = col(w, "A.y");
  const size_t hip_y = col(w, "l13.y"), e1 = col(w, "E.x"), e2 = col(w, "Ep.x");
  for (int k = 0; k < options.steps; ++k) {
    double x0 = NAN, x1 = NAN, lo = INFINITY, hi = -INFINITY, com_lo = INFINITY, com_hi = -INFINITY;
    for (const auto& row : w.rows) {
      if (static_cast<int>(row[step]) != k) continue;
      if (std::isnan(x0)) x0 = row[ax];
      x1 = row[ax];
      lo = std::min(lo, row[ay]), hi = std::max(hi, row[ay]);
      com_lo = std::min(com_lo, row[hip_y]), com_hi = std::max(com_hi, row[hip_y]);
      // The support foot does not move.
      EXPECT_NEAR(row[k % 2 ? e2 : e1], static_cast<double>(k) * stride, 1e-12);
    }
    EXPECT_NEAR(x1 - x0, stride, 1e-12) << "hip travel of step " << k;
    EXPECT_LT((hi - lo) / hi, 0.005) << "crank axis height, step " << k;
    EXPECT_LT((com_hi - com_lo) / com_hi, 0.005) << "hip centre of mass height, step " << k;
    EXPECT_GT(hi - lo, 0) << "a real variation, not a constant";
  }
}

TEST(Walking, RampedMotionIsConsistent) {
  // q, qd, qdd of the ramp are each other's derivatives (central differences) and continuous at
  // the ramp's end.
  const double ramp = 0.7, w8 = 2;
  for (double t : {0.05, 0.2, 0.35, 0.5, 0.69}) {
    const double h = 1e-5;
    const auto a = mechgen::analysis::ramped_motion(1, w8, ramp, t - h);
    const auto b = mechgen::analysis::ramped_motion(1, w8, ramp, t);
    const auto c = mechgen::analysis::ramped_motion(1, w8, ramp, t + h);
    EXPECT_NEAR((c.q - a.q) / (2 * h), b.qd, 1e-8);
    EXPECT_NEAR((c.qd - a.qd) / (2 * h), b.qdd, 1e-7);
  }
  const auto end = mechgen::analysis::ramped_motion(1, w8, ramp, ramp);
  const auto before = mechgen::analysis::ramped_motion(1, w8, ramp, ramp * (1 - 1e-9));
  EXPECT_NEAR(end.q, 1 + w8 * ramp / 2, 1e-12);
  EXPECT_NEAR(before.q, end.q, 1e-8);
  EXPECT_NEAR(before.qd, w8, 1e-8);
  EXPECT_NEAR(before.qdd, 0, 1e-6);
}

TEST(Walking, BadRequestsAreClearErrors) {
  WalkOptions options;
  options.steps = 0;
  EXPECT_THROW(walk(pasibot(), options), mechgen::ModelError);
  options.steps = 2;
  options.mirror_suffix = "_mirror";
  try {
    walk(pasibot(), options);
    FAIL() << "no mirror foot, no walk";
  } catch (const mechgen::ModelError& error) {
    EXPECT_NE(std::string(error.what()).find("has no mirror 'l1_mirror'"), std::string::npos)
        << error.what();
  }
}

}  // namespace

namespace {

// The driven entry point of every compiled kernel, fed the model's own motion, gives the model's
// own row: the (q, qd, qdd) array maps onto the right Inputs fields.
TEST(CompiledKernels, DrivenEntryFedTheOwnMotionGivesTheOwnRow) {
  for (const std::string& name : mechgen::compiled_kernel_models()) {
    SCOPED_TRACE(name);
    if (mechgen::split_support_model_name(name)) continue;  // tests/support_kernel_test.cpp
    const std::string path = MECHGEN_SOURCE_DIR "/models/" + name + ".yaml";
    if (mechgen::is_spatial_description(path)) continue;  // tests/spatial_kernel_test.cpp
    const mechgen::CompiledKernel& kernel = *mechgen::find_compiled_kernel(name);
    const Model model = mechgen::read_model(path);
    const std::vector<double> parameters = model.default_parameters();
    const mechgen::ColumnLayout layout = mechgen::column_layout(model);
    ASSERT_EQ(kernel.driver_count, static_cast<int>(model.drivers.size()));
    std::vector<double> own(static_cast<size_t>(kernel.column_count)), driven = own;
    for (double t : {0.1, 0.4, 0.9}) {
      int group = -1;
      ASSERT_EQ(kernel.evaluate_double(parameters.data(), t, own.data(), &group), 0);
      std::vector<double> drivers;
      for (int d : layout.driver)
        for (int k = 0; k < 3; ++k) drivers.push_back(own[static_cast<size_t>(d + k)]);
      ASSERT_EQ(kernel.evaluate_driven_double(parameters.data(), t, drivers.data(), driven.data(),
                                              &group),
                0);
      for (size_t c = 0; c < own.size(); ++c)
        EXPECT_EQ(driven[c], own[c]) << kernel.column_names[c];
    }
  }
}

}  // namespace
