// Planar loops inside spatial models in closed form (generator/spatial_planar_loops.hpp): random
// Grashof crank-rocker four-bars in randomly oriented planes (pivots offset at random along the
// axis, axes written either way) are closed by the RRR dyad with no Newton-Raphson, as are a
// four-bar closed by an in-plane revolute and a spherical joint (out-of-plane coordinates held at
// 0, the imported five-bars' pattern) and loops sharing a pivot (the imported Delta's), and the
// derivation's outputs evaluated numerically along a full crank turn (each sample warm-started
// from the previous one, as a kernel in a sweep) equal the numeric solver's; a non-Grashof
// four-bar driven past its limit makes the kernel built on demand report Status::unreachable in
// the loop's group, where the numeric solver cannot assemble either.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "ondemand_test_support.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial_derivation.hpp"

namespace mechgen::gen {
namespace {

using Vec = std::array<double, 3>;

std::string num(double x) {
  std::ostringstream o;
  o.precision(17);
  o << x;
  return o.str();
}
std::string vec(const Vec& v) {
  return "[" + num(v[0]) + ", " + num(v[1]) + ", " + num(v[2]) + "]";
}

// A four-bar in the plane: ground pivots A = (0, 0), B = (ground, 0); crank A-P, coupler P-M,
// rocker M-B, assembled at crank angle crank0 on the intersection with M above the line P-B.
struct FourBar {
  double crank, coupler, rocker, ground, crank0;
};

// The unit quaternion q (w, x, y, z) applied to v.
Vec rotate(const std::array<double, 4>& q, const Vec& v) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  return {
      (1 - 2 * (y * y + z * z)) * v[0] + 2 * (x * y - w * z) * v[1] + 2 * (x * z + w * y) * v[2],
      2 * (x * y + w * z) * v[0] + (1 - 2 * (x * x + z * z)) * v[1] + 2 * (y * z - w * x) * v[2],
      2 * (x * z - w * y) * v[0] + 2 * (y * z + w * x) * v[1] + (1 - 2 * (x * x + y * y)) * v[2]};
}

// The four-bar as a spatial model in the plane turned by q and shifted by `origin`, each pivot
// offset along the axis by offset[k], joint k's axis written as -n where flip[k].
std::string four_bar_model(const FourBar& f, const std::array<double, 4>& q, const Vec& origin,
                           const std::array<double, 4>& offset, const std::array<bool, 4>& flip) {
  const double px = f.crank * std::cos(f.crank0), py = f.crank * std::sin(f.crank0);
  const double dx = f.ground - px, dy = -py, d2 = dx * dx + dy * dy;
  const double e = (d2 + f.coupler * f.coupler - f.rocker * f.rocker) / 2;
  const double h = std::sqrt(f.coupler * f.coupler * d2 - e * e);
  const double mx = px + (e * dx - h * dy) / d2, my = py + (e * dy + h * dx) / d2;
  const std::array<std::array<double, 2>, 4> pivot{{{0, 0}, {px, py}, {mx, my}, {f.ground, 0}}};
  std::array<std::string, 4> at;
  for (size_t k = 0; k < 4; ++k) {
    const Vec r = rotate(q, {pivot[k][0], pivot[k][1], offset[k]});
    at[k] = vec({r[0] + origin[0], r[1] + origin[1], r[2] + origin[2]});
  }
  const Vec n = rotate(q, {0, 0, 1});
  const auto axis = [&](size_t k) { return vec(flip[k] ? Vec{-n[0], -n[1], -n[2]} : n); };
  const std::string mass = "mass: {mass: 0.5, com: " + at[1] + ", inertia: [1e-3, 2e-3, 3e-3]}";
  return "name: four_bar\ndimension: spatial\ngravity: [0, -9.81, 0]\n"
         "parameters:\n  w: {value: 2, unit: rad/s}\n"
         "bodies:\n  - {name: ground, ground: true}\n"
         "  - {name: crank, " +
         mass + "}\n  - {name: coupler, " + mass +
         "}\n"
         "  - {name: rocker, " +
         mass +
         "}\n"
         "joints:\n"
         "  - {name: jA, type: revolute, first: ground, second: crank, s: " +
         axis(0) + ", s0: " + at[0] +
         "}\n"
         "  - {name: jP, type: revolute, first: crank, second: coupler, s: " +
         axis(1) + ", s0: " + at[1] +
         "}\n"
         "  - {name: jM, type: revolute, first: rocker, second: coupler, s: " +
         axis(2) + ", s0: " + at[2] +
         "}\n"
         "  - {name: jB, type: revolute, first: ground, second: rocker, s: " +
         axis(3) + ", s0: " + at[3] +
         "}\n"
         "drivers:\n  - {name: crank_angle, joint: jA, kind: angle, value: w*t}\n"
         "step: {t0: 0, t1: 2*pi/w, samples: 37}\n";
}

double evaluate(const GiNaC::ex& e, const std::map<std::string, double>& values) {
  GiNaC::exmap subs;
  for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (GiNaC::is_a<GiNaC::symbol>(*it))
      subs[*it] = values.at(GiNaC::ex_to<GiNaC::symbol>(*it).get_name());
  return GiNaC::ex_to<GiNaC::numeric>(GiNaC::evalf(e.subs(subs))).to_double();
}

double kernel_against_numeric(const std::string& text, double t_end, size_t angles,
                              const std::vector<std::string>& groups);

// A random crank-rocker (Grashof: shortest + longest < the other two, the crank the shortest)
// in a random plane; returns the worst difference from the numeric solver over a crank turn.
double random_crank_rocker_against_numeric(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  FourBar f{};
  do {
    f = {0.05, 0.05 + 0.15 * u(rng), 0.05 + 0.15 * u(rng), 0.05 + 0.15 * u(rng), 6.3 * u(rng)};
  } while (f.crank + std::max({f.coupler, f.rocker, f.ground}) >
           f.coupler + f.rocker + f.ground - std::max({f.coupler, f.rocker, f.ground}) - 0.02);
  std::normal_distribution<double> g;
  std::array<double, 4> q{g(rng), g(rng), g(rng), g(rng)};
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& x : q) x /= norm;
  const std::string text = four_bar_model(f, q, {u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5},
                                          {0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng)},
                                          {u(rng) < 0.5, u(rng) < 0.5, u(rng) < 0.5, u(rng) < 0.5});
  return kernel_against_numeric(text, M_PI, 3, {"planar_loop_"});
}

