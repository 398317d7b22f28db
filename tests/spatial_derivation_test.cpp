// The spatial kernel derivation (generator/spatial_derivation.hpp) on a tree with every joint
// type a tree can drive (revolute, prismatic, helical, cylindrical), a joint written against the
// tree's direction, rotated body frames and parameter-dependent geometry: its definitions and
// outputs evaluated numerically (GiNaC, 17 digits) equal the numeric reference solver on random
// configurations and parameter values (every body output, Jacobian, effort and reaction).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>

#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"
#include "spatial_derivation.hpp"
#include "spatial_derivation_values.hpp"
#include "spatial_test_models.hpp"

namespace mechgen::gen {
namespace {

const char* const kTree = R"(name: tree_kinds
dimension: spatial
gravity: [0.5, -1, -9.81]
parameters:
  L: {value: 0.1, unit: m}
  m3: {value: 0.1, unit: kg}
bodies:
  - {name: waist, ground: true}
  - {name: r1, mass: {mass: 0.3, com: [0.01, -0.05, -0.02], inertia: [[1e-3, 1e-4, 0], [1e-4, 2e-3, -2e-4], [0, -2e-4, 1.5e-3]]}}
  - {name: r2, origin: [0, -0.05, -L], rotation: {axis: [0, 0.6, 0.8], angle: 0.7},
     mass: {mass: 0.2, com: [0.02, 0, -0.05], inertia: [[2e-3, 0, 3e-4], [0, 2e-3, 0], [3e-4, 0, 1e-3]]}}
  - {name: r3, points: {tip: [0.03, -0.05, -0.3]},
     mass: {mass: m3, com: [0.01, -0.05, -0.25], inertia: [1e-4, 2e-4, 3e-4]}}
  - {name: l1, mass: {mass: 0.25, com: [0, 0.05, -0.03], inertia: [1e-3, 1e-3, 5e-4]}}
  - {name: l2, mass: {mass: 0.15, com: [0.01, 0.06, -0.12], inertia: [[1e-3, -1e-4, 0], [-1e-4, 1e-3, 0], [0, 0, 4e-4]]}}
  - {name: l3, points: {heel: [0.02, 0.1, -0.3]},
     mass: {mass: 0.1, com: [0.0, 0.08, -0.25], inertia: [[2e-4, 0, 1e-5], [0, 3e-4, 0], [1e-5, 0, 1e-4]]}}
joints:
  - {name: rj1, type: revolute, first: waist, second: r1, s: [0, 0, 1], s0: [0, -0.05, 0]}
  - {name: rj2, type: cylindrical, first: r1, second: r2, s: [1, 0, 0], s0: [0, -0.05, -L]}
  - {name: rj3, type: prismatic, first: r2, second: r3, s: [0, 0.6, -0.8], s0: [0, -0.05, -0.2]}
  - {name: lj1, type: helical, first: waist, second: l1, s: [0, 1, 0], s0: [0, 0.05, 0], pitch: 0.02}
  - {name: lj2, type: revolute, first: l1, second: l2, s: [0.6, 0, 0.8], s0: [0.01, 0.05, -L]}
  - {name: lj3, type: revolute, first: l3, second: l2, s: [0, 0.8, 0.6], s0: [0.01, 0.07, -2*L]}
drivers:
  - {name: d1, joint: rj1, kind: angle, value: t}
  - {name: d2, joint: rj2, kind: length, value: t}
  - {name: d3, joint: rj2, kind: angle, value: t}
  - {name: d4, joint: rj3, kind: length, value: t}
  - {name: d5, joint: lj1, kind: angle, value: t}
  - {name: d6, joint: lj2, kind: angle, value: t}
  - {name: d7, joint: lj3, kind: angle, value: t}
step: {t0: 0, t1: 1}
)";

// The derivation's outputs at one random configuration against the solver's: the worst
// relative difference (floor 1) and the number of outputs compared.
void compare(const SpatialModel& model, const SpatialGraph& graph, const SpatialDerivation& d,
             const std::vector<double>& parameters, std::mt19937& rng, double& worst,
             int& compared) {
  std::uniform_real_distribution<double> u(-1, 1);
  const int n = graph.cols();
  const spatial::SpatialSolver solver(model, parameters);
  spatial::SpatialState s;
  s.q = Eigen::VectorXd(n);
  Eigen::VectorXd qd(n), qdd(n);
  for (int i = 0; i < n; ++i) s.q[i] = 1.2 * u(rng), qd[i] = 2 * u(rng), qdd[i] = 4 * u(rng);
  solver.place(s);
  solver.rates(s, qd, qdd);
  const spatial::SpatialLoads loads = spatial::inverse_dynamics(solver, s);

  Values values = input_values(model, graph, parameters, s.q, qd, qdd);
  for (const auto& [symbol, value] : d.definitions)
    values[symbol.get_name()] = evaluate(value, values);
  Values out;
  for (const auto* list : {&d.kinematics, &d.jacobians, &d.dynamics})
    for (const SpatialOutput& o : *list) out[o.target] = evaluate(o.value, values);

  // A Jacobian the model's `kernel: {jacobians}` leaves out must not be an output at all.
  std::string owner;  // the body or point of the Jacobian entries checked next
  auto check = [&](const std::string& target, double expected) {
    if (target.find("_jacobians.") != std::string::npos && !model.emits_jacobian(owner)) {
      EXPECT_FALSE(out.count(target)) << target;
      return;
    }
    ASSERT_TRUE(out.count(target)) << target;
    worst =
        std::max(worst, std::abs(out.at(target) - expected) / std::max(1.0, std::abs(expected)));
    ++compared;
  };
  const spatial::SpatialInstance& in = solver.instance();
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    if (model.bodies[b].ground) continue;
    const int bi = static_cast<int>(b);
    const std::string o = "s.bodies." + model.bodies[b].name + ".";
    const spatial::Pose frame = solver.body_pose(s, bi);
    const spatial::V3 c = geometry::apply(frame, in.com[b]);
    const spatial::V3 v = solver.point_velocity(s, bi, in.com[b]);
    const spatial::V3 a = solver.point_acceleration(s, bi, in.com[b]);
    for (int i = 0; i < 3; ++i) {
      const auto k = static_cast<size_t>(i);
      check(o + "xyz"[i], c[k]);
      check(o + "v" + "xyz"[i], v[k]);
      check(o + "a" + "xyz"[i], a[k]);
      check(o + "w" + "xyz"[i], s.V[b].w[k]);
      check(o + "al" + "xyz"[i], s.A[b].w[k]);
    }
    for (size_t k = 0; k < 9; ++k) check(o + "R[" + std::to_string(k) + "]", frame.R.m[k]);
    owner = model.bodies[b].name;
    const Eigen::MatrixXd J = solver.body_jacobian(s, bi);
    for (int r = 0; r < 6; ++r)
      for (int col = 0; col < n; ++col)
        check("s.body_jacobians." + model.bodies[b].name + "[" + std::to_string(r) + "][" +
                  std::to_string(col) + "]",
              J(r, col));
  }
  for (const auto& [point, b] : model.named_points()) {
    const spatial::V3 x = solver.point_position(
        s, b, in.points[static_cast<size_t>(b)][0]);  // one point per body here
    const spatial::V3 xv = solver.point_velocity(s, b, in.points[static_cast<size_t>(b)][0]);
    const spatial::V3 xa = solver.point_acceleration(s, b, in.points[static_cast<size_t>(b)][0]);
    for (int r = 0; r < 3; ++r) {
      check("s.points." + point + ".v" + "xyz"[r], xv[static_cast<size_t>(r)]);
      check("s.points." + point + ".a" + "xyz"[r], xa[static_cast<size_t>(r)]);
    }
    owner = point;
    const Eigen::MatrixXd J = solver.point_jacobian(s, b, x);
    for (int r = 0; r < 3; ++r) {
      check("s.points." + point + "." + "xyz"[r], x[static_cast<size_t>(r)]);
      for (int col = 0; col < n; ++col)
        check("s.point_jacobians." + point + "[" + std::to_string(r) + "][" + std::to_string(col) +
                  "]",
              J(r, col));
    }
  }
  for (size_t k = 0; k < graph.primary.size(); ++k) {
    const SpatialColumn& col = graph.columns[static_cast<size_t>(graph.primary[k])];
    check("s.drivers." + model.drivers[static_cast<size_t>(col.driver)].name + ".effort",
          loads.effort[static_cast<Eigen::Index>(k)]);
  }
  for (size_t j = 0; j < model.joints.size(); ++j) {
    const std::string o = "s.joints." + model.joints[j].name + ".";
    for (int i = 0; i < 3; ++i) {
      check(o + "f" + "xyz"[i], loads.reaction[j].f[static_cast<size_t>(i)]);
      check(o + "m" + "xyz"[i], loads.reaction[j].m[static_cast<size_t>(i)]);
    }
  }
}

