// Link loads and the ground reaction (runtime/analysis/) against hand closed forms of statics
// (a cantilever and a simply supported bar), the dynamic equilibrium of every PASIBOT body, and
// the floor reaction of the momentum rate of all bodies.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/free_body.hpp"
#include "analysis/ground_reaction.hpp"
#include "analysis/link_loads.hpp"
#include "model/model.hpp"
#include "sweep/sweep.hpp"

namespace mechgen::analysis {
namespace {

constexpr double kG = 9.81;

std::string model_path(const std::string& name) {
  return std::string(MECHGEN_SOURCE_DIR) + "/models/" + name + ".yaml";
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

SweepResult sweep(const Model& model, const std::string& solver, int samples = 0) {
  SweepOptions options = default_sweep(model);
  options.solver = solver;
  if (samples > 0) options.samples = samples;
  return run_sweep(model, options);
}

// A 20 x 5 mm aluminium bar of length L pinned to the floor at A and held still at th0 by a
// motor: a cantilever under its own weight. The floor (the "foot", heel H, toe T) has a mass too.
const char* const kCantilever = R"(
name: cantilever
parameters: {L: 0.5, th0: 0.3, m_floor: 2}
bodies:
  - name: floor
    ground: true
    points: {H: [-0.1, 0], A: [0, 0.5], T: [0.3, 0]}
    mass: {mass: m_floor, com: [0.05, 0], inertia: 0.01}
  - name: arm
    points: {A: [0, 0], B: [L, 0]}
    mass: {bar: [A, B], width: 0.02, thickness: 0.005, density: 2700}
    assembly: th0
joints:
  - {name: pivot, type: revolute, first: floor, second: arm, point: A}
drivers:
  - {name: hold, joint: pivot, kind: angle, value: th0}
step: {t0: 0, t1: 1, samples: 3}
)";

// The same bar, level, on a pin at A and a roller (pin in a horizontal slot) at B, with a load P
// at its middle C: simply supported.
const char* const kSimplySupported = R"(
name: beam
parameters: {L: 0.4, P: 30}
bodies:
  - name: floor
    ground: true
    points: {A: [0, 0], R: [L, 0]}
  - name: bar
    points: {A: [0, 0], C: [L/2, 0], B: [L, 0]}
    mass: {bar: [A, B], width: 0.02, thickness: 0.005, density: 2700}
joints:
  - {name: pin, type: revolute, first: floor, second: bar, point: A}
  - {name: roller, type: pin_in_slot, first: floor, second: bar, point: B,
     line: {through: [0, 0], direction: [1, 0]}}
forces:
  - {name: load, type: force, body: bar, point: C, value: [0, -P]}
step: {t0: 0, t1: 1, samples: 2}
)";

BeamLoads beam_of(const Model& model, const SweepResult& result, const std::string& body_name,
                  size_t row = 0) {
  const std::vector<double> parameters = model.default_parameters();
  const FreeBodies bodies(model, parameters, result.columns);
  const int body = model.body_index(body_name);
  const std::optional<BarAxis> axis = bar_axis(model, body, model.substitutions(parameters));
  EXPECT_TRUE(axis.has_value());
  EXPECT_TRUE(axis->distributed);
  const std::vector<double>& r = result.rows[row];
  return beam_loads(bodies.at(r)[static_cast<size_t>(body)], *axis, bodies.point(axis->from, r),
                    bodies.point(axis->to, r), bodies.gravity(), 40);
}

TEST(LinkLoads, CantileverUnderItsWeightMatchesTheBeamFormulas) {
  const Model model = read_model_text(kCantilever, "cantilever.yaml");
  const SweepResult result = sweep(model, "numeric");
  const double length = 0.5, th0 = 0.3;
  const double w = 2700 * 0.02 * 0.005 * kG;  // weight per metre
  const BeamLoads beam = beam_of(model, result, "arm");
  EXPECT_NEAR(beam.length, length, 1e-12);
  ASSERT_GE(beam.stations.size(), 41u);
  for (const BeamStation& st : beam.stations) {
    const double rest = length - st.s;  // the part of the bar beyond the cut
    EXPECT_NEAR(st.n, -w * std::sin(th0) * rest, 1e-9) << "s = " << st.s;
    EXPECT_NEAR(st.v, w * std::cos(th0) * rest, 1e-9) << "s = " << st.s;
    EXPECT_NEAR(st.m, -w * std::cos(th0) * rest * rest / 2, 1e-9) << "s = " << st.s;
  }
  // Root: the motor holds the whole weight's moment.
  EXPECT_NEAR(beam.stations.front().m, -w * length * length * std::cos(th0) / 2, 1e-9);
  EXPECT_NEAR(beam.end_n, 0, 1e-9);
  EXPECT_NEAR(beam.end_v, 0, 1e-9);
  EXPECT_NEAR(beam.end_m, 0, 1e-9);
}

TEST(LinkLoads, SimplySupportedBarWithAMidpointLoadMatchesTheBeamFormulas) {
  const Model model = read_model_text(kSimplySupported, "beam.yaml");
  const SweepResult result = sweep(model, "numeric");
  const double length = 0.4, load = 30;
  const double w = 2700 * 0.02 * 0.005 * kG;
  const double support = load / 2 + w * length / 2;  // each end's reaction
  const BeamLoads beam = beam_of(model, result, "bar");
  for (const BeamStation& st : beam.stations) {
    const double s = st.s, past = s >= length / 2 ? 1.0 : 0.0;
    EXPECT_NEAR(st.n, 0, 1e-9) << "s = " << s;
    // Just past s: the roller's reaction at s = L closes the diagram.
    const double roller = s >= length ? support : 0.0;
    EXPECT_NEAR(st.v, support - w * s - load * past + roller, 1e-9) << "s = " << s;
    EXPECT_NEAR(st.m, support * s - w * s * s / 2 - load * std::max(0.0, s - length / 2), 1e-9)
        << "s = " << s;
  }
  // The classic figures: PL/4 + wL^2/8 at midspan, and the jump of V by P under the load.
  const auto mid = std::find_if(beam.stations.begin(), beam.stations.end(),
                                [&](const BeamStation& st) { return st.s == length / 2; });
  ASSERT_NE(mid, beam.stations.end());
  EXPECT_NEAR(mid->m, load * length / 4 + w * length * length / 8, 1e-9);
  EXPECT_NEAR(mid->v_before - mid->v, load, 1e-9);

  // The same diagram through link_diagram(), by name; the floor is no bar.
  const BeamLoads by_name = link_diagram(model, model.default_parameters(), result.columns,
                                         result.rows.front(), "bar", 40);
  ASSERT_EQ(by_name.stations.size(), beam.stations.size());
  for (size_t i = 0; i < beam.stations.size(); ++i)
    EXPECT_EQ(by_name.stations[i].m, beam.stations[i].m);
  EXPECT_THROW(
      link_diagram(model, model.default_parameters(), result.columns, result.rows.front(), "floor"),
      std::invalid_argument);

  // The report: stresses of the 20 x 5 mm section (bending about the 5 mm side).
  const LinkLoadReport report = link_loads(model, model.default_parameters(), result.columns,
                                           result.rows, LinkLoadOptions{276e6, 64});
  ASSERT_EQ(report.links.size(), 1u);
  const LinkResult& bar = report.links.front();
  const double area = 0.02 * 0.005, modulus = 0.005 * 0.02 * 0.02 / 6;
  EXPECT_NEAR(bar.m.value, load * length / 4 + w * length * length / 8, 1e-9);
  EXPECT_NEAR(bar.sigma.value, bar.m.value / modulus, 1e-6 * bar.sigma.value);
  EXPECT_NEAR(bar.tau.value, 1.5 * support / area, 1e-6 * bar.tau.value);
  EXPECT_NEAR(bar.safety, 276e6 / bar.sigma.value, 1e-9 * bar.safety);
}

// Joint forces, driver efforts, applied loads, weight and d'Alembert inertia of every moving body
// add up to zero force and zero moment about its centre of mass at every sample. Forces are
// compared with the largest joint force, moments with it at the model's largest point distance.
// Returns that largest joint force.
double expect_every_body_in_equilibrium(const Model& model, const SweepResult& result) {
  const FreeBodies free_bodies(model, model.default_parameters(), result.columns);
  double scale = 0, arm = 0;
  for (const std::vector<double>& row : result.rows) {
    for (const FreeBody& b : free_bodies.at(row))
      for (const PointLoad& l : b.forces) scale = std::max(scale, l.force.norm());
    for (const auto& [name, body] : model.named_points())
      arm = std::max(arm, free_bodies.point(name, row).norm());
  }
  EXPECT_GT(scale, 0);
  EXPECT_GT(arm, 0);
  for (const std::vector<double>& row : result.rows)
    for (const FreeBody& b : free_bodies.at(row)) {
      const std::string& name = model.bodies[static_cast<size_t>(b.body)].name;
      if (model.bodies[static_cast<size_t>(b.body)].ground) continue;
      const Resultant r = resultant(b, free_bodies.gravity());
      EXPECT_LT(r.force.norm(), 1e-9 * scale) << model.name << " " << name;
      EXPECT_LT(std::abs(r.moment), 1e-9 * scale * arm) << model.name << " " << name;
    }
  return scale;
}

// Every moving body of PASIBOT over a step is in dynamic equilibrium, and each bar's N, V, M
// vanish past its last load.
TEST(LinkLoads, EveryPasibotBodyIsInDynamicEquilibrium) {
  const Model model = read_model(model_path("pasibot"));
  const SweepResult result = sweep(model, "generated");
  const std::vector<double> parameters = model.default_parameters();
  const double scale = expect_every_body_in_equilibrium(model, result);
  ASSERT_GT(scale, 100.0);
  const LinkLoadReport report = link_loads(model, parameters, result.columns, result.rows);
  EXPECT_EQ(report.links.size(), 22u);  // every moving body but the hip plate
  ASSERT_EQ(report.skipped.size(), 1u);
  EXPECT_EQ(report.skipped.front().substr(0, 4), "l13:");
  EXPECT_LT(report.largest_end_residual, 1e-9 * scale);
  ASSERT_GE(report.critical, 0);
  for (const LinkResult& l : report.links) {
    EXPECT_NEAR(l.section.yield, 276e6, 1);
    EXPECT_GE(l.safety, report.links[static_cast<size_t>(report.critical)].safety);
  }
}

// Every kind of load the free bodies read: a prismatic joint's moment, a spring-damper, an applied
// force and torque, an angle driver.
TEST(LinkLoads, SliderCrankBodiesWithEveryKindOfLoadAreInEquilibrium) {
  const Model model = read_model(model_path("slider_crank"));
  const SweepResult result = sweep(model, "numeric", 61);
  expect_every_body_in_equilibrium(model, result);
  const LinkLoadReport report =
      link_loads(model, model.default_parameters(), result.columns, result.rows);
  EXPECT_FALSE(report.links.empty());
  EXPECT_LT(report.largest_end_residual, 1e-9 * expect_every_body_in_equilibrium(model, result));
}

// Euler buckling of the slider-crank's rod. At t = 0 (outer dead centre, rod on the x axis, slider
// at rest) the slider holds the gas load F0 = 100 N, the compressed spring k (0.1 - s0) = -25 N
// and its inertia m_s (-r w^2 (1 + r/L)) = -3.125 N, so the rod pushes it with 121.875 N: the
// rod's N just before the slider pin is -121.875 N. Its Euler load, pinned-pinned over L = 0.2 m,
// out of the plane (20 x 8 mm: I = 0.02 0.008^3 / 12), with E = 200 GPa, is pi^2 E I / L^2.
TEST(LinkLoads, CompressedRodGetsEulersBucklingLoad) {
  const std::string text =
      read_text(model_path("slider_crank")) + "material: {youngs_modulus: 200e9}\n";
  const Model model = read_model_text(text, "models/slider_crank.yaml");
  const SweepResult result = sweep(model, "numeric");
  ASSERT_EQ(result.rows.front()[0], 0.0);
  const BeamLoads rod =
      link_diagram(model, model.default_parameters(), result.columns, result.rows.front(), "rod");
  EXPECT_NEAR(rod.stations.back().s, 0.2, 1e-12);
  EXPECT_NEAR(rod.stations.back().n_before, -121.875, 1e-9);

  const LinkLoadReport report =
      link_loads(model, model.default_parameters(), result.columns, result.rows);
  const auto link = std::find_if(report.links.begin(), report.links.end(),
                                 [](const LinkResult& l) { return l.name == "rod"; });
  ASSERT_NE(link, report.links.end());
  const double inertia = 0.02 * 0.008 * 0.008 * 0.008 / 12;
  const double euler = M_PI * M_PI * 200e9 * inertia / (0.2 * 0.2);
  EXPECT_NEAR(link->section.buckling_inertia, inertia, 1e-24);
  EXPECT_NEAR(link->buckling_load, euler, 1e-9 * euler);
  EXPECT_LE(link->compression.value, -121.875 + 1e-9);  // the largest compression over the turn
  EXPECT_NEAR(link->buckling_safety, euler / -link->compression.value, 1e-12 * euler);
  EXPECT_TRUE(std::isnan(link->safety));  // no yield strength given

  // Without Young's modulus there is no buckling figure.
  const LinkLoadReport plain = link_loads(read_model(model_path("slider_crank")),
                                          model.default_parameters(), result.columns, result.rows);
  for (const LinkResult& l : plain.links) EXPECT_TRUE(std::isnan(l.buckling_load)) << l.name;
  // A material needs at least one of its values.
  EXPECT_THROW(read_model_text(read_text(model_path("slider_crank")) + "material: {}\n", "m.yaml"),
               ModelError);
}

// A carriage on a rail (prismatic joint) pushed back and forth by a length driver, its centre of
// mass off the joint point: the rail's moment and the driver's force are not zero. An explicit
// mass with a section: a beam with lumped weight and inertia.
const char* const kCarriage = R"(
name: carriage
parameters: {w: 2}
bodies:
  - name: floor
    ground: true
    points: {H: [-0.5, 0], O: [0, 0], T: [0.5, 0]}
  - name: carriage
    points: {Q: [0, 0], Z: [0.2, 0]}
    mass: {mass: 1.5, com: [0.1, 0.05], inertia: 0.01}
    section: {width: 0.02, thickness: 0.01}
joints:
  - {name: rail, type: prismatic, first: floor, second: carriage, point: Q,
     line: {through: [0, 0], direction: [1, 0]}, angle: 0}
drivers:
  - {name: push, joint: rail, kind: length, value: 0.1*sin(w*t)}
step: {t0: 0, t1: 3, samples: 31}
)";