// The derivation's outputs evaluated numerically at `samples` times over [0, t_end], each
// warm-started from the previous one (as a kernel in a sweep), against the numeric solver: the
// worst difference of a joint coordinate, body position or rotation entry. The model's driver is
// crank_angle on its first joint; no Newton-Raphson, `angles` warm starts, and a plan line
// starting with each of `groups` (closed forms).
double kernel_against_numeric(const std::string& text, double t_end, size_t angles,
                              const std::vector<std::string>& groups) {
  const SpatialModel model = read_spatial_model_text(text, "four_bar.yaml");
  const SpatialGraph graph = build_spatial_graph(model);
  const SpatialDerivation d = derive_spatial(model, graph);
  EXPECT_TRUE(d.closure_start.empty()) << text;  // no Newton-Raphson coordinates
  EXPECT_EQ(d.angle_start.size(), angles);
  for (const std::string& group : groups)
    EXPECT_TRUE(std::any_of(d.plan.begin(), d.plan.end(),
                            [&](const std::string& line) { return line.rfind(group, 0) == 0; }))
        << group << "\n"
        << text;
  // The outputs compared: every joint coordinate, every body's position and rotation; the warm
  // starts (the previous sample's coordinates) from the kernel's own outputs.
  std::map<std::string, GiNaC::ex> outputs;
  std::map<std::string, std::string> warm_of;  // s.closure.w[k] <- its wnext output's symbol
  for (const SpatialOutput& o : d.kinematics) {
    if (o.target.rfind("s.closure.wnext[", 0) == 0)
      warm_of["s.closure.w[" + o.target.substr(16)] =
          GiNaC::ex_to<GiNaC::symbol>(o.value).get_name();
    if (o.target.rfind("s.joints.", 0) == 0 && o.target.back() != 'd') outputs[o.target] = o.value;
    if (o.target.rfind("s.bodies.", 0) == 0) outputs[o.target] = o.value;
  }
  EXPECT_EQ(warm_of.size(), angles);
  std::set<GiNaC::ex, GiNaC::ex_is_less> needed;
  std::vector<GiNaC::ex> pending;
  for (const auto& [target, value] : outputs) pending.push_back(value);
  std::map<GiNaC::ex, GiNaC::ex, GiNaC::ex_is_less> definition;
  for (const auto& [symbol, value] : d.definitions) definition[symbol] = value;
  while (!pending.empty()) {
    const GiNaC::ex e = pending.back();
    pending.pop_back();
    for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it)
      if (GiNaC::is_a<GiNaC::symbol>(*it) && needed.insert(*it).second && definition.count(*it))
        pending.push_back(definition.at(*it));
  }
  const std::vector<double> parameters = model.common.default_parameters();
  const spatial::SpatialSolver solver(model, parameters);
  spatial::SpatialState st;
  // The warm starts: the assembly's at first, then the previous sample's coordinates (carried
  // without rates: the samples are near enough for the nearer root to be the motion's).
  std::map<std::string, double> previous{{"s.closure.wt", 0}, {"s.closure.follow", 1}};
  for (size_t k = 0; k < d.angle_start.size(); ++k) {
    const std::string index = "[" + std::to_string(k) + "]";
    previous["s.closure.w" + index] = d.angle_start[k];
    previous["s.closure.wd" + index] = previous["s.closure.wdd" + index] = 0;
  }
  double worst = 0;
  const int samples = 25;
  for (int i = 0; i < samples; ++i) {
    const double t = t_end * i / (samples - 1);
    solver.solve(t, st);
    std::map<std::string, double> values = previous;
    values["p.w"] = parameters[0];
    values["in.t"] = t;
    values["in.crank_angle"] = st.q[graph.joint_column[0]];
    values["in.crank_angle_d"] = st.qd[graph.joint_column[0]];
    values["in.crank_angle_dd"] = st.qdd[graph.joint_column[0]];
    for (const auto& [symbol, value] : d.definitions)
      if (needed.count(symbol)) values[symbol.get_name()] = evaluate(value, values);
    for (size_t j = 0; j < model.joints.size(); ++j) {
      const size_t n = model.joints[j].columns.size();
      for (size_t k = 0; k < n; ++k) {
        const std::string q = n == 1 ? "q" : "q" + std::to_string(k + 1);
        const double got =
            evaluate(outputs.at("s.joints." + model.joints[j].name + "." + q), values);
        worst =
            std::max(worst, std::abs(got - st.q[static_cast<size_t>(graph.joint_column[j]) + k]));
      }
    }
    for (size_t b = 0; b < model.bodies.size(); ++b) {
      if (model.bodies[b].ground) continue;
      const std::string o = "s.bodies." + model.bodies[b].name + ".";
      const spatial::Pose pose = solver.body_pose(st, static_cast<int>(b));
      const spatial::V3 com = geometry::apply(pose, solver.instance().com[b]);  // s.bodies.b.x
      for (int k = 0; k < 3; ++k)
        worst = std::max(worst, std::abs(evaluate(outputs.at(o + "xyz"[k]), values) -
                                         com[static_cast<size_t>(k)]));
      for (size_t k = 0; k < 9; ++k)
        worst = std::max(worst,
                         std::abs(evaluate(outputs.at(o + "R[" + std::to_string(k) + "]"), values) -
                                  pose.R.m[k]));
    }
    for (const auto& [w, q] : warm_of) previous[w] = values.at(q);
  }
  return worst;
}

