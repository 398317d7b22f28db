// Motor selection (seed 000, section 4): catalogue reading and the iteration, on catalogues whose
// answer is worked out by hand in the comments.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "analysis/motor_sizing.hpp"
#include "model/model.hpp"
#include "report/csv_table.hpp"

namespace mechgen {
namespace {

const char* const kHeader =
    "name,rated_torque[N m],peak_torque[N m],no_load_speed[rpm],mass[kg],gear_ratio,efficiency\n";

// Output side (torque x ratio x efficiency, speed / ratio), by hand:
//   small:  rated 0.01 x 100 x 0.5 = 0.5 N m, peak 0.03 x 100 x 0.5 = 1.5 N m,
//           6000 rpm / 100 = 60 rpm = 2 pi rad/s; 0.2 kg
//   medium: rated 0.02 x 100 x 0.5 = 1.0 N m, peak 0.06 x 100 x 0.5 = 3.0 N m, 2 pi rad/s; 0.5 kg
//   large:  rated 0.04 x 100 x 0.5 = 2.0 N m, peak 0.12 x 100 x 0.5 = 6.0 N m, 2 pi rad/s; 1.0 kg
// Listed largest first: "smallest" is the catalogue's order by output torque, not the file's.
const std::string kCatalogue = std::string("# a comment line\n") + kHeader +
                               "large,0.04,0.12,6000,1.0,100,0.5\n"
                               "small,0.01,0.03,6000,0.2,100,0.5\n"
                               "medium,0.02,0.06,6000,0.5,100,0.5\n";

int index_of(const std::vector<Motor>& catalogue, const std::string& name) {
  for (size_t i = 0; i < catalogue.size(); ++i)
    if (catalogue[i].name == name) return static_cast<int>(i);
  return -1;
}

TEST(MotorCatalogue, ReadsUnitsAndOutputSide) {
  const std::vector<Motor> catalogue = parse_catalogue(kCatalogue, "fake.csv");
  ASSERT_EQ(catalogue.size(), 3u);
  const Motor& small = catalogue[1];
  EXPECT_EQ(small.name, "small");
  EXPECT_DOUBLE_EQ(small.no_load_speed, 6000 * 2 * std::numbers::pi / 60);
  EXPECT_DOUBLE_EQ(small.output_rated_torque(), 0.5);
  EXPECT_DOUBLE_EQ(small.output_peak_torque(), 1.5);
  EXPECT_DOUBLE_EQ(small.output_speed(), 2 * std::numbers::pi);
}

TEST(MotorCatalogue, BadLinesNameFileAndLine) {
  auto message = [](const std::string& text) {
    try {
      parse_catalogue(text, "fake.csv");
    } catch (const report::CsvError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("name,mass[kg]\n").rfind("fake.csv:1: the header has no column", 0), 0u);
  EXPECT_EQ(message(std::string(kHeader) + "a,0.01,0.03,6000,0.2,100,0.5\nb,0.01,x,1,1,1,1\n"),
            "fake.csv:3: peak_torque[N m]: 'x' is not a number");
  EXPECT_EQ(message(std::string(kHeader) + "a,0.01,0.03,6000,0.2,100,1.5\n"),
            "fake.csv:2: efficiency must be at most 1, got 1.5");
  EXPECT_EQ(message(std::string(kHeader) + "a,0.01,0.03,6000,0.2,100\n"),
            "fake.csv:2: expected 7 cells as in the header, got 6");
  EXPECT_EQ(message(std::string(kHeader) + "a,0.01,0.03,0,0.2,100,0.5\n"),
            "fake.csv:2: no_load_speed[rpm] must be positive, got 0");
  EXPECT_EQ(message(kHeader), "fake.csv:1: no motor in the catalogue");
}

// A requirement that does not depend on the motor's mass: peak 0.8, RMS 0.4 N m, 3 rad/s.
// x 1.5: peak 1.2, RMS 0.6, speed 4.5 rad/s <= 2 pi. small fails on RMS (0.5 < 0.6); medium
// covers it: chosen at the first recomputation.
TEST(MotorSizing, SmallestCoveringMotorWithSafetyFactor) {
  const std::vector<Motor> catalogue = parse_catalogue(kCatalogue, "fake.csv");
  int calls = 0;
  const SizingResult result = size_motor(catalogue, 1.5, [&](double added_mass) {
    ++calls;
    EXPECT_EQ(added_mass, calls == 1 ? 0.0 : 0.5);
    return MotorRequirement{0.8, 0.4, 3.0};
  });
  EXPECT_EQ(result.chosen, index_of(catalogue, "medium"));
  ASSERT_EQ(result.iterations.size(), 2u);
  EXPECT_EQ(result.iterations[0].proposed, index_of(catalogue, "medium"));
  EXPECT_TRUE(result.iterations[1].holds);
  // Without the safety factor the small motor suffices (0.4 <= 0.5, 0.8 <= 1.5).
  EXPECT_EQ(size_motor(catalogue, 1.0,
                       [](double) {
                         return MotorRequirement{0.8, 0.4, 3.0};
                       })
                .chosen,
            index_of(catalogue, "small"));
}

// The motor's own mass raises the torque: peak = 1.0 + 2.5 m, RMS = 0.4 + 1.0 m (N m), m the
// motor mass on the hip; safety 1. Without a motor: peak 1.0, RMS 0.4 -> small (1.5, 0.5).
// With small (0.2 kg): peak 1.5, RMS 0.6 > 0.5 -> small fails; medium (3.0, 1.0) covers it.
// With medium (0.5 kg): peak 2.25, RMS 0.9 <= 1.0 -> medium holds.
TEST(MotorSizing, StepsUpWhenTheMotorsMassRaisesTheTorque) {
  const std::vector<Motor> catalogue = parse_catalogue(kCatalogue, "fake.csv");
  auto need = [](double m) { return MotorRequirement{1.0 + 2.5 * m, 0.4 + 1.0 * m, 1.0}; };
  const SizingResult result = size_motor(catalogue, 1.0, need);
  ASSERT_EQ(result.iterations.size(), 3u);
  EXPECT_EQ(result.iterations[0].tried, -1);
  EXPECT_EQ(result.iterations[0].proposed, index_of(catalogue, "small"));
  EXPECT_EQ(result.iterations[1].tried, index_of(catalogue, "small"));
  EXPECT_DOUBLE_EQ(result.iterations[1].added_mass, 0.2);
  EXPECT_DOUBLE_EQ(result.iterations[1].need.rms_torque, 0.6);
  EXPECT_FALSE(result.iterations[1].holds);
  EXPECT_EQ(result.iterations[1].proposed, index_of(catalogue, "medium"));
  EXPECT_TRUE(result.iterations[2].holds);
  EXPECT_DOUBLE_EQ(result.iterations[2].added_mass, 0.5);
  EXPECT_EQ(result.chosen, index_of(catalogue, "medium"));
  const std::string table = format_sizing(catalogue, 1.0, result);
  EXPECT_NE(table.find("chosen: medium"), std::string::npos) << table;
}

TEST(MotorSizing, NothingSufficesIsAClearError) {
  const std::vector<Motor> catalogue = parse_catalogue(kCatalogue, "fake.csv");
  // Too fast for every gearbox: 7 rad/s > 2 pi.
  try {
    size_motor(catalogue, 1.0, [](double) { return MotorRequirement{0.1, 0.1, 7.0}; });
    FAIL() << "expected an error";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()).rfind("no motor in the catalogue covers", 0), 0u)
        << error.what();
  }
  // Each motor's own mass pushes the torque past it: peak = 1 + 10 m. small (0.2 kg) -> 3.0 >
  // 1.5; medium (0.5 kg) -> 6.0 > 3.0; large (1.0 kg) -> 11 > 6: no larger motor left.
  try {
    size_motor(catalogue, 1.0, [](double m) { return MotorRequirement{1 + 10 * m, 0.1, 1.0}; });
    FAIL() << "expected an error";
  } catch (const MotorSizingError& error) {
    EXPECT_EQ(error.partial.iterations.size(), 4u);  // none, small, medium, large
    EXPECT_EQ(error.partial.chosen, -1);
    EXPECT_EQ(std::string(error.what()).rfind("no larger motor in the catalogue covers", 0), 0u)
        << error.what();
  }
}

// The real model. At the defaults the crank turns at exactly w8 = 2 rad/s, and (seed Fig. 11,
// out/pasibot_fig11_load.csv) the peak torque is 0.9948 N m with nothing on the hip and
// 1.1502 N m with 15 kg. Two fictitious 15 kg motors straddle that rise: "A" (output peak
// 0.105 x 10 x 1 = 1.05 N m) covers the bare robot but not itself on the hip; "B" (1.2 N m)
// covers both. The iteration must go none -> A -> B, B holding with its own mass.
TEST(MotorSizing, PasibotStepsUpWhenTheMotorsMassRaisesThePeak) {
  const Model model = read_model(std::string(MECHGEN_SOURCE_DIR) + "/models/pasibot.yaml");
  const std::vector<double> defaults = model.default_parameters();
  auto need = [&](double added) {
    return step_requirement(model, defaults, "m_load", added, "theta8");
  };
  const MotorRequirement bare = need(0), loaded = need(15);
  EXPECT_DOUBLE_EQ(bare.peak_speed, 2.0);
  EXPECT_NEAR(bare.peak_torque, 0.9948, 1e-4);
  EXPECT_NEAR(loaded.peak_torque, 1.1502, 1e-4);
  const std::vector<Motor> catalogue = parse_catalogue(
      std::string(kHeader) + "B,0.11,0.12,1000,15,10,1\n" + "A,0.10,0.105,1000,15,10,1\n",
      "heavy.csv");
  const SizingResult result = size_motor(catalogue, 1.0, need);
  ASSERT_EQ(result.iterations.size(), 3u);
  EXPECT_EQ(result.iterations[0].proposed, index_of(catalogue, "A"));
  EXPECT_FALSE(result.iterations[1].holds);
  EXPECT_DOUBLE_EQ(result.iterations[1].need.peak_torque, loaded.peak_torque);
  EXPECT_EQ(result.iterations[1].proposed, index_of(catalogue, "B"));
  EXPECT_TRUE(result.iterations[2].holds);
  EXPECT_EQ(result.chosen, index_of(catalogue, "B"));
  EXPECT_THROW(step_requirement(model, defaults, "m_motor", 1, "theta8"), ModelError);
}

}  // namespace
}  // namespace mechgen
