// A branch choice is never silent: chebyshev without the hints of its dyad (coupler, rocker) still
// assembles, on a branch that nothing in the model chose; `check` names it, gives both branches'
// body angles (checked here against the circle-circle intersection computed independently) and
// the hint that pins it. With the shipped hints, or a hint added as suggested, no warning.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "branch_choice.hpp"
#include "generate.hpp"
#include "model/model.hpp"

namespace mechgen {
namespace {

std::string chebyshev_text() {
  std::ifstream in(MECHGEN_SOURCE_DIR "/models/chebyshev.yaml");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The model with the coupler's and the rocker's hints replaced (empty: removed).
Model chebyshev_with(const std::string& coupler, const std::string& rocker) {
  std::string text = chebyshev_text();
  auto replace = [&](const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  };
  replace("    assembly: pi/2\n  - name: rocker",
          (coupler.empty() ? "" : "    assembly: " + coupler + "\n") + "  - name: rocker");
  replace("    assembly: 0.6435\n", rocker.empty() ? "" : "    assembly: " + rocker + "\n");
  return read_model_text(text, "chebyshev.yaml");
}

std::vector<std::string> warnings(const Model& model, std::vector<gen::BranchChoice>& choices) {
  gen::branch_notes(model, &choices);
  return gen::unpinned_branch_warnings(model, choices);
}

TEST(BranchChoice, ShippedHintsPinEveryBranch) {
  std::vector<gen::BranchChoice> choices;
  const Model model = chebyshev_with("pi/2", "0.6435");
  EXPECT_TRUE(warnings(model, choices).empty());
  ASSERT_EQ(choices.size(), 1u);
  EXPECT_TRUE(gen::branch_pinned(model, choices[0]));
}

TEST(BranchChoice, UnhintedDyadIsReportedWithBothBranches) {
  // Independently: at t0 the crank pin is P = (0, l), the rocker pivot B = (2 l, 0); the coupler
  // pin M is at 2.5 l from both. Coupler angle: direction M -> P; rocker angle: M -> B.
  const double l = 0.03;
  const double px = 0, py = l, bx = 2 * l, by = 0, r = 2.5 * l;
  const double dx = bx - px, dy = by - py, d = std::hypot(dx, dy);
  const double h = std::sqrt(r * r - d * d / 4);
  std::set<std::pair<long, long>> expected;  // (coupler, rocker) angles in 1e-4 rad
  for (int s : {1, -1}) {
    const double mx = px + dx / 2 - s * h * dy / d, my = py + dy / 2 + s * h * dx / d;
    expected.insert({std::lround(std::atan2(py - my, px - mx) * 1e4),
                     std::lround(std::atan2(by - my, bx - mx) * 1e4)});
  }
  std::vector<gen::BranchChoice> choices;
  const Model model = chebyshev_with("", "");
  const std::vector<std::string> lines = warnings(model, choices);
  ASSERT_EQ(choices.size(), 1u);
  ASSERT_EQ(lines.size(), 1u);
  const gen::BranchChoice& c = choices[0];
  ASSERT_EQ(c.bodies.size(), 2u);
  EXPECT_EQ(model.bodies[static_cast<size_t>(c.bodies[0])].name, "coupler");
  EXPECT_EQ(model.bodies[static_cast<size_t>(c.bodies[1])].name, "rocker");
  const std::set<std::pair<long, long>> got{
      {std::lround(c.taken[0] * 1e4), std::lround(c.taken[1] * 1e4)},
      {std::lround(c.other[0] * 1e4), std::lround(c.other[1] * 1e4)}};
  EXPECT_EQ(got, expected);
  const std::string& w = lines[0];
  EXPECT_NE(w.find("no assembly hint tells its two branches apart; took branch"), std::string::npos)
      << w;
  for (double a : {c.taken[0], c.taken[1], c.other[0], c.other[1]}) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4f", a);
    EXPECT_NE(w.find(text), std::string::npos) << text << " in " << w;
  }
  // The suggested hint pins the branch taken, and then the warning is gone.
  const size_t at = w.find("pin it with `assembly: ") + 23;
  const std::string hint = w.substr(at, w.find('`', at) - at);
  const std::string body =
      w.substr(w.find("on body '") + 9, w.find("' (or") - w.find("on body '") - 9);
  std::vector<gen::BranchChoice> pinned_choices;
  const Model pinned = body == "coupler" ? chebyshev_with(hint, "") : chebyshev_with("", hint);
  EXPECT_TRUE(warnings(pinned, pinned_choices).empty()) << body << " " << hint;
}

// A hint between the branches, within the tolerance of both, does not tell them apart.
TEST(BranchChoice, AHintNearBothBranchesDoesNotPin) {
  gen::BranchChoice c{"g", 1, {2, 3}, {1.0, 0.2}, {1.3, 0.4}};
  const Model model = chebyshev_with("1.15", "");  // 0.15 from both (tolerance 0.35)
  EXPECT_FALSE(gen::branch_pinned(model, c));
  const Model far = chebyshev_with("0.9", "");  // 0.1 from the taken, 0.4 from the other
  EXPECT_TRUE(gen::branch_pinned(far, c));
}

}  // namespace
}  // namespace mechgen