TEST(SpatialPlanarLoop, RandomCrankRockersInRandomPlanesEqualTheNumericSolver) {
  std::mt19937 rng(2026);
  double worst = 0;
#if defined(MECHGEN_SANITIZE_BUILD)
  const int trials = 1;  // each trial derives and evaluates symbolically: ~50 s under them
#else
  const int trials = 4;
#endif
  for (int trial = 0; trial < trials; ++trial)
    worst = std::max(worst, random_crank_rocker_against_numeric(rng));
  EXPECT_LT(worst, 1e-10);
  std::cout << "random crank-rockers in random planes, closed-form dyad against numeric: worst "
            << worst << "\n";
}

// The pivots of a four-bar in the plane z = z0 (A, P, M, B as four_bar_model).
std::array<Vec, 4> four_bar_pivots(const FourBar& f, double z0) {
  const double px = f.crank * std::cos(f.crank0), py = f.crank * std::sin(f.crank0);
  const double dx = f.ground - px, dy = -py, d2 = dx * dx + dy * dy;
  const double e = (d2 + f.coupler * f.coupler - f.rocker * f.rocker) / 2;
  const double h = std::sqrt(f.coupler * f.coupler * d2 - e * e);
  return {{{0, 0, z0},
           {px, py, z0},
           {px + (e * dx - h * dy) / d2, py + (e * dy + h * dx) / d2, z0},
           {f.ground, 0, z0}}};
}