TEST(LinkLoads, CarriageOnARailWithALengthDriverIsInEquilibrium) {
  const Model model = read_model_text(kCarriage, "carriage.yaml");
  const SweepResult result = sweep(model, "numeric");
  const double scale = expect_every_body_in_equilibrium(model, result);
  double largest_moment = 0, largest_push = 0;
  const auto column = [&](const std::string& name) {
    return static_cast<size_t>(std::find(result.columns.begin(), result.columns.end(), name) -
                               result.columns.begin());
  };
  for (const std::vector<double>& row : result.rows) {
    largest_moment = std::max(largest_moment, std::abs(row[column("rail.m")]));
    largest_push = std::max(largest_push, std::abs(row[column("push.effort")]));
  }
  EXPECT_GT(largest_moment, 1.0);  // m g 0.1 = 1.47 N m at rest, more with inertia
  EXPECT_GT(largest_push, 0.5);    // m 0.1 w^2 = 0.6 N at the turns
  const LinkLoadReport report =
      link_loads(model, model.default_parameters(), result.columns, result.rows);
  ASSERT_EQ(report.links.size(), 1u);
  EXPECT_FALSE(report.links.front().axis.distributed);
  EXPECT_LT(report.largest_end_residual, 1e-9 * scale);
}

// ---- ground reaction and ZMP --------------------------------------------------------------------