TEST(SpatialDerivation, TreeOfEveryDrivableJointEqualsTheNumericSolver) {
  const SpatialModel model = read_spatial_model_text(kTree, "tree_kinds.yaml");
  const SpatialGraph graph = build_spatial_graph(model);
  ASSERT_EQ(graph.circuits(), 0);
  ASSERT_EQ(graph.primary.size(), 7u);
  const SpatialDerivation d = derive_spatial(model, graph);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1, 1);
  double worst = 0;
  int compared = 0;
  for (int trial = 0; trial < 6; ++trial)
    compare(model, graph, d, {0.1 + 0.05 * u(rng), 0.1 + 0.05 * u(rng)}, rng, worst, compared);
  EXPECT_GT(compared, 6 * 400);
  EXPECT_LT(worst, 1e-12);
  std::cout << "tree of every drivable joint type: " << compared << " outputs, worst " << worst
            << "\n";
}

// `kernel: {jacobians: [r2, heel]}`: r2's twist Jacobian and heel's velocity Jacobian are
// outputs and equal the solver's; the other bodies' and tip's are not outputs (compare() checks
// both); everything else is as without the key.
TEST(SpatialDerivation, OnlyTheJacobiansTheModelAsksForAreEmitted) {
  const SpatialModel model = read_spatial_model_text(
      std::string(kTree) + "kernel: {jacobians: [r2, heel]}\n", "tree_kinds.yaml");
  const SpatialGraph graph = build_spatial_graph(model);
  const SpatialDerivation d = derive_spatial(model, graph);
  std::set<std::string> owners;
  for (const SpatialOutput& o : d.jacobians) owners.insert(o.target.substr(0, o.target.find('[')));
  EXPECT_EQ(owners, (std::set<std::string>{"s.body_jacobians.r2", "s.point_jacobians.heel"}));
  std::mt19937 rng(29);
  double worst = 0;
  int compared = 0;
  for (int trial = 0; trial < 3; ++trial)
    compare(model, graph, d, {0.1, 0.12}, rng, worst, compared);
  EXPECT_LT(worst, 1e-12);
  // Per trial: r2's 6 x 7 and heel's 3 x 7 entries besides the other outputs.
  const SpatialDerivation all =
      derive_spatial(read_spatial_model_text(kTree, "tree_kinds.yaml"), graph);
  EXPECT_EQ(d.jacobians.size(), 6u * 7 + 3u * 7);
  EXPECT_EQ(all.jacobians.size(), (6u * 6 + 3u * 2) * 7);
}