std::string body(const std::string& name, const Vec& com) {
  return "  - {name: " + name + ", mass: {mass: 0.5, com: " + vec(com) +
         ", inertia: [1e-3, 2e-3, 3e-3]}}\n";
}
std::string revolute(const std::string& name, const std::string& first, const std::string& second,
                     const Vec& s, const Vec& s0) {
  return "  - {name: " + name + ", type: revolute, first: " + first + ", second: " + second +
         ", s: " + vec(s) + ", s0: " + vec(s0) + "}\n";
}

// An imported five-bar's pattern on a four-bar (issue 21 item 4): the coupler ends in a
// revolute whose axis lies in the plane (normal to the coupler) and a spherical joint at the
// rocker, as the Extended URDF five-bars close their loop. Their out-of-plane coordinates stay 0.
TEST(SpatialPlanarLoop, OutOfPlaneJointsHeldAtZeroEqualTheNumericSolver) {
  const FourBar f{0.05, 0.15, 0.12, 0.14, 1.0};
  const std::array<Vec, 4> p = four_bar_pivots(f, 0.02);
  const Vec o{(p[1][0] + p[2][0]) / 2, (p[1][1] + p[2][1]) / 2, 0.05};
  const double lx = p[2][0] - p[1][0], ly = p[2][1] - p[1][1], l = std::hypot(lx, ly);
  const std::string text =
      "name: held_loop\ndimension: spatial\ngravity: [0, -9.81, 0]\n"
      "parameters:\n  w: {value: 2, unit: rad/s}\nbodies:\n  - {name: ground, ground: true}\n" +
      body("crank", p[1]) + body("coupler", o) + body("link2", p[2]) + body("rocker", p[3]) +
      "joints:\n" + revolute("jA", "ground", "crank", {0, 0, 1}, p[0]) +
      revolute("jP", "crank", "coupler", {0, 0, -1}, p[1]) +
      revolute("jO", "coupler", "link2", {-ly / l, lx / l, 0}, o) +
      "  - {name: jM, type: spherical, first: link2, second: rocker, s0: " + vec(p[2]) + "}\n" +
      revolute("jB", "ground", "rocker", {0, 0, 1}, p[3]) +
      "drivers:\n  - {name: crank_angle, joint: jA, kind: angle, value: w*t}\n"
      "step: {t0: 0, t1: 2*pi/w, samples: 37}\n";
  const double worst = kernel_against_numeric(text, M_PI, 3, {"planar_loop_held_"});
  EXPECT_LT(worst, 1e-10);
  std::cout << "four-bar closed by an in-plane revolute and a spherical joint, out-of-plane "
               "coordinates held at 0: worst "
            << worst << "\n";
}