void expect_reactions_agree(const Model& model, const SweepResult& result) {
  const ZmpReport report = zmp_over(model, model.default_parameters(), result.columns, result.rows);
  double scale = 0;
  for (const ZmpSample& s : report.samples) scale = std::max(scale, s.reaction.force.norm());
  ASSERT_GT(scale, 0);
  EXPECT_LT(report.largest_disagreement, 1e-9 * scale) << model.name;
  const GiNaC::exmap subs = model.substitutions(model.default_parameters());
  for (const ZmpSample& s : report.samples) {
    ASSERT_TRUE(std::isfinite(s.zmp));
    // The centre of pressure of the momentum-rate reaction, on the same sole.
    const Body& ground = model.bodies[static_cast<size_t>(model.ground)];
    const auto local = [&](const std::string& name) -> Eigen::Vector2d {
      const BodyPoint* p = ground.find_point(name);
      return {model.evaluate(p->local.x, subs), model.evaluate(p->local.y, subs)};
    };
    const double zmp = centre_of_pressure(s.momentum, local(report.heel), local(report.toe));
    EXPECT_NEAR(zmp, s.zmp, 1e-9 * report.sole_length * std::max(1.0, std::abs(s.zmp)))
        << model.name << " t = " << s.t;
  }
}

TEST(GroundReaction, PasibotReactionEqualsTheMomentumRateOfAllBodies) {
  const Model model = read_model(model_path("pasibot"));
  expect_reactions_agree(model, sweep(model, "generated"));
  // The default sole is the foot l1's two points: heel E, toe F.
  EXPECT_EQ(sole_points(model, model.default_parameters(), "", ""),
            std::make_pair(std::string("E"), std::string("F")));
}