TEST(SpatialDerivation, KernelJacobiansNamesAreChecked) {
  for (const auto& [entry, message] : std::vector<std::pair<std::string, std::string>>{
           {"[r2, knee]", "'knee' is neither a moving body nor a named point"},
           {"[waist]", "'waist' is neither a moving body nor a named point"},
           {"[heel, heel]", "'heel' is listed twice"},
           {"r2", "must be a list"}}) {
    try {
      read_spatial_model_text(std::string(kTree) + "kernel:\n  jacobians: " + entry + "\n",
                              "tree_kinds.yaml");
      ADD_FAILURE() << entry << " was accepted";
    } catch (const ModelError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("tree_kinds.yaml:"), std::string::npos) << what;
      EXPECT_NE(what.find(message), std::string::npos) << what;
      // The line of the kernel entry: the last line of the text.
      EXPECT_NE(
          what.find(":" + std::to_string(std::count(kTree, kTree + std::strlen(kTree), '\n') + 2) +
                    ":"),
          std::string::npos)
          << what;
    }
  }
}

// A closed chain's reactions (N_s transposed, minimum norm over the redundant rows' null space)
// evaluated numerically against the numeric solver's A x = b along the step: chebyshev_spatial
// with gravity tilted out of its plane, so that its three redundant components (fz, mx, my of
// every joint) carry load and the minimum-norm choice matters, and rsur (no redundancy).
void closed_reactions_equal_numeric(const std::string& text, const std::string& label,
                                    int expected_redundancy) {
  const SpatialModel model = read_spatial_model_text(text, label);
  const SpatialGraph graph = build_spatial_graph(model);
  const SpatialDerivation d = derive_spatial(model, graph);
  const std::vector<double> parameters = model.common.default_parameters();
  const spatial::SpatialSolver solver(model, parameters);
  const spatial::SpatialSweepOptions options = spatial::default_spatial_sweep(model, parameters);
  spatial::SpatialState st;
  double worst = 0, largest = 0;
  for (int i = 0; i < 12; ++i) {
    solver.solve(options.t0 + (options.t1 - options.t0) * i / 12, st);
    const spatial::SpatialLoads loads = spatial::inverse_dynamics(solver, st);
    EXPECT_EQ(loads.redundancy, expected_redundancy);
    const Values values = derivation_values(model, graph, d, parameters, st);
    std::map<std::string, double> out;
    for (const SpatialOutput& o : d.dynamics) out[o.target] = evaluate(o.value, values);
    for (size_t j = 0; j < model.joints.size(); ++j) {
      const std::string o = "s.joints." + model.joints[j].name + ".";
      for (int k = 0; k < 3; ++k) {
        const auto kk = static_cast<size_t>(k);
        for (const auto& [target, expected] :
             {std::pair{o + "f" + "xyz"[k], loads.reaction[j].f[kk]},
              std::pair{o + "m" + "xyz"[k], loads.reaction[j].m[kk]}}) {
          ASSERT_TRUE(out.count(target)) << target;
          worst = std::max(worst, std::abs(out.at(target) - expected));
          largest = std::max(largest, std::abs(expected));
        }
      }
    }
  }
  EXPECT_LT(worst, 1e-9 * largest);
  std::cout << label << ": reactions (minimum norm, redundancy " << expected_redundancy
            << ") against the numeric solver, 12 poses: worst " << worst << " of " << largest
            << "\n";
}

