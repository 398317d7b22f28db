// The closed-form pre-pass of a closed chain's positions (issue 11 item 1): solvers that recognise
// position groups in the graph (never by model name) and define some secondary coordinates in
// closed form; generator/spatial_derivation.cpp's Newton-Raphson closure runs only when some
// secondary coordinate is left. Each solver scans the graph with what is known so far and appends
// the groups it finds; the solvers run in turns until none finds more (dependency order).
#pragma once

#include <ginac/ginac.h>

#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "geometry/screw.hpp"
#include "model/spatial_graph.hpp"
#include "model/spatial_model.hpp"

namespace mechgen::gen {

// What a solver works from: the derivation's own symbols, and their values at the assembly
// (default parameters, t0: the numeric solver's pose) to choose branches and to check itself.
struct ClosureContext {
  const SpatialModel& model;
  const SpatialGraph& graph;
  std::vector<geometry::ScrewAxis<GiNaC::ex>> axes;  // per column, parameters as `p.<name>`
  std::vector<GiNaC::ex> q;                          // per column: its coordinate's symbol
  std::vector<GiNaC::ex> warm;                       // per column: the warm start (secondary)
  std::vector<geometry::Pose<GiNaC::ex>> tree_pose;  // per body: displacement along the tree
  std::vector<bool> known;                           // per column: primary or solved
  GiNaC::exmap assembly;           // every symbol in play -> its value at the assembly
  std::vector<double> assembly_q;  // per column: the coordinate at the assembly

  // The value of e at the assembly.
  double value(const GiNaC::ex& e) const;
  // Body b's tree pose is usable: every coordinate on its tree path is known.
  bool pose_known(int body) const;
};

// One closed-form group: the secondary coordinates it defines and how.
struct ClosedFormGroup {
  std::string name;          // for Status::unreachable's failed_group
  std::string plan;          // one line for `check` and the kernel banner
  std::vector<int> columns;  // secondary columns it defines
  // Program order; the columns' own symbols (ClosureContext::q) are defined among them.
  std::vector<std::pair<GiNaC::symbol, GiNaC::ex>> definitions;
  std::vector<GiNaC::ex> reach;  // each >= 0 where the group closes (its discriminants)
  // Per column: its cosine and sine where the group has them without trigonometry; the tree's
  // positions use them (a positions-only entry then needs no angle at all).
  std::map<int, std::pair<GiNaC::ex, GiNaC::ex>> cos_sin;
};

// A solver appends the groups it can close given ctx.known, marks their columns known and adds
// their definitions' values to ctx.assembly; returns whether it found any.
using ClosedFormSolver = std::function<bool(ClosureContext&, std::vector<ClosedFormGroup>&)>;

// Every closed-form group of the chain, the solvers taking turns until none finds more.
std::vector<ClosedFormGroup> closed_form_groups(ClosureContext& ctx);

}  // namespace mechgen::gen