// Two revolutes on one pivot (a Delta's rod ends): the four-bar's coupler and rocker meet at M
// through a plate turning about M, held by a bar from its corner Q to the ground. The first loop
// gives the coupler and rocker and the plate-rocker sum, the plate's loop its angle, then the
// last revolute its own.
TEST(SpatialPlanarLoop, SharedPivotsEqualTheNumericSolver) {
  const FourBar f{0.05, 0.15, 0.12, 0.14, 1.0};
  const std::array<Vec, 4> p = four_bar_pivots(f, 0);
  const Vec q{p[2][0] + 0.03, p[2][1] + 0.05, 0.01}, c{q[0] + 0.02, q[1] - 0.12, -0.02};
  const Vec n{0, 0, 1};
  const std::string text =
      "name: shared_pivot\ndimension: spatial\ngravity: [0, -9.81, 0]\n"
      "parameters:\n  w: {value: 0.5, unit: rad/s}\nbodies:\n  - {name: ground, ground: true}\n" +
      body("crank", p[1]) + body("coupler", p[2]) + body("plate", q) + body("rocker", p[3]) +
      body("bar", c) + "joints:\n" + revolute("jA", "ground", "crank", n, p[0]) +
      revolute("jP", "crank", "coupler", n, p[1]) + revolute("jT", "coupler", "plate", n, p[2]) +
      revolute("jM", "plate", "rocker", {0, 0, -1}, {p[2][0], p[2][1], 0.03}) +
      revolute("jB", "ground", "rocker", n, p[3]) + revolute("jQ", "plate", "bar", n, q) +
      revolute("jC", "ground", "bar", n, c) +
      "drivers:\n  - {name: crank_angle, joint: jA, kind: angle, value: w*t}\n"
      "step: {t0: 0, t1: 1, samples: 21}\n";
  const double worst = kernel_against_numeric(text, 1, 6, {"planar_loop_held_", "one_angle_"});
  EXPECT_LT(worst, 1e-10);
  std::cout << "shared pivots: worst " << worst << "\n";
}

// A non-Grashof four-bar (1 + 2.5 > 1 + 1): the crank cannot pass 0.863 rad (|P - B| = 2, the
// coupler and rocker stretched). The kernel built on demand sweeps it within the limit; driven
// from 0.3 rad over 2 rad its dyad group reports unreachable (exit 1 naming it, no CSV), where
// the numeric solver fails to assemble too.
TEST(SpatialPlanarLoop, NonGrashofDrivenPastItsLimitIsUnreachableInTheLoopsGroup) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("mechgen_planar_loop_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string text = four_bar_model({1, 1, 1, 2.5, 0.3}, {0.5, 0.5, 0.5, 0.5}, {0.1, 0.2, 0.3},
                                    {0, 0.2, -0.1, 0.3}, {false, true, false, true});
  // The generator samples the model's own step: w = 0.5 keeps it within the limit (crank 0.3 ..
  // 0.8 rad); w = 2 at run time drives the crank to 2.3 rad.
  text = test::replaced(text, "value: 2, unit: rad/s", "value: 0.5, unit: rad/s");
  text = test::replaced(text, "t1: 2*pi/w, samples: 37", "t1: 1, samples: 41");
  std::ofstream(dir / "four_bar.yaml") << text;
  const std::string model = (dir / "four_bar.yaml").string();
  const std::string cache = " --cache " + (dir / "cache").string();
  std::string err;
  ASSERT_EQ(
      test::run_mechgen("sweep " + model + cache + " --out " + (dir / "w.csv").string(), dir, err),
      0)
      << err;
  EXPECT_EQ(
      test::run_mechgen(
          "sweep " + model + " --set w=2" + cache + " --out " + (dir / "g.csv").string(), dir, err),
      1);
  EXPECT_NE(err.find(": unreachable in group planar_loop_"), std::string::npos) << err;
  EXPECT_EQ(err.find("nan"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir / "g.csv"));
  EXPECT_NE(test::run_mechgen(
                "sweep " + model + " --set w=2 --solver numeric --out " + (dir / "n.csv").string(),
                dir, err),
            0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mechgen::gen
