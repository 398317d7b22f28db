// Applied loads (`forces:`) and the Newton-Euler system in the spatial derivation
// (generator/spatial_derivation.hpp): a tree (leg6) and closed chains (rsur; chebyshev_spatial
// with gravity tilted out of its plane, so its redundant reaction components carry load) with
// forces at points and couples, constant and functions of t. The derivation evaluated
// numerically (GiNaC, 17 digits) at poses along the step against the numeric solver: every
// driver effort and joint reaction (inverse_dynamics, minimum norm where redundant) and every
// entry of A and b (newton_euler_system).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"
#include "spatial_derivation.hpp"
#include "spatial_derivation_values.hpp"
#include "spatial_primary_inputs.hpp"

namespace mechgen::gen {
namespace {

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

struct Worst {
  double efforts = 0, effort_scale = 0, reactions = 0, reaction_scale = 0, A = 0, A_scale = 0,
         b = 0, b_scale = 0;
};

// The derivation against the numeric solver at `poses` instants of the model's step.
Worst loaded_derivation_equals_numeric(const std::string& text, const std::string& label,
                                       int poses = 8) {
  const SpatialModel model = read_spatial_model_text(text, label);
  const SpatialGraph graph = build_spatial_graph(model);
  const SpatialDerivation d = derive_spatial(model, graph);
  const std::vector<double> parameters = model.common.default_parameters();
  const spatial::SpatialSolver solver(model, parameters);
  const spatial::SpatialSweepOptions options = spatial::default_spatial_sweep(model, parameters);
  const std::vector<SpatialPrimaryInput> inputs = spatial_primary_inputs(model, graph);
  Worst w;
  spatial::SpatialState st;
  for (int i = 0; i < poses; ++i) {
    solver.solve(options.t0 + (options.t1 - options.t0) * (i + 0.5) / poses, st);
    const spatial::SpatialLoads loads = spatial::inverse_dynamics(solver, st);
    const spatial::NewtonEulerSystem system = spatial::newton_euler_system(solver, st);
    const Values values = derivation_values(model, graph, d, parameters, st);
    std::map<std::string, double> out;
    for (const SpatialOutput& o : d.dynamics) out[o.target] = evaluate(o.value, values);
    // Efforts: input k is primary column graph_column.
    for (const SpatialPrimaryInput& in : inputs) {
      const auto k = std::find(graph.primary.begin(), graph.primary.end(), in.graph_column) -
                     graph.primary.begin();
      const double expected = loads.effort[k];
      w.efforts =
          std::max(w.efforts, std::abs(out.at("s.drivers." + in.name + ".effort") - expected));
      w.effort_scale = std::max(w.effort_scale, std::abs(expected));
    }
    for (size_t j = 0; j < model.joints.size(); ++j) {
      if (model.joints[j].is_virtual) continue;
      const std::string o = "s.joints." + model.joints[j].name + ".";
      for (size_t k = 0; k < 3; ++k)
        for (const auto& [target, expected] :
             {std::pair{o + "f" + "xyz"[k], loads.reaction[j].f[k]},
              std::pair{o + "m" + "xyz"[k], loads.reaction[j].m[k]}}) {
          w.reactions = std::max(w.reactions, std::abs(out.at(target) - expected));
          w.reaction_scale = std::max(w.reaction_scale, std::abs(expected));
        }
    }
    // A and b entry by entry (the derivation lists A's nonzero entries).
    EXPECT_EQ(d.ne_rows, system.A.rows());
    EXPECT_EQ(static_cast<Eigen::Index>(d.ne_unknowns.size()), system.A.cols());
    const auto n = static_cast<Eigen::Index>(d.ne_unknowns.size());
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(d.ne_rows, n);
    for (const auto& [index, value] : d.ne_matrix)
      A(index / n, index % n) = evaluate(value, values);
    Eigen::VectorXd b(d.ne_rows);
    for (Eigen::Index r = 0; r < d.ne_rows; ++r)
      b[r] = evaluate(d.ne_rhs[static_cast<size_t>(r)], values);
    w.A = std::max(w.A, (A - system.A).cwiseAbs().maxCoeff());
    w.A_scale = std::max(w.A_scale, system.A.cwiseAbs().maxCoeff());
    w.b = std::max(w.b, (b - system.b).cwiseAbs().maxCoeff());
    w.b_scale = std::max(w.b_scale, system.b.cwiseAbs().maxCoeff());
  }
  EXPECT_GT(w.effort_scale, 0);
  EXPECT_LT(w.efforts, 1e-9 * w.effort_scale) << label;
  EXPECT_LT(w.reactions, 1e-9 * w.reaction_scale) << label;
  EXPECT_LT(w.A, 1e-12 * w.A_scale) << label;
  EXPECT_LT(w.b, 1e-12 * w.b_scale) << label;
  std::cout << label << ", " << poses << " poses: efforts " << w.efforts << " of " << w.effort_scale
            << ", reactions " << w.reactions << " of " << w.reaction_scale << ", A " << w.A
            << " of " << w.A_scale << ", b " << w.b << " of " << w.b_scale << "\n";
  return w;
}

// A force at the toe that varies with t, a constant couple on the calf.
const char* const kLeg6Loads =
    "forces:\n"
    "  - {name: push, type: force, body: foot_link, point: toe, value: [3*cos(w*t), -2, 40 + "
    "10*sin(w*t)]}\n"
    "  - {name: twist, type: torque, body: calf, value: [0.2, -0.1, 0.3]}\n";

TEST(SpatialAppliedLoads, TreeWithLoadsEqualsTheNumericSolver) {
  loaded_derivation_equals_numeric(model_text("leg6") + kLeg6Loads, "leg6_loaded.yaml");
}

TEST(SpatialAppliedLoads, ClosedChainsWithLoadsEqualTheNumericSolver) {
  loaded_derivation_equals_numeric(
      model_text("rsur") +
          "forces:\n"
          "  - {name: pull, type: force, body: coupler, point: B, value: [2, -1, 5*sin(w*t)]}\n"
          "  - {name: brake, type: torque, body: rocker, value: [-0.4*cos(w*t), 0, 0.1]}\n",
      "rsur_loaded.yaml");
  // Tilted gravity and an out-of-plane force: the redundant components carry load, so the
  // minimum-norm reactions are a real choice.
  loaded_derivation_equals_numeric(
      replaced(model_text("chebyshev_spatial"), "gravity: [0, -9.81, 0]",
               "gravity: [1.5, -9.81, -4]") +
          "forces:\n"
          "  - {name: tool, type: force, body: coupler, point: C, value: [1 + t, -3, 2]}\n"
          "  - {name: drag, type: torque, body: rocker, value: [0.1, 0.2, -0.5*sin(w*t)]}\n",
      "chebyshev_spatial_loaded.yaml");
}

// The same models without loads: the loads above must change the efforts (else the test could
// not fail on a kernel that leaves them out).
TEST(SpatialAppliedLoads, TheLoadsMatter) {
  const Worst loaded =
      loaded_derivation_equals_numeric(model_text("leg6") + kLeg6Loads, "leg6_loaded.yaml", 1);
  const Worst bare = loaded_derivation_equals_numeric(model_text("leg6"), "leg6.yaml", 1);
  EXPECT_GT(loaded.effort_scale, 2 * bare.effort_scale);
}

}  // namespace
}  // namespace mechgen::gen