TEST(GroundReaction, SliderCrankWithSpringGasForceAndFrictionTorqueAgrees) {
  // Applied loads of every kind: the spring (internal, between the floor and the slider), the
  // gas force and the friction torque (external), and a prismatic joint's moment.
  const Model model = read_model(model_path("slider_crank"));
  expect_reactions_agree(model, sweep(model, "numeric", 61));
}

TEST(GroundReaction, CarriageOnARailAgrees) {
  const Model model = read_model_text(kCarriage, "carriage.yaml");
  expect_reactions_agree(model, sweep(model, "numeric"));
}

TEST(GroundReaction, ChebyshevLinkageAgrees) {
  const Model model = read_model(model_path("chebyshev"));
  expect_reactions_agree(model, sweep(model, "numeric", 61));
}

TEST(GroundReaction, StaticArmOnAWeightedFootHasItsZmpUnderTheCentreOfMass) {
  const Model model = read_model_text(kCantilever, "cantilever.yaml");
  const SweepResult result = sweep(model, "numeric");
  const ZmpReport report =
      zmp_over(model, model.default_parameters(), result.columns, result.rows, "H", "T");
  const double m_arm = 2700 * 0.02 * 0.005 * 0.5, m_floor = 2;
  const double x_arm = 0.25 * std::cos(0.3), x_floor = 0.05;
  const double x_zmp = (m_arm * x_arm + m_floor * x_floor) / (m_arm + m_floor);
  EXPECT_NEAR(report.sole_length, 0.4, 1e-12);
  for (const ZmpSample& s : report.samples) {
    EXPECT_NEAR(s.reaction.force.x(), 0, 1e-9);
    EXPECT_NEAR(s.reaction.force.y(), (m_arm + m_floor) * kG, 1e-9);
    EXPECT_NEAR(s.normal, (m_arm + m_floor) * kG, 1e-9);
    EXPECT_NEAR(s.zmp, x_zmp + 0.1, 1e-9);
    EXPECT_NEAR(s.heel_margin, x_zmp + 0.1, 1e-9);
    EXPECT_NEAR(s.toe_margin, 0.3 - x_zmp, 1e-9);
  }
  EXPECT_NEAR(report.min_margin, std::min(x_zmp + 0.1, 0.3 - x_zmp), 1e-9);
  EXPECT_EQ(report.inside, 3);
  EXPECT_THROW(zmp_over(model, model.default_parameters(), result.columns, result.rows, "Q", ""),
               ModelError);
}

