// Parameters as a designer writes them: units converted to SI when read (an unknown unit is a
// located error), and derived parameters (a value that is an expression of other parameters) in
// dependency order, cycles located, following --set of what they use in the numeric solver.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "model/columns.hpp"
#include "model/model.hpp"
#include "model/units.hpp"
#include "numeric/reference_solver.hpp"

namespace mechgen {
namespace {

// A crank of length `l` about A, driven at angle t; `parameters` is the YAML block's body.
std::string crank(const std::string& parameters) {
  return "name: m\nparameters:\n" + parameters +
         "bodies:\n"
         "  - {name: g, ground: true, points: {A: [0, 0]}}\n"
         "  - {name: c, points: {A: [0, 0], P: [l, 0]}, mass: {mass: 1, com: [l/2, 0], "
         "inertia: 0.01}}\n"
         "joints:\n  - {name: j, type: revolute, first: g, second: c, point: A}\n"
         "drivers:\n  - {name: d, joint: j, kind: angle, value: t}\nstep: {t0: 0, t1: 1}\n";
}

std::string error_of(const std::string& text) {
  try {
    read_model_text(text, "p.yaml");
  } catch (const ModelError& e) {
    return e.what();
  }
  return "(accepted)";
}

double value_of(const Model& model, const std::string& name) {
  const int i = model.parameter_index(name);
  if (i >= 0) return model.parameters[static_cast<size_t>(i)].value;
  const int d = model.derived_index(name);
  EXPECT_GE(d, 0) << "no parameter " << name;
  return d < 0 ? NAN : model.derived_values(model.default_parameters())[static_cast<size_t>(d)];
}

// Today's trap: 38.0 with unit mm was read as 38 m.
TEST(Units, ConvertedToSiWhenRead) {
  const Model model = read_model_text(crank("  l: {value: 38.0, unit: mm}\n"
                                            "  h: {value: 2.5, unit: cm}\n"
                                            "  a: {value: 90, unit: deg}\n"
                                            "  w: {value: 30, unit: rpm}\n"
                                            "  m: {value: 250, unit: g}\n"
                                            "  rho: {value: 2.7, unit: g/cm^3}\n"
                                            "  k: {value: 3, unit: N*m}\n"
                                            "  s: {value: 0.5, unit: m}\n"),
                                      "p.yaml");
  EXPECT_DOUBLE_EQ(value_of(model, "l"), 0.038);
  EXPECT_DOUBLE_EQ(value_of(model, "h"), 0.025);
  EXPECT_DOUBLE_EQ(value_of(model, "a"), M_PI / 2);
  EXPECT_DOUBLE_EQ(value_of(model, "w"), M_PI);
  EXPECT_DOUBLE_EQ(value_of(model, "m"), 0.25);
  EXPECT_DOUBLE_EQ(value_of(model, "rho"), 2700);
  EXPECT_DOUBLE_EQ(value_of(model, "k"), 3);
  EXPECT_DOUBLE_EQ(value_of(model, "s"), 0.5);
  const Parameter& l = model.parameters[static_cast<size_t>(model.parameter_index("l"))];
  EXPECT_EQ(l.unit, "m");
  EXPECT_EQ(l.written, "38 mm");
  EXPECT_EQ(model.parameters[static_cast<size_t>(model.parameter_index("k"))].unit, "N m");
  EXPECT_EQ(model.parameters[static_cast<size_t>(model.parameter_index("s"))].written, "");
  // The geometry uses the converted value: the crank pin is 38 mm from A.
  numeric::ReferenceSolver solver(model, model.default_parameters());
  solver.assemble(0);
  std::vector<double> row(column_names(model).size());
  ASSERT_EQ(solver.solve(0, row), numeric::Status::ok);
  const std::vector<std::string> names = column_names(model);
  const size_t px =
      static_cast<size_t>(std::find(names.begin(), names.end(), "P.x") - names.begin());
  EXPECT_NEAR(row[px], 0.038, 1e-15);
}

TEST(Units, UnknownUnitIsALocatedError) {
  const std::string e = error_of(crank("  l: {value: 2, unit: furlong}\n"));
  EXPECT_EQ(e.rfind("p.yaml:3:23: error: parameter 'l': unknown unit 'furlong' (known units: ", 0),
            0u)
      << e;
  EXPECT_NE(e.find("mm"), std::string::npos) << e;
}

// docs/model_format.md lists exactly the units the reader knows.
TEST(Units, TheDocumentedListIsTheReadersList) {
  std::ifstream in(MECHGEN_SOURCE_DIR "/docs/model_format.md");
  std::stringstream text;
  text << in.rdbuf();
  const std::string doc = text.str();
  const size_t from = doc.find("- **Units.**"), to = doc.find("- **Derived parameters.**");
  ASSERT_NE(from, std::string::npos);
  ASSERT_NE(to, std::string::npos);
  std::string documented = doc.substr(from, to - from);
  for (char& c : documented)
    if (c == '\n') c = ' ';
  std::set<std::string> listed;  // every `...` span of the paragraph
  for (size_t at = documented.find('`'); at != std::string::npos;) {
    const size_t end = documented.find('`', at + 1);
    if (end == std::string::npos) break;
    std::string unit = documented.substr(at + 1, end - at - 1);
    while (unit.find("  ") != std::string::npos) unit.erase(unit.find("  "), 1);
    listed.insert(unit);
    at = documented.find('`', end + 1);
  }
  std::set<std::string> known;
  const std::string all = known_units() + ", ";
  for (size_t at = 0, comma; (comma = all.find(", ", at)) != std::string::npos; at = comma + 2)
    known.insert(all.substr(at, comma - at));
  ASSERT_GE(known.size(), 30u);
  for (const std::string& unit : known) {
    EXPECT_TRUE(listed.count(unit)) << "unit '" << unit << "' is not documented";
    EXPECT_TRUE(find_unit(unit).has_value()) << unit;
  }
  EXPECT_FALSE(find_unit("furlong").has_value());
}

TEST(DerivedParameters, DependencyOrderAndValues) {
  // Written before what they use; units of the base parameters converted first.
  const Model model = read_model_text(crank("  hip_x: {value: -a, unit: m, doc: mirrored}\n"
                                            "  m_link: rho*w*th*(b + d)\n"
                                            "  l: hip_x^2/a + b\n"
                                            "  a: {value: 38, unit: mm}\n"
                                            "  b: {value: 0.1, unit: m}\n"
                                            "  d: {value: 5, unit: cm}\n"
                                            "  rho: 2700\n  w: 0.02\n  th: 0.005\n"
                                            "  half_pi: pi/2\n"),
                                      "p.yaml");
  ASSERT_EQ(model.parameters.size(), 7u);  // a, b, d, rho, w, th, half_pi: the run-time values
  EXPECT_EQ(model.parameters[0].name, "a");
  EXPECT_EQ(model.parameters[6].name, "half_pi");  // an expression of no parameter is a base one
  EXPECT_DOUBLE_EQ(value_of(model, "half_pi"), M_PI / 2);
  ASSERT_EQ(model.derived.size(), 3u);
  EXPECT_DOUBLE_EQ(value_of(model, "hip_x"), -0.038);
  EXPECT_DOUBLE_EQ(value_of(model, "m_link"), 2700 * 0.02 * 0.005 * 0.15);
  EXPECT_DOUBLE_EQ(value_of(model, "l"), 0.038 + 0.1);
  // hip_x comes before l, which uses it.
  EXPECT_LT(model.derived_index("hip_x"), model.derived_index("l"));
  EXPECT_EQ(model.derived[static_cast<size_t>(model.derived_index("l"))].uses,
            (std::vector<std::string>{"a", "b", "hip_x"}));
}

// --set of a base parameter moves what is derived from it: the crank pin follows l = 2 a + b.
TEST(DerivedParameters, SetOfABaseParameterMovesTheDerivedOnesInTheSolver) {
  const Model model = read_model_text(crank("  l: 2*a + b\n  a: 0.1\n  b: 0.05\n"), "p.yaml");
  std::vector<double> values = model.default_parameters();
  apply_overrides(model, {"a=0.3"}, values);
  EXPECT_DOUBLE_EQ(model.derived_values(values)[0], 0.65);
  numeric::ReferenceSolver solver(model, values);
  solver.assemble(0);
  std::vector<double> row(column_names(model).size());
  ASSERT_EQ(solver.solve(0.5, row), numeric::Status::ok);
  const std::vector<std::string> names = column_names(model);
  auto column = [&](const std::string& n) {
    return row[static_cast<size_t>(std::find(names.begin(), names.end(), n) - names.begin())];
  };
  EXPECT_NEAR(column("P.x"), 0.65 * std::cos(0.5), 1e-14);
  EXPECT_NEAR(column("P.y"), 0.65 * std::sin(0.5), 1e-14);
  EXPECT_NEAR(column("c.x"), 0.325 * std::cos(0.5), 1e-14);  // com: [l/2, 0]
  // A derived parameter is not a run-time value of its own.
  try {
    apply_overrides(model, {"l=1"}, values);
    FAIL() << "--set of a derived parameter accepted";
  } catch (const ModelError& e) {
    EXPECT_STREQ(e.what(),
                 "<command line>: error: --set: parameter 'l' is derived (l = 2*a + b); set what "
                 "it depends on: a, b");
  }
}

TEST(DerivedParameters, CyclesAndUndefinedNamesAreLocated) {
  EXPECT_EQ(error_of(crank("  l: 2*a\n  a: b + 1\n  b: l/2\n")),
            "p.yaml:5:6: error: parameters defined in a cycle: l -> a -> b -> l (a derived "
            "parameter may not depend on itself)");
  EXPECT_EQ(error_of(crank("  l: {value: l + 1}\n")),
            "p.yaml:3:14: error: parameters defined in a cycle: l -> l (a derived parameter may "
            "not depend on itself)");
  EXPECT_EQ(error_of(crank("  l: 2*half\n  a: 1\n")),
            "p.yaml:3:6: error: parameter 'l' value '2*half': undefined name 'half' (parameters: "
            "l, a)");
  EXPECT_EQ(error_of(crank("  l: 2*t\n")),
            "p.yaml:3:6: error: parameter 'l' value '2*t' may not depend on time t");
  EXPECT_EQ(error_of(crank("  l: {value: 2*a, unit: mm}\n  a: 0.1\n")),
            "p.yaml:3:25: error: parameter 'l' is derived, so computed in SI from the SI values "
            "of a: its unit must be 'm', not 'mm'");
  EXPECT_EQ(error_of(crank("  l: 2*(a\n  a: 0.1\n"))
                .rfind("p.yaml:3:6: error: parameter 'l' "
                       "value '2*(a': syntax error",
                       0),
            0u);
}

}  // namespace
}  // namespace mechgen
