// The walking example (examples/walking, built as its own CMake project by tests/CMakeLists.txt)
// checked from its joint angle stream: walking_example_test STREAM.csv. The lecture's pattern and
// abstract kinematics are written again here in double (seed 003, ../shared/seeds/003_*.txt); the
// stream's joint angles go back through the generated FK of models/lecture_leg.yaml in double, and
// the foot path must be the pattern's own closed form (ankle at 2 l eta from the hip, at the leg
// angle theta_leg from -y; the toe f ahead of it, the sole level), the legs in antiphase, and the
// swing and stance phases each half a cycle at the ticks the phase says.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "lecture_leg/lecture_leg.hpp"

namespace {

namespace k = mechgen::gen::lecture_leg;
using std::numbers::pi;

std::string stream_path;

// The example's settings (examples/walking/walking.cpp), restated: 1 kHz, a 1 s gait cycle,
// S = 0.25 rad, C1 = 0.1, eta0 = 0.9, C2 levelling the stance hip, 3 s; the model's l and f.
constexpr int cycle = 1000;
constexpr int rate = 1000;
constexpr long rows_expected = 3001;
constexpr double S = 0.25, C1 = 0.1, eta0 = 0.9;
const double C2 = eta0 * (std::cos(S) - 1);
constexpr double l = 0.2, f = 0.08;
// Float stream against double expectations.
constexpr double tolerance = 1e-5;

// The lecture: leg lifting and leg swing, piecewise in mu in [-pi, pi); swing for mu < 0.
double extension(double mu) {
  return eta0 + (mu < 0 ? C1 * std::sin(mu) : C2 * std::sin(mu));
}
double leg_angle(double mu) {
  return mu < 0 ? S * (2 * mu + pi) / pi : S * std::cos(mu);
}
// The phase of each leg at tick n: the right leg touches down at t = 0 (mu = 0), the left one
// lifts off then (mu = -pi).
double phase(long n, int leg) {
  const long shifted = (n + (leg == 0 ? cycle / 2 : 0)) % cycle;
  return -pi + 2 * pi * static_cast<double>(shifted) / cycle;
}
bool in_swing(long n, int leg) {
  return phase(n, leg) < 0;
}

struct Stream {
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;
  size_t column(const std::string& name) const {
    for (size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return i;
    ADD_FAILURE() << "no column " << name;
    return 0;
  }
};

const Stream& stream() {
  static const Stream s = [] {
    Stream s;
    std::ifstream in(stream_path);
    EXPECT_TRUE(in) << stream_path;
    std::string line, cell;
    std::getline(in, line);
    for (std::istringstream header(line); std::getline(header, cell, ',');) s.names.push_back(cell);
    while (std::getline(in, line)) {
      std::vector<double> row;
      for (std::istringstream cells(line); std::getline(cells, cell, ',');)
        row.push_back(std::stod(cell));
      EXPECT_EQ(row.size(), s.names.size()) << line;
      s.rows.push_back(row);
    }
    return s;
  }();
  return s;
}

const char* const legs[] = {"right", "left"};

double at(long n, int leg, const char* quantity) {
  const Stream& s = stream();
  return s.rows[static_cast<size_t>(n)][s.column(std::string(legs[leg]) + "." + quantity)];
}

// The generated FK in double of the stream's joint angles.
k::State<double> fk(long n, int leg) {
  k::Inputs<double> in;
  in.q1 = at(n, leg, "q1"), in.q2 = at(n, leg, "q2"), in.q3 = at(n, leg, "q3");
  k::State<double> s;
  EXPECT_EQ(k::kinematics(k::Params<double>{}, in, s), k::Status::ok);
  return s;
}

TEST(WalkingExample, StreamHasOneRowPerMillisecond) {
  const Stream& s = stream();
  ASSERT_EQ(static_cast<long>(s.rows.size()), rows_expected);
  ASSERT_EQ(s.names.size(), 21u);
  for (size_t n = 0; n < s.rows.size(); ++n)
    EXPECT_NEAR(s.rows[n][s.column("t")], static_cast<double>(n) / rate, 1e-12);
}

TEST(WalkingExample, PatternAndJointAnglesAreTheLecturesFormulas) {
  ASSERT_EQ(static_cast<long>(stream().rows.size()), rows_expected);
  double worst = 0;
  for (long n = 0; n < rows_expected; ++n)
    for (int leg = 0; leg < 2; ++leg) {
      const double mu = phase(n, leg), eta = extension(mu), theta = leg_angle(mu);
      EXPECT_NEAR(at(n, leg, "mu"), mu, 1e-6) << legs[leg] << " tick " << n;
      EXPECT_NEAR(at(n, leg, "eta"), eta, 1e-6) << legs[leg] << " tick " << n;
      EXPECT_NEAR(at(n, leg, "theta_leg"), theta, 1e-6) << legs[leg] << " tick " << n;
      // Abstract kinematics with theta_foot = 0.
      const double q2 = 2 * std::acos(eta), q1 = theta - q2 / 2, q3 = -theta - q2 / 2;
      for (const auto& [name, value] : {std::pair{"q1", q1}, {"q2", q2}, {"q3", q3}}) {
        const double error = std::abs(at(n, leg, name) - value);
        worst = std::max(worst, error);
        EXPECT_LT(error, tolerance) << legs[leg] << "." << name << " tick " << n;
      }
    }
  std::cout << "joint angles against the lecture's abstract kinematics in double: worst " << worst
            << " rad\n";
}

// The foot path: the stream's joint angles through the generated FK (double) put the ankle at
// 2 l eta (sin theta_leg, -cos theta_leg) from the hip and the toe f ahead of it (foot angle 0),
// with eta and theta_leg from the phase alone; the example's own float FK columns agree.
TEST(WalkingExample, FootPathThroughTheGeneratedFkIsThePatternsClosedForm) {
  ASSERT_EQ(static_cast<long>(stream().rows.size()), rows_expected);
  double worst = 0, worst_float = 0, reach = 0;
  for (long n = 0; n < rows_expected; ++n)
    for (int leg = 0; leg < 2; ++leg) {
      const double mu = phase(n, leg), r = 2 * l * extension(mu), theta = leg_angle(mu);
      const double ax = r * std::sin(theta), ay = -r * std::cos(theta);
      const k::State<double> s = fk(n, leg);
      const double errors[] = {
          s.points.ankle.x - ax, s.points.ankle.y - ay, s.points.ankle.z, s.points.toe.x - (ax + f),
          s.points.toe.y - ay,   s.points.toe.z,        s.points.hip.x,   s.points.hip.y};
      for (double e : errors) {
        worst = std::max(worst, std::abs(e));
        EXPECT_LT(std::abs(e), tolerance) << legs[leg] << " tick " << n;
      }
      const double floats[] = {
          at(n, leg, "ankle.x") - s.points.ankle.x, at(n, leg, "ankle.y") - s.points.ankle.y,
          at(n, leg, "toe.x") - s.points.toe.x, at(n, leg, "toe.y") - s.points.toe.y};
      for (double e : floats) {
        worst_float = std::max(worst_float, std::abs(e));
        EXPECT_LT(std::abs(e), tolerance) << legs[leg] << " tick " << n;
      }
      reach = std::max(reach, std::abs(ax));
    }
  EXPECT_NEAR(reach, 2 * l * eta0 * std::sin(S), 1e-12);  // a real stride, not a still leg
  std::cout << "foot path: generated FK (double) against the closed form, worst " << worst
            << " m; the example's float FK against it, worst " << worst_float << " m\n";
}

// Antiphase: the left leg does at tick n what the right leg did half a cycle earlier.
TEST(WalkingExample, LegsAreInAntiphase) {
  ASSERT_EQ(static_cast<long>(stream().rows.size()), rows_expected);
  const char* quantities[] = {"mu", "eta",     "theta_leg", "q1",    "q2",
                              "q3", "ankle.x", "ankle.y",   "toe.x", "toe.y"};
  for (long n = cycle / 2; n < rows_expected; ++n)
    for (const char* q : quantities)
      EXPECT_NEAR(at(n, 1, q), at(n - cycle / 2, 0, q), 1e-6) << q << " tick " << n;
  // ... and not trivially: half a cycle apart the two legs are at opposite leg angles.
  EXPECT_NEAR(at(0, 0, "theta_leg"), S, 1e-6);
  EXPECT_NEAR(at(0, 1, "theta_leg"), -S, 1e-6);
}

// Swing and stance from the FK foot path alone: the leg angle atan2(x, -y) of the ankle rises
// (the foot carried forward) exactly on the swing ticks (mu < 0) and falls on the stance ticks;
// each phase lasts half a cycle, touch-down at mu = 0 and lift-off at mu = -pi; exactly one leg
// swings at a time, its ankle above the stance ankle (the ground) by up to 2 l (eta0 - C1)
// against the stance height; the stance hip stays level to the height the levelling C2 gives.
TEST(WalkingExample, SwingAndStanceTiming) {
  ASSERT_EQ(static_cast<long>(stream().rows.size()), rows_expected);
  std::vector<double> angle[2], height[2];
  for (long n = 0; n < rows_expected; ++n)
    for (int leg = 0; leg < 2; ++leg) {
      const k::State<double> s = fk(n, leg);
      angle[leg].push_back(std::atan2(s.points.ankle.x, -s.points.ankle.y));
      height[leg].push_back(s.points.ankle.y);
    }
  std::map<std::string, std::vector<long>> events;
  double clearance = 0, stance_low = 0, stance_high = -1;
  int mid_swings = 0;
  for (long n = 0; n + 1 < rows_expected; ++n) {
    bool swinging[2];
    for (int leg = 0; leg < 2; ++leg) {
      const size_t i = static_cast<size_t>(n);
      swinging[leg] = angle[leg][i + 1] > angle[leg][i];
      EXPECT_EQ(swinging[leg], in_swing(n, leg)) << legs[leg] << " tick " << n;
      if (n > 0 && swinging[leg] != (angle[leg][i] > angle[leg][i - 1]))
        events[std::string(legs[leg]) + (swinging[leg] ? " lift-off" : " touch-down")].push_back(n);
      if (!swinging[leg]) {
        stance_low = std::min(stance_low, height[leg][i]);
        stance_high = std::max(stance_high, height[leg][i]);
      }
    }
    EXPECT_NE(swinging[0], swinging[1]) << "tick " << n;
    const int swing = swinging[0] ? 0 : 1;
    const size_t i = static_cast<size_t>(n);
    if (phase(n, swing) > -pi) {
      EXPECT_GT(height[swing][i], height[1 - swing][i]) << "tick " << n;
    }
    clearance = std::max(clearance, height[swing][i] - height[1 - swing][i]);
    // Mid-swing (mu = -pi/2, leg angle 0, extension eta0 - C1) against the other leg at
    // mid-stance (mu = pi/2, leg angle 0, extension eta0 + C2).
    if ((n + (swing == 0 ? cycle / 2 : 0)) % cycle == cycle / 4) {
      EXPECT_NEAR(height[swing][i] - height[1 - swing][i], 2 * l * (C1 + C2), tolerance);
      ++mid_swings;
    }
  }
  EXPECT_EQ(mid_swings, 6);
  EXPECT_EQ(events["right lift-off"], (std::vector<long>{500, 1500, 2500}));
  EXPECT_EQ(events["right touch-down"], (std::vector<long>{1000, 2000}));
  EXPECT_EQ(events["left lift-off"], (std::vector<long>{1000, 2000}));
  EXPECT_EQ(events["left touch-down"], (std::vector<long>{500, 1500, 2500}));
  EXPECT_GE(clearance, 2 * l * (C1 + C2) - tolerance);
  EXPECT_NEAR(stance_low, -2 * l * eta0 * std::cos(S), 1e-5);
  EXPECT_LT(stance_high - stance_low, 0.003);  // the hip stays level within 3 mm in stance
  std::cout << "largest swing foot clearance " << clearance << " m; stance hip height "
            << -stance_high << " .. " << -stance_low << " m\n";
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (argc != 2) {
    std::cerr << "usage: walking_example_test STREAM.csv\n";
    return 2;
  }
  stream_path = argv[1];
  return RUN_ALL_TESTS();
}
