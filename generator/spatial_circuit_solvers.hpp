// Closed-form solvers of a closed chain's circuits, tried before the unrolled Newton fallback
// (generator/spatial_derivation.cpp, close_positions). Each solver looks at one circuit; when it
// recognises the geometry (never the names) it returns the values of some secondary
// coordinates as expressions of the primary inputs, the parameters and the coordinates already
// known, and the circuit counts as closed. The unclosed circuits are offered again after each
// success (a circuit may need coordinates another circuit's closed form gives: dependency
// order) until no solver makes progress; Newton then runs only on the circuits and coordinates
// that are left.
#pragma once

#include <ginac/ginac.h>

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "geometry/screw.hpp"
#include "model/spatial_graph.hpp"
#include "model/spatial_model.hpp"

namespace mechgen::gen {

struct CircuitColumn {
  geometry::ScrewAxis<GiNaC::ex> axis;     // at the reference pose (named parameter expressions)
  GiNaC::ex q;                             // the coordinate (a primary one: from the inputs)
  geometry::Pose<GiNaC::ex> displacement;  // exp(screw q), sine and cosine named
};

// What a solver sees of the derivation: the columns (graph order), a way to name definitions,
// and the numeric assembly (default parameters, t0) to choose branches from.
struct CircuitSolverContext {
  const SpatialModel& model;
  const SpatialGraph& graph;
  std::vector<CircuitColumn> columns;
  std::vector<double> assembly_q;  // per column
  std::function<GiNaC::ex(const std::string&, const GiNaC::ex&)> named;
  std::function<double(const GiNaC::ex&)> at_assembly;  // an expression's value there
  std::vector<bool> known;  // per column: primary, or given by a closed form found before
  std::vector<geometry::Pose<GiNaC::ex>> tree_pose;  // per body: its displacement along the tree
  // A closed form's warm start for a column it defines: the previous call's value of the
  // coordinate, kept in the kernel's State (the assembly's at first), so that an angle unwound
  // to it stays continuous along a sweep. Only for a closed form that is returned.
  std::function<GiNaC::ex(int column)> warm_start;
};

struct CircuitClosedForm {
  std::string name;  // the kernel's group (failed_group when unreachable)
  std::string plan;  // one line for the banner and `check`
  std::vector<std::pair<int, GiNaC::ex>> coordinates;  // graph column, its value
  std::vector<GiNaC::ex> reach;  // defined names that must be >= 0, else unreachable
  // Per graph column: its cosine and sine where the closed form has them without trigonometry
  // (the tree's positions then use them instead of cos q, sin q).
  std::map<int, std::pair<GiNaC::ex, GiNaC::ex>> cos_sin;
  // Whether the circuit is closed by these coordinates. A partial closed form (false) defines some
  // of the circuit's coordinates only (a planar loop with two unknown revolutes on one pivot gives
  // their sum, not each): the circuit is offered again once other circuits gave more coordinates.
  bool closes = true;
};

using CircuitSolver =
    std::function<std::optional<CircuitClosedForm>(const CircuitSolverContext&, int circuit)>;

// Every closed-form solver, in the order they are tried on each circuit.
const std::vector<CircuitSolver>& circuit_solvers();

// The solvers tried, after those above, only once those above make no more progress (issue 21
// item 4: the imported robots' planar loops): a circuit the others close, at any pass, keeps the
// kernel it had before them (the shipped models' kernels unchanged).
const std::vector<CircuitSolver>& fallback_circuit_solvers();

}  // namespace mechgen::gen