TEST(SpatialDerivation, ClosedChainReactionsAreTheNumericSolversMinimumNormOnes) {
  std::string chebyshev = model_text("chebyshev_spatial");
  const std::string planar_gravity = "gravity: [0, -9.81, 0]";
  ASSERT_NE(chebyshev.find(planar_gravity), std::string::npos);
  chebyshev.replace(chebyshev.find(planar_gravity), planar_gravity.size(),
                    "gravity: [1.5, -9.81, -4]");
  closed_reactions_equal_numeric(chebyshev, "chebyshev_spatial_tilted.yaml", 3);
  closed_reactions_equal_numeric(model_text("rsur"), "rsur.yaml", 0);
}

// Random geometry: serial chains of five joints of random kinds about random unit axes through
// random points, random masses, centres of mass and positive-definite inertia tensors.
std::string random_chain(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  auto num = [](double x) {
    std::ostringstream o;
    o.precision(17);
    o << x;
    return o.str();
  };
  auto vec = [&](double scale) {
    return "[" + num(scale * u(rng)) + ", " + num(scale * u(rng)) + ", " + num(scale * u(rng)) +
           "]";
  };
  auto axis = [&]() {
    double a[3], n = 0;
    for (double& x : a) x = u(rng), n += x * x;
    n = std::sqrt(n);
    return "[" + num(a[0] / n) + ", " + num(a[1] / n) + ", " + num(a[2] / n) + "]";
  };
  std::string text = "name: random_chain\ndimension: spatial\ngravity: " + vec(5) +
                     "\nbodies:\n  - {name: b0, ground: true}\n";
  std::string joints = "joints:\n", drivers = "drivers:\n";
  const char* const kinds[] = {"revolute", "prismatic", "helical"};
  for (int i = 1; i <= 5; ++i) {
    const double d0 = 1e-3 * (1 + std::abs(u(rng))), d1 = 1e-3 * (1 + std::abs(u(rng)));
    const double d2 = 1e-3 * (1 + std::abs(u(rng))), o = 2e-4;
    const double p = o * u(rng), q = o * u(rng), r = o * u(rng);
    text += "  - {name: b" + std::to_string(i) + ", points: {x" + std::to_string(i) + ": " +
            vec(0.3) + "}, mass: {mass: " + num(0.1 + 0.5 * std::abs(u(rng))) +
            ", com: " + vec(0.2) + ", inertia: [[" + num(d0) + ", " + num(p) + ", " + num(q) +
            "], [" + num(p) + ", " + num(d1) + ", " + num(r) + "], [" + num(q) + ", " + num(r) +
            ", " + num(d2) + "]]}}\n";
    const std::string kind = kinds[std::uniform_int_distribution<int>(0, 2)(rng)];
    joints += "  - {name: j" + std::to_string(i) + ", type: " + kind + ", first: b" +
              std::to_string(i - 1) + ", second: b" + std::to_string(i) + ", s: " + axis() +
              ", s0: " + vec(0.2) + (kind == "helical" ? ", pitch: 0.03" : "") + "}\n";
    drivers += "  - {name: d" + std::to_string(i) + ", joint: j" + std::to_string(i) +
               ", kind: " + (kind == "prismatic" ? "length" : "angle") + ", value: t}\n";
  }
  return text + joints + drivers + "step: {t0: 0, t1: 1}\n";
}

