// The order in which a mechanism's bodies can be located: a sequence of small groups (a driven
// joint, a dyad, a body on a circle and a line, a cylinder driven or passive; as a last resort a
// group with no closed form, solved iteratively), found from the joint graph alone. The symbolic
// generator follows it; `mechgen check` prints it (docs/solve_groups.md).
#pragma once

#include <string>
#include <vector>

#include "model/model.hpp"

namespace mechgen {

enum class GroupKind {
  driven_revolute,   // one body: revolute joint to a located body, its angle driven
  driven_prismatic,  // one body: prismatic joint on a located body's line, its length driven
  rrr,               // two bodies: revolute - revolute - revolute (circle-circle)
  rrp,               // two bodies: revolute - revolute - prismatic on a located line (circle-line)
  r_slot,        // one body: revolute to a located point, its pin in a located slot (circle-line)
  slot_on_body,  // one body: revolute to a located point, its own slot around a located pin
  prp,           // two bodies pinned together, each on a located prismatic line (line-line)
  rpr,           // three bodies: a link pinned to a located body, and a driven-length cylinder (two
                 // bodies, prismatic between them) from another located pin to the link (triangle)
  passive_rpr,   // two bodies: a link pinned to a located point and a block pinned to another,
                 // sliding along each other (undriven prismatic: an inverted slider-crank, a
                 // passive strut); circle-line in the link's frame
  iterative,     // bodies with no closed form (e.g. an Assur triad): fixed-iteration Newton
};

const char* to_string(GroupKind kind);
bool has_branch(GroupKind kind);
bool is_iterative(GroupKind kind);

struct SolveGroup {
  GroupKind kind;
  std::vector<int> bodies;  // located by this group, in the order the kind describes
  std::vector<int> joints;  // constraints this group satisfies, in the order the kind describes
                            // (iterative: first one tree joint per body, in body order, then the
                            // closing joints)
  int driver = -1;          // driver used, for driven kinds
  std::string name;         // "g<index>_<bodies>", an identifier for generated code
};

struct SolvePlan {
  int reference = -1;  // the body whose frame the shape is solved in
  std::vector<SolveGroup> groups;
  std::vector<int> unsolved;  // bodies no closed-form group reaches (empty when complete)
  bool complete() const { return unsolved.empty(); }
};

// Tries the ground first, then the bodies that carry a driver's first side, then the others; the
// first reference from which every body is reached in closed form wins. When none does, plans
// from the ground with iterative groups (Newton-Raphson) for what no closed form reaches; when
// even that leaves bodies, returns the closed-form plan from the ground with `unsolved` listing
// what remains.
SolvePlan make_solve_plan(const Model& model);

std::string describe(const Model& model, const SolveGroup& group);

}  // namespace mechgen
