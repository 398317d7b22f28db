// Mass shorthands of links that are not one bar: a triangular (or polygonal) plate and several
// bars between a body's points. Checked against the triangle's textbook formulas and against a
// direct numerical integration over the material, at the defaults and after --set of a length.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "model/model.hpp"

namespace mechgen {
namespace {

struct Integrated {
  double mass = 0, cx = 0, cy = 0, inertia = 0;
};

// Midpoint-rule integration of density * thickness over the cells of a fine grid whose centres
// pass `inside`, then the inertia about the centre of mass.
template <class Inside>
Integrated integrate(Inside inside, double x0, double x1, double y0, double y1, double areal) {
  const int n = 1500;
  const double dx = (x1 - x0) / n, dy = (y1 - y0) / n;
  double m = 0, mx = 0, my = 0, mr2 = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = x0 + (i + 0.5) * dx, y = y0 + (j + 0.5) * dy;
      const double weight = inside(x, y) * areal * dx * dy;
      m += weight;
      mx += weight * x;
      my += weight * y;
      mr2 += weight * (x * x + y * y);
    }
  Integrated r{m, mx / m, my / m, 0};
  r.inertia = mr2 - m * (r.cx * r.cx + r.cy * r.cy);
  return r;
}

// Mass properties of body `name` at the given parameter values.
Integrated properties(const Model& model, const std::string& name,
                      const std::vector<double>& values) {
  const Body& body = model.bodies[static_cast<size_t>(model.body_index(name))];
  const GiNaC::exmap subs = model.substitutions(values);
  return {model.evaluate(body.mass.mass, subs), model.evaluate(body.mass.com.x, subs),
          model.evaluate(body.mass.com.y, subs), model.evaluate(body.mass.inertia, subs)};
}

double side2(double ax, double ay, double bx, double by) {
  return (ax - bx) * (ax - bx) + (ay - by) * (ay - by);
}

TEST(LinkMass, TriangularPlateOfTheExampleModel) {
  const Model model = read_model(MECHGEN_SOURCE_DIR "/models/plate_crank.yaml");
  for (const double e : {0.04, 0.05}) {  // the default, then --set e=0.05
    std::vector<double> values = model.default_parameters();
    apply_overrides(model, {"e=" + std::to_string(e)}, values);
    const Integrated p = properties(model, "coupler", values);
    // Independent: the triangle P(0,0), M(b,0), C(e cos phi, e sin phi) by its textbook formulas.
    const double b = 0.055, phi = M_PI / 3, cx = e * std::cos(phi), cy = e * std::sin(phi);
    const double areal = 2700 * 0.003, mass = areal * b * cy / 2;
    EXPECT_NEAR(p.mass, mass, 1e-15);
    EXPECT_NEAR(p.cx, (b + cx) / 3, 1e-15);
    EXPECT_NEAR(p.cy, cy / 3, 1e-15);
    // Polar moment about the centroid: m (a^2 + b^2 + c^2) / 36.
    const double sides = side2(0, 0, b, 0) + side2(b, 0, cx, cy) + side2(cx, cy, 0, 0);
    EXPECT_NEAR(p.inertia, mass * sides / 36, 1e-14 * mass * sides);
    // And by integration over the plate.
    const Integrated q = integrate(
        [&](double x, double y) {
          const double l1 = y, l2 = cy * x - cx * y, l3 = cy * (x - b) - (cx - b) * y;
          return (l1 >= 0 && l2 >= 0 && l3 <= 0) ? 1.0 : 0.0;
        },
        0, b, 0, cy, areal);
    EXPECT_NEAR(p.mass, q.mass, 2e-3 * mass);
    EXPECT_NEAR(p.inertia, q.inertia, 5e-3 * p.inertia);
  }
}

// The bell crank: bars B-M along x (length c) and B-R along -y (length c/2), width w: an L.
TEST(LinkMass, TwoBarsAsOneLink) {
  const Model model = read_model(MECHGEN_SOURCE_DIR "/models/plate_crank.yaml");
  for (const double c : {0.05, 0.06}) {  // the default, then --set c=0.06 (r = c/2 follows)
    std::vector<double> values = model.default_parameters();
    apply_overrides(model, {"c=" + std::to_string(c)}, values);
    const Integrated p = properties(model, "rocker", values);
    const double w = 0.01, areal = 2700 * 0.003, r = c / 2;
    // Two rectangles: [0, c] x [-w/2, w/2] and [-w/2, w/2] x [-r, 0] (overlapping at B, as two
    // separate bars are: each bar is a full w x L rectangle).
    const Integrated h = integrate(
        [&](double x, double y) { return std::abs(y) <= w / 2 && x >= 0 && x <= c ? 1.0 : 0.0; }, 0,
        c, -w / 2, w / 2, areal);
    const Integrated v = integrate(
        [&](double x, double y) { return std::abs(x) <= w / 2 && y <= 0 && y >= -r ? 1.0 : 0.0; },
        -w / 2, w / 2, -r, 0, areal);
    const double m = h.mass + v.mass;
    const double cx = (h.mass * h.cx + v.mass * v.cx) / m, cy = (h.mass * h.cy + v.mass * v.cy) / m;
    const double inertia = h.inertia + h.mass * side2(h.cx, h.cy, cx, cy) + v.inertia +
                           v.mass * side2(v.cx, v.cy, cx, cy);
    EXPECT_NEAR(p.mass, areal * w * (c + r), 1e-15);
    EXPECT_NEAR(p.mass, m, 1e-6 * m);
    EXPECT_NEAR(p.cx, cx, 1e-6 * c);
    EXPECT_NEAR(p.cy, cy, 1e-6 * c);
    EXPECT_NEAR(p.inertia, inertia, 1e-5 * inertia);
  }
}

// A clockwise square plate gives the same as the counter-clockwise one: m a^2 / 6 about the centre.
TEST(LinkMass, PlateOrientationAndErrors) {
  auto model_with = [](const std::string& plate) {
    return "name: m\nparameters: {s: 0.1}\nbodies:\n"
           "  - {name: g, ground: true, points: {A: [0, 0]}}\n"
           "  - name: p\n    points: {A: [0, 0], B: [s, 0], C: [s, s], D: [0, s], E: [2*s, 0]}\n"
           "    mass: {plate: " +
           plate +
           ", thickness: 0.01, density: 1000}\n"
           "joints:\n  - {name: j, type: revolute, first: g, second: p, point: A}\n"
           "drivers:\n  - {name: d, joint: j, kind: angle, value: t}\nstep: {t0: 0, t1: 1}\n";
  };
  for (const std::string order : {"[A, B, C, D]", "[A, D, C, B]"}) {
    const Model model = read_model_text(model_with(order), "m.yaml");
    const Integrated p = properties(model, "p", model.default_parameters());
    const double mass = 1000 * 0.01 * 0.01;
    EXPECT_NEAR(p.mass, mass, 1e-15) << order;
    EXPECT_NEAR(p.cx, 0.05, 1e-15) << order;
    EXPECT_NEAR(p.cy, 0.05, 1e-15) << order;
    EXPECT_NEAR(p.inertia, mass * 0.01 / 6, 1e-18) << order;
  }
  auto error = [&](const std::string& plate) {
    try {
      read_model_text(model_with(plate), "m.yaml");
    } catch (const ModelError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(error("[A, B, E]"),
            "m.yaml:7:19: error: mass of body 'p': the plate's points enclose no area");
  EXPECT_EQ(error("[A, B]"),
            "m.yaml:7:19: error: mass of body 'p': plate must list at least three of the body's "
            "points");
  EXPECT_EQ(error("[A, B, Z]"), "m.yaml:7:26: error: mass of body 'p': body has no point 'Z'");
}

}  // namespace
}  // namespace mechgen