TEST(SpatialDerivation, RandomChainsEqualTheNumericSolver) {
  std::mt19937 rng(23);
  double worst = 0;
  int compared = 0;
  for (int model_index = 0; model_index < 8; ++model_index) {
    const SpatialModel model = read_spatial_model_text(random_chain(rng), "random_chain.yaml");
    const SpatialGraph graph = build_spatial_graph(model);
    const SpatialDerivation d = derive_spatial(model, graph);
    for (int trial = 0; trial < 3; ++trial) compare(model, graph, d, {}, rng, worst, compared);
  }
  EXPECT_GT(compared, 8 * 3 * 300);
  EXPECT_LT(worst, 1e-12);
  std::cout << "8 random chains: " << compared << " outputs, worst " << worst << "\n";
}

// Copies of the RSUR loop side by side, sharing only the ground: N_s is block diagonal, one block
// per copy, and the kernel checks each block's determinant against its own value at the assembly
// (issue 28: 16 copies in phase multiplied into one determinant that fell below its floor at a
// regular pose). Expected: as many blocks as copies, six pivots each, each block's determinant the
// single loop's.
TEST(SpatialDerivation, IndependentCircuitsAreCheckedBlockByBlock) {
  constexpr int kCopies = 4;
  const std::string rsur = model_text("rsur");
  const std::string copies = spatial::rsur_copies(kCopies, false);
  const SpatialModel one_model = read_spatial_model_text(rsur, "rsur.yaml");
  const SpatialDerivation one = derive_spatial(one_model, build_spatial_graph(one_model));
  const SpatialModel model = read_spatial_model_text(copies, "rsur_copies.yaml");
  const SpatialDerivation d = derive_spatial(model, build_spatial_graph(model));
  double one_det = 1;
  for (const double pivot : one.closure_pivots) one_det *= pivot;
  ASSERT_EQ(d.closure_pivots.size(), kCopies * one.closure_pivots.size());
  ASSERT_EQ(d.closure_blocks.size(), d.closure_pivots.size());
  std::map<size_t, std::pair<int, double>> blocks;  // pivots and determinant per block
  for (size_t k = 0; k < d.closure_pivots.size(); ++k) {
    auto& [count, det] = blocks.try_emplace(d.closure_blocks[k], 0, 1.0).first->second;
    ++count;
    det *= d.closure_pivots[k];
  }
  ASSERT_EQ(blocks.size(), static_cast<size_t>(kCopies));
  for (const auto& [block, pivots] : blocks) {
    EXPECT_EQ(pivots.first, 6) << "block " << block;
    EXPECT_NEAR(std::abs(pivots.second), std::abs(one_det), 1e-12 * std::abs(one_det))
        << "block " << block;
  }
}

}  // namespace
}  // namespace mechgen::gen
