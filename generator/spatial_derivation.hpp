// Symbolic derivation of a spatial model's kernel (issue 11), through the same geometry layer the
// numeric solver uses (runtime/geometry/screw.hpp with GiNaC::ex as the scalar):
//  - positions by successive screw displacements along the spanning tree, each joint
//    coordinate's cosine and sine named once, every body's displacement a named 3 x 3 rotation
//    matrix and translation;
//  - each joint's current screws, body twists and twist rates by the recursive propagation
//    (V_b = V_parent + sum q' $, A_b = A_parent + sum q'' $ + q' [carrier, $]): exact, no
//    differentiation of large expressions;
//  - screw Jacobians (each body's twist and each named point's velocity against the primary
//    rates) read off the same screws;
//  - inverse dynamics by a recursive backward pass: each body's rate of momentum plus what its
//    children draw, transmitted through its tree joint; a driven coordinate's effort is the
//    reciprocal product of its screw with that wrench, the rest is the joint's reaction.
//  - closed chains: secondary coordinates in closed form or by Newton steps on the closure (one
//    step derived, repeated by the kernel in a loop shared by its entry points), Davies' rates
//    through a fixed-order elimination of N_s, efforts by virtual power, and the reactions from
//    the chords' wrenches through N_s transposed (the same elimination), projected off the
//    redundant rows' null space to the numeric solver's minimum-norm ones.
// Every intermediate is a named definition (an expanded expression of earlier names).
#pragma once

#include <ginac/ginac.h>

#include <string>
#include <utility>
#include <vector>

#include "model/spatial_graph.hpp"
#include "model/spatial_model.hpp"

namespace mechgen::gen {

struct SpatialOutput {
  std::string target;  // C++ lvalue in the kernel, e.g. "s.bodies.thigh.x"
  GiNaC::ex value;
};

struct SpatialDerivation {
  std::vector<std::pair<GiNaC::symbol, GiNaC::ex>> definitions;  // program order
  std::vector<SpatialOutput> kinematics;  // bodies, points, joint and driver coordinates
  std::vector<SpatialOutput> jacobians;   // body twist and point velocity Jacobians
  std::vector<SpatialOutput> dynamics;    // joint reactions and driver efforts
  std::vector<std::string> groups;        // one per located body: "thigh"
  std::vector<std::string> plan;          // one line per group, for the banner
  int primary_count = 0;
  // Closed chains: the secondary coordinates left to the Newton fallback at the assembly
  // (default parameters, t0), the State's default warm start. Empty for a tree and for a closed
  // chain solved in closed form throughout.
  std::vector<double> closure_start;
  // The Newton fallback's one step: definitions reading the iterate s.closure.next[] and the
  // iterate's new values; the kernel runs it newton_steps times from the warm start
  // s.closure.q[] (one function shared by every entry point), and the main definitions read the
  // result as s.closure.next[].
  std::vector<std::pair<GiNaC::symbol, GiNaC::ex>> newton_step;
  std::vector<GiNaC::ex> newton_update;
  int newton_steps = 0;
  std::vector<double> closure_pivots;  // the pivots of the eliminated N_s there
  std::vector<size_t> closure_blocks;  // each pivot's independent block (circuits sharing none)
  // The pivots are those of N_s^T N_s (no fixed set of rows holds: every row kept, least squares).
  bool closure_least_squares = false;
  bool closed_chain = false;
  // Closed-form groups' reachability: each value must be >= 0, else the kernel returns
  // unreachable naming groups[group] (a law of cosines' 1 - cos^2, before its square root).
  struct Guard {
    GiNaC::ex value;  // a defined name
    int group = -1;
  };
  std::vector<Guard> guards;
  // Closed-form angles' warm starts (`s.closure.w[k]`, unwinding, and the branch nearer them):
  // their values at the assembly.
  std::vector<double> angle_start;
  // The graph columns (SpatialGraph::columns) of closure_start's and angle_start's entries, so
  // that a run can start both from the numeric solver's assembly at its own parameters.
  std::vector<int> closure_columns, angle_columns;
  std::vector<int> closed_form_groups;  // indices into groups (and plan) of the closed forms
  // The Newton-Euler system A x = b of the numeric solver (runtime/spatial/spatial_dynamics.cpp):
  // rows 6 per moving body (force, moment about the ground origin), then one per coordinate (the
  // reaction does no work on the joint's screw); unknowns 6 per joint (force, moment at the joint
  // point), then one effort per driven coordinate. Nonzero entries only.
  int ne_rows = 0;
  std::vector<std::string> ne_unknowns;
  std::vector<std::pair<int, GiNaC::ex>> ne_matrix;  // (row * ne_unknowns.size() + column, value)
  std::vector<GiNaC::ex> ne_rhs;
};

// Parameters print as `p.<name>`, driver inputs as `in.<driver>`, `in.<driver>_d`, `_dd` (a pose
// coordinate: `in.<pose>_<coordinate>`).
GiNaC::exmap spatial_parameter_symbols(const SpatialModel& model);

// Throws std::runtime_error (naming what is missing) for a tree with an undriven coordinate or a
// closed chain with no pivot order that stays regular over its step. Pose drivers' prescribed
// coordinates are inputs like joint drivers (spatial_primary_inputs.hpp).
SpatialDerivation derive_spatial(const SpatialModel& model, const SpatialGraph& graph);

}  // namespace mechgen::gen