TEST(ModelFormat, SectionsAndMaterialAreReadAndCheckedWithTheirLocation) {
  std::string text = kCantilever;
  text.replace(text.find("    assembly: th0"), 0,
               "    section: {area: 1e-4, inertia: 3e-9, fibre: 0.01, yield_strength: 2e8}\n");
  text += "material: {yield_strength: 1e8}\n";
  const Model model = read_model_text(text, "m.yaml");
  const GiNaC::exmap subs = model.substitutions(model.default_parameters());
  const auto section = section_properties(model, model.body_index("arm"), subs);
  ASSERT_TRUE(section.has_value());
  EXPECT_DOUBLE_EQ(section->area, 1e-4);
  EXPECT_DOUBLE_EQ(section->inertia, 3e-9);
  EXPECT_DOUBLE_EQ(section->fibre, 0.01);
  EXPECT_DOUBLE_EQ(section->yield, 2e8);  // the section's own, not the material's

  std::string bad = kCantilever;
  bad.replace(bad.find("    assembly: th0"), 0, "    section: {width: 0.02, depth: 1}\n");
  try {
    read_model_text(bad, "bad.yaml");
    FAIL() << "an unknown section key was accepted";
  } catch (const ModelError& error) {
    EXPECT_EQ(error.where().line, 12);
    EXPECT_NE(std::string(error.what()).find("unknown key 'depth'"), std::string::npos);
  }
  std::string negative = kCantilever + std::string("material: {yield_strength: -1}\n");
  EXPECT_THROW(read_model_text(negative, "neg.yaml"), ModelError);
}

}  // namespace
}  // namespace mechgen::analysis
