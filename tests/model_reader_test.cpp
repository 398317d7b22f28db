// The description reader: shipped models load with the counts the seeds give, and malformed
// descriptions are rejected with FILE:LINE:COL: error: messages.
//
// Every bad description below is a complete model with one thing wrong; each check pins the exact
// location prefix (1-based line and column of the offending YAML node) and a key part of the
// message. Nothing may be accepted, crash, hang, or throw anything but ModelError.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "model/mechanism_graph.hpp"
#include "model/model.hpp"
#include "model/spatial_model.hpp"
#include "numeric/reference_solver.hpp"

namespace mechgen {
namespace {

TEST(ModelReader, PasibotHasTheSeedsCounts) {
  const Model model = read_model(MECHGEN_SOURCE_DIR "/models/pasibot.yaml");
  const StructureReport r = analyze_structure(model);
  EXPECT_EQ(model.bodies.size(), 24u);  // 24 links, the support foot as ground
  EXPECT_EQ(r.moving_bodies, 23);
  EXPECT_EQ(r.ne_unknowns, 69);  // seed: 69 Newton-Euler unknowns
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
    EXPECT_EQ(std::string(e.what()).rfind("m.yaml:5:39: error: point 'B' x '2*ll': undefined", 0),
              0u)
        << e.what();
  }
}

TEST(ModelReader, EveryShippedModelReadsWithMobilityEqualToDrivers) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(MECHGEN_SOURCE_DIR "/models")) {
    // Spatial descriptions have their own suite (spatial_model_test.cpp).
    if (entry.path().extension() != ".yaml" || is_spatial_description(entry.path())) continue;
    ++count;
    SCOPED_TRACE(entry.path().string());
    Model model;
    try {
      model = read_model(entry.path().string());
    } catch (const std::exception& e) {
      ADD_FAILURE() << e.what();
      continue;
    }
    EXPECT_EQ(model.name, entry.path().stem().string());  // models/<name>.yaml
    const StructureReport r = analyze_structure(model);
    EXPECT_GE(r.drivers, 1);
    EXPECT_EQ(r.drivers, static_cast<int>(model.drivers.size()));
    EXPECT_EQ(r.mobility, r.drivers);
  }
  EXPECT_GE(count, 4);  // chebyshev, leg3, pasibot, slider_crank
}

// ---------------------------------------------------------------------------------------------
// Bad input

// The text of the ModelError `action` throws; anything else is reported in the returned text, so
// that the prefix check below fails and shows it.
std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const ModelError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("<not a ModelError: ") + e.what() + ">";
  } catch (...) {
    return "<not a std::exception>";
  }
  return "<accepted>";
}

// The error of reading `text` as the file bad.yaml.
std::string read_error(const std::string& text) {
  return error_of([&] { read_model_text(text, "bad.yaml"); });
}

// `error` starts with exactly `prefix` ("FILE:LINE:COL: error: ") and its message contains `part`.
testing::AssertionResult Is(const std::string& error, const std::string& prefix,
                            const std::string& part) {
  if (error.rfind(prefix, 0) != 0)
    return testing::AssertionFailure() << "expected the prefix \"" << prefix << "\" in: " << error;
  if (error.find(part, prefix.size()) == std::string::npos)
    return testing::AssertionFailure() << "expected \"" << part << "\" in: " << error;
  return testing::AssertionSuccess();
}

// The well-formed pendulum most bad descriptions below are variations of.
const char* const pendulum = R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)";

TEST(ModelReaderBadInput, TheBaseCaseIsGood) {
  EXPECT_EQ(read_error(pendulum), "<accepted>");
}

TEST(ModelReaderBadInput, Files) {
  EXPECT_TRUE(Is(error_of([] { read_model(MECHGEN_SOURCE_DIR "/models/no_such_model.yaml"); }),
                 MECHGEN_SOURCE_DIR "/models/no_such_model.yaml: error: ", "no such model file"));
  EXPECT_TRUE(Is(error_of([] { read_model(MECHGEN_SOURCE_DIR "/models"); }),
                 MECHGEN_SOURCE_DIR "/models: error: ", "is a directory"));
}

