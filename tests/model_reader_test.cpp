// The description reader: shipped models load with the counts the seeds give, and malformed
// descriptions are rejected with FILE:LINE:COL: error: messages.
#include <gtest/gtest.h>

#include "model/mechanism_graph.hpp"
#include "model/model.hpp"

namespace mechgen {
namespace {

TEST(ModelReader, PasibotHasTheSeedsCounts) {
  const Model model = read_model(MECHGEN_SOURCE_DIR "/models/pasibot.yaml");
  const StructureReport r = analyze_structure(model);
  EXPECT_EQ(model.bodies.size(), 24u);  // 24 links, the support foot as ground
  EXPECT_EQ(r.moving_bodies, 23);
  EXPECT_EQ(r.ne_unknowns, 69);         // seed: 69 Newton-Euler unknowns
  EXPECT_EQ(r.ne_equations, 69);
  EXPECT_EQ(r.mobility, 1);
}

TEST(ModelReader, UndefinedParameterIsLocated) {
  const std::string text =
      "name: m\nparameters: {l: 1}\nbodies:\n  - {name: g, ground: true, points: {A: [0, 0]}}\n"
      "  - {name: b, points: {A: [0, 0], B: [2*ll, 0]}, mass: {mass: 1, com: [0, 0], inertia: 1}}\n"
      "joints:\n  - {name: j, type: revolute, first: g, second: b, point: A}\n"
      "drivers:\n  - {name: d, joint: j, kind: angle, value: t}\nstep: {t0: 0, t1: 1}\n";
  try {
    read_model_text(text, "m.yaml");
    FAIL() << "accepted an undefined parameter";
  } catch (const ModelError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("m.yaml:5:39: error: point 'B' x '2*ll': undefined", 0), 0u)
        << e.what();
  }
}

}  // namespace
}  // namespace mechgen