TEST(ModelReaderBadInput, YamlSyntaxAndShape) {
  // An unclosed flow mapping: the parser stops where the closing brace should be.
  EXPECT_TRUE(Is(read_error(R"(name: m
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}
joints: []
)"),
                 "bad.yaml:4:1: error: ", "invalid YAML"));
  // A tab in the indentation.
  EXPECT_TRUE(Is(read_error("name: m\nbodies:\n\t- {name: ground, ground: true}\n"),
                 "bad.yaml:3:2: error: ", "invalid YAML"));
  // An alias to an anchor that does not exist.
  EXPECT_TRUE(Is(read_error("name: m\nparameters: {l: 0.5, k: *l}\n"),
                 "bad.yaml:2:25: error: ", "invalid YAML: the referenced anchor is not defined"));
  // Empty, or comments only: there is no node to point at.
  EXPECT_TRUE(Is(read_error(""), "bad.yaml: error: ", "the model description is empty"));
  EXPECT_TRUE(Is(read_error("# nothing\n"), "bad.yaml: error: ", "is empty"));
  // A list or a scalar instead of a mapping.
  EXPECT_TRUE(Is(read_error("- name: m\n- bodies: []\n"),
                 "bad.yaml:1:1: error: ", "must be a YAML mapping"));
  EXPECT_TRUE(Is(read_error("pendulum\n"), "bad.yaml:1:1: error: ", "must be a YAML mapping"));
  // A key that is a list, not a name.
  EXPECT_TRUE(Is(read_error("name: m\n[bodies, joints]: []\n"),
                 "bad.yaml:2:1: error: ", "a key in model must be a plain name"));
  // bodies not a list; a body not a mapping.
  EXPECT_TRUE(Is(read_error("name: m\nbodies: {ground: true}\nstep: {t0: 0, t1: 1}\n"),
                 "bad.yaml:2:9: error: ", "bodies must be a list"));
  EXPECT_TRUE(Is(read_error("name: m\nbodies:\n  - ground\nstep: {t0: 0, t1: 1}\n"),
                 "bad.yaml:3:5: error: ", "a body must be a mapping"));
}

TEST(ModelReaderBadInput, TopLevel) {
  // No name: located at the model's mapping.
  EXPECT_TRUE(Is(read_error(R"(parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:1:1: error: ", "the model needs 'name'"));
  // A name that cannot be a C++ identifier.
  EXPECT_TRUE(Is(read_error(R"(name: 2-bar
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:1:7: error: ", "model name '2-bar' is not an identifier"));
  // A misspelt top-level key.
  EXPECT_TRUE(Is(read_error(R"(name: m
gravty: [0, -9.81]
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:2:1: error: ", "unknown key 'gravty' in model"));
  // A spatial model.
  EXPECT_TRUE(Is(read_error(R"(name: m
dimension: spatial
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:2:12: error: ", "takes planar models only"));
  // Gravity with three components.
  EXPECT_TRUE(Is(read_error(R"(name: m
gravity: [0, -9.81, 0]
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:2:10: error: ", "gravity must be a pair [x, y] (got 3 values)"));
  // No step.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
)"),
                 "bad.yaml:1:1: error: ", "the model needs 'step'"));
  // A non-positive assembly tolerance.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
assembly_tolerance: 0
)"),
                 "bad.yaml:11:21: error: ", "assembly_tolerance must be positive"));
}

TEST(ModelReaderBadInput, Parameters) {
  // Neither a number nor an expression of parameters (derived parameters: parameter_test.cpp).
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: {value: half, unit: m}}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:2:25: error: ",
                 "parameter 'l' value 'half': undefined name 'half' (parameters: l)"));
  // Defined twice.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters:
  l: 0.5
  l: 0.6
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:4:3: error: ", "duplicate parameter 'l'"));
  // The time is not a parameter.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5, t: 2}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:2:22: error: ", "parameter name 't' is reserved"));
  // A misspelt key of a parameter.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: {value: 0.5, units: m}}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:2:30: error: ", "unknown key 'units' in parameter 'l'"));
}

TEST(ModelReaderBadInput, Bodies) {
  // The classic typo.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - name: arm
    points: {O: [0, 0], P: [l, 0]}
    masss: {mass: 1, com: [l/2, 0], inertia: 0.02}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:7:5: error: ", "unknown key 'masss' in body"));
  // Two bodies of one name.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
  - {name: arm, points: {P: [0, 0]}, mass: {mass: 1, com: [0, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:6:12: error: ", "duplicate body 'arm'"));
  // No ground: located at the list of bodies.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, points: {O: [0, 0]}, mass: {mass: 1, com: [0, 0], inertia: 1}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:4:3: error: ", "no ground body"));
  // Two grounds: located at the second.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, ground: true, points: {O: [0, 0], P: [l, 0]}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:5:12: error: ", "more than one ground body ('ground' and 'arm')"));
  // ground neither true nor false.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: maybe, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:4:28: error: ", "ground must be true or false"));
  // A body name that is not an identifier.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: upper arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: upper arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:5:12: error: ", "body name 'upper arm' is not an identifier"));
  // Names that would not compile as fields of a generated kernel: the scalar type of the kernels'
  // structs (`Real`; `T` is allowed: tests/spatial_ondemand_test.cpp), a C++ keyword, a reserved
  // identifier.
  EXPECT_TRUE(
      Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], Real: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
         "bad.yaml:5:37: error: ",
         "point name 'Real' is reserved: the generated kernels use it (their scalar type or "
         "a struct); rename it (e.g. 'Real_')"));
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: class, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: class, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:7:12: error: ", "joint name 'class' is reserved: it is a C++ keyword"));
  EXPECT_TRUE(Is(
      read_error(R"(name: m
parameters: {l__2: 0.5}
)"),
      "bad.yaml:2:14: error: ", "parameter name 'l__2' is reserved: C++ reserves names with '__'"));
  // Points: one coordinate, three coordinates, a point named twice.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:5:40: error: ", "point 'P' must be a pair [x, y] (got 1 value)"));
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:5:40: error: ", "point 'P' must be a pair [x, y] (got 3 values)"));
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - name: arm
    points:
      O: [0, 0]
      P: [l, 0]
      O: [l, 0]
    mass: {mass: 1, com: [l/2, 0], inertia: 0.02}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:9:7: error: ", "body 'arm': duplicate point 'O'"));
  // An assembly hint on the ground.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}, assembly: 0}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:4:65: error: ", "the ground body takes no assembly hint"));
}

TEST(ModelReaderBadInput, Expressions) {
  // An undefined parameter (a typo of l).
  EXPECT_TRUE(
      Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [2*ll, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
         "bad.yaml:5:41: error: ", "point 'P' x '2*ll': undefined name 'll' (parameters: l)"));
  // A syntax error.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: "2*(t + 1"}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:9:50: error: ", "driver value '2*(t + 1': syntax error"));
  // An unknown function.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: sine(t)}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:9:50: error: ", "syntax error (no function \"sine\""));
  // The time in a geometric quantity.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l*(1 + t), 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:5:41: error: ", "point 'P' x 'l*(1 + t)' may not depend on time t"));
  // A pole, found while parsing, is no syntax error.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 1/0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:5:44: error: ", "point 'P' y '1/0' cannot be evaluated"));
  // Complex at the default parameters.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [sqrt(l - 1), 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:5:41: error: ", "'sqrt(l - 1)' evaluates to a complex number"));
  // An empty expression.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, ""]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:5:44: error: ", "point 'P' y is empty"));
}

TEST(ModelReaderBadInput, Mass) {
  // A negative mass.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: -1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:5:62: error: ", "body 'arm' has a non-positive mass"));
  // No mass at all on a moving body: located at its name.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:5:12: error: ", "body 'arm' has no mass"));
  // Zero and negative inertia.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:5:89: error: ", "body 'arm' has a non-positive inertia"));
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: -l^2/12}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:5:89: error: ", "body 'arm' has a non-positive inertia"));
  // An explicit mass without its centre.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:5:55: error: ", "mass of body 'arm' needs 'com'"));
  // A bar between a point of the body and one it does not have.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {bar: [O, Q], width: 0.02, thickness: 0.005, density: 2700}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:5:65: error: ", "body has no point 'Q'"));
  // A bar of zero width.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {bar: [O, P], width: 0, thickness: 0.005, density: 2700}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:5:76: error: ", "body 'arm': bar width '0' must be positive"));
}

TEST(ModelReaderBadInput, Joints) {
  // A joint naming a body that does not exist.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: armm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:7:55: error: ",
                 "joint 'jO' second body: unknown body 'armm' (bodies: ground, arm)"));
  // The joint point is missing on the first body.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: P}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:7:67: error: ", "joint 'jO': body 'ground' has no point 'P'"));
  // A body joined to itself.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: arm, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:7:52: error: ", "joint 'jO' joins a body to itself"));
  // An unknown joint type.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: hinge, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:7:22: error: ", "unknown joint type 'hinge'"));
  // Two joints of one name (a copy-paste slip in a double pendulum).
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
  - {name: arm2, points: {P: [0, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
  - {name: jO, type: revolute, first: arm, second: arm2, point: P}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
  - {name: phi, joint: jP, kind: angle, value: 0}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:9:12: error: ", "duplicate name 'jO' (already the name of a joint)"));
  // A joint named like a body: the two would share columns.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: arm, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: arm, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:7:12: error: ", "duplicate name 'arm' (already the name of a body)"));
  // Keys that belong to other joint types, and a slider without its line.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O, angle: 0}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:7:77: error: ", "joint 'jO': a revolute joint takes no angle"));
  EXPECT_TRUE(Is(read_error(R"(name: m
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: slider, points: {S: [0, 0]}, mass: {mass: 1, com: [0, 0], inertia: 0.01}}
joints:
  - {name: slide, type: prismatic, first: ground, second: slider, point: S}
drivers:
  - {name: x, joint: slide, kind: length, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:6:5: error: ", "joint 'slide' needs 'line'"));
  // A zero line direction.
  EXPECT_TRUE(Is(read_error(R"(name: m
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: slider, points: {S: [0, 0]}, mass: {mass: 1, com: [0, 0], inertia: 0.01}}
joints:
  - name: slide
    type: prismatic
    first: ground
    second: slider
    point: S
    line: {through: [0, 0], direction: [0, 0]}
drivers:
  - {name: x, joint: slide, kind: length, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:11:41: error: ", "joint 'slide': zero line direction"));
}

TEST(ModelReaderBadInput, Drivers) {
  // A driver on a joint that does not exist.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jA, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:9:26: error: ", "driver 'theta': unknown joint 'jA'"));
  // An angle driver on a prismatic joint.
  EXPECT_TRUE(Is(read_error(R"(name: m
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: slider, points: {S: [0, 0]}, mass: {mass: 1, com: [0, 0], inertia: 0.01}}
joints:
  - {name: slide, type: prismatic, first: ground, second: slider, point: S,
     line: {through: [0, 0], direction: [1, 0]}}
drivers:
  - {name: x, joint: slide, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:9:35: error: ",
                 "driver 'x': an angle driver needs a revolute joint, 'slide' is prismatic"));
  // A length driver on a revolute joint.
  EXPECT_TRUE(
      Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: length, value: t}
step: {t0: 0, t1: 1}
)"),
         "bad.yaml:9:36: error: ", "a length driver needs a prismatic or pin_in_slot joint"));
  // An unknown kind.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: speed, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:9:36: error: ", "unknown driver kind 'speed'"));
  // Two drivers on one joint: located at the second's joint.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
  - {name: theta2, joint: jO, kind: angle, value: 2*t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:10:27: error: ", "joint 'jO' is already driven by 'theta'"));
  // Fewer drivers than degrees of freedom (a double pendulum driven at one joint): located at the
  // first driver.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
  - {name: arm2, points: {P: [0, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
  - {name: jP, type: revolute, first: arm, second: arm2, point: P}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:11:12: error: ",
                 "mobility is 2 (3 x 2 moving bodies - 4 joint constraints) but 1 driver(s)"));
}

TEST(ModelReaderBadInput, Structure) {
  // A body joined to nothing.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
  - {name: loose, points: {Q: [0, 0]}, mass: {mass: 1, com: [0, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:6:12: error: ", "body 'loose' is not connected to the ground"));
  // Two bodies carry the point P but meet there through a pin-in-slot, not a revolute joint:
  // "P" would name two different places. Located at the second body carrying it.
  EXPECT_TRUE(Is(read_error(R"(name: m
bodies:
  - {name: ground, ground: true, points: {O: [0, 0], Q: [0.6, 0]}}
  - {name: arm, points: {O: [0, 0], P: [0.2, 0]}, mass: {mass: 1, com: [0.1, 0], inertia: 0.01}}
  - {name: rocker, points: {Q: [0, 0], P: [0.5, 0]}, mass: {mass: 1, com: [0.25, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
  - {name: jQ, type: revolute, first: ground, second: rocker, point: Q}
  - {name: slot, type: pin_in_slot, first: rocker, second: arm, point: P,
     line: {through: [0, 0], direction: [1, 0]}}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:5:12: error: ",
                 "point 'P' is on bodies 'arm' and 'rocker' but no revolute joint pins them"));
}

TEST(ModelReaderBadInput, Step) {
  // An empty sweep, t1 = t0.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5, w: 2}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: w*t}
step: {t0: pi/w, t1: pi/2}
)"),
                 "bad.yaml:10:22: error: ", "step: t1 (1.5708) must be greater than t0 (1.5708)"));
  // One sample, and a fractional count.
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1, samples: 1}
)"),
                 "bad.yaml:10:31: error: ", "step samples must be at least 2"));
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1, samples: 10.5}
)"),
                 "bad.yaml:10:31: error: ", "step samples must be an integer"));
}

TEST(ModelReaderBadInput, Forces) {
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
forces:
  - {name: push, type: impulse, body: arm, point: P, value: [0, 1]}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:11:24: error: ", "unknown force type 'impulse'"));
  EXPECT_TRUE(Is(read_error(R"(name: m
parameters: {l: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], inertia: 0.02}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
forces:
  - {name: spring, type: spring_damper, first: ground, first_point: O, second: arm,
     second_point: P, stiffness: -100, free_length: l}
step: {t0: 0, t1: 1}
)"),
                 "bad.yaml:12:34: error: ", "force 'spring': negative stiffness"));
}

TEST(ModelReaderBadInput, Overrides) {
  const Model model = read_model_text(pendulum, "bad.yaml");
  auto set_error = [&](const std::vector<std::string>& overrides) {
    return error_of([&] {
      std::vector<double> values = model.default_parameters();
      apply_overrides(model, overrides, values);
    });
  };
  EXPECT_TRUE(Is(set_error({"l=0.25", "ll=1"}),
                 "<command line>: error: ", "--set: model 'm' has no parameter 'll'"));
  EXPECT_TRUE(
      Is(set_error({"l=short"}), "<command line>: error: ", "--set l: 'short' is not a number"));
  EXPECT_TRUE(Is(set_error({"l=0.5m"}), "<command line>: error: ", "'0.5m' is not a number"));
  EXPECT_TRUE(Is(set_error({"l="}), "<command line>: error: ", "'' is not a number"));
  EXPECT_TRUE(Is(set_error({"l"}), "<command line>: error: ", "--set expects NAME=VALUE, got 'l'"));
  std::vector<double> values = model.default_parameters();
  EXPECT_NO_THROW(apply_overrides(model, {"l=0.25"}, values));
  EXPECT_EQ(values[0], 0.25);
}

// ---------------------------------------------------------------------------------------------
// Bad input only the numeric assembly finds

// The error of assembling a description (read as bad.yaml) at t = 0.
std::string assembly_error(const std::string& text) {
  return error_of([&] {
    const Model model = read_model_text(text, "bad.yaml");
    numeric::ReferenceSolver solver(model, model.default_parameters());
    solver.assemble(0);
  });
}

// A four-bar: ground O-D 0.3, crank O-P 0.1, coupler P-Q 0.3, rocker D-Q 0.25. At the crank angle
// pi/2 the coupler is at 0.512 rad and the rocker at 1.725 (or, on the other branch, -1.156 and
// -2.369).
std::string four_bar(const std::string& ground_length, const std::string& coupler_hint) {
  return R"(name: fourbar
bodies:
  - {name: ground, ground: true, points: {O: [0, 0], D: [)" +
         ground_length + R"(, 0]}}
  - {name: crank, points: {O: [0, 0], P: [0.1, 0]}, mass: {mass: 0.1, com: [0.05, 0], inertia: 1e-4}}
  - name: coupler
    points: {P: [0, 0], Q: [0.3, 0]}
    mass: {mass: 0.3, com: [0.15, 0], inertia: 2e-3}
    assembly: )" +
         coupler_hint + R"(
  - name: rocker
    points: {D: [0, 0], Q: [0.25, 0]}
    mass: {mass: 0.25, com: [0.125, 0], inertia: 1.5e-3}
    assembly: 1.7
joints:
  - {name: jO, type: revolute, first: ground, second: crank, point: O}
  - {name: jP, type: revolute, first: crank, second: coupler, point: P}
  - {name: jQ, type: revolute, first: coupler, second: rocker, point: Q}
  - {name: jD, type: revolute, first: ground, second: rocker, point: D}
drivers:
  - {name: theta, joint: jO, kind: angle, value: pi/2 + t}
step: {t0: 0, t1: 1}
)";
}

TEST(ModelReaderBadInput, AssemblyHintThatDoesNotAssemble) {
  EXPECT_EQ(assembly_error(four_bar("0.3", "0.5")), "<accepted>");
  // 2.5 is 2 rad from the coupler angle of one branch and 2.6 from the other's: located at the
  // hint (line 8, `assembly: 2.5`).
  EXPECT_TRUE(Is(assembly_error(four_bar("0.3", "2.5")), "bad.yaml:8:15: error: ",
                 "the assembly hint of body 'coupler' does not assemble"));
}

TEST(ModelReaderBadInput, FourBarThatCannotClose) {
  // Ground 0.7 but crank + coupler + rocker only 0.65: no configuration at all. The solver names
  // the model file (no single node is at fault).
  EXPECT_TRUE(Is(assembly_error(four_bar("0.7", "0.5")),
                 "bad.yaml: error: ", "the mechanism does not assemble at t = 0"));
}

// The count is right but the constraints are not independent: the arm is pinned to the ground
// twice at O (4 equations for its 3 coordinates with the driver: 5), while the block, held only by
// a pin-in-slot, keeps 2 free coordinates. Gruebler: 3 x 2 - (2 + 2 + 1) = 1 = drivers, so the
// reader accepts it; the Jacobian has rank 4 for 6 equations. Located at the first joint involved.
TEST(ModelReaderBadInput, RedundantConstraints) {
  const std::string error = assembly_error(R"(name: m
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0], P: [0.5, 0]}, mass: {mass: 1, com: [0.25, 0], inertia: 0.02}}
  - {name: block, points: {S: [0, 0]}, mass: {mass: 1, com: [0, 0], inertia: 0.01}}
joints:
  - {name: jO, type: revolute, first: ground, second: arm, point: O}
  - {name: jO_again, type: revolute, first: ground, second: arm, point: O}
  - {name: slot, type: pin_in_slot, first: ground, second: block, point: S,
     line: {through: [0, -0.5], direction: [1, 0]}}
drivers:
  - {name: theta, joint: jO, kind: angle, value: t}
step: {t0: 0, t1: 1}
)");
  EXPECT_TRUE(Is(error, "bad.yaml:7:12: error: ", "rank 4 for 6 equations in 6 coordinates"));
  EXPECT_TRUE(
      Is(error, "bad.yaml:7:12: error: ", "redundant constraints among joints jO, jO_again"));
  EXPECT_TRUE(Is(error, "bad.yaml:7:12: error: ", "the motion of bodies block is not determined"));
  EXPECT_EQ(error.find("slot"), std::string::npos) << error;
  EXPECT_EQ(error.find("driver theta"), std::string::npos) << error;
}

}  // namespace
}  // namespace mechgen
