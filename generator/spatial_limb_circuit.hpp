// What the pose-driven limb solvers share (spatial_limb_ik.hpp, spatial_position_ik.hpp): a
// circuit read as a serial limb of real revolutes closed by a rest of known motion, and the
// Paden-Kahan pieces they build their closed forms from, each branch chosen from the numeric
// assembly.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "spatial_circuit_loop.hpp"
#include "spatial_circuit_solvers.hpp"

namespace mechgen::gen {

using LimbStep = CircuitStep;

// A circuit split into the limb (its real joints with secondary coordinates, contiguous, fixed
// joints between them allowed) and the rest of the loop, from the limb's end back to its start.
struct LimbCircuit {
  std::vector<LimbStep> limb, rest;
  std::vector<int> free;  // the rest's secondary (free virtual) columns
  int pose_driver = -1;   // theirs, or of any virtual joint of the rest
};

std::optional<LimbCircuit> limb_circuit(const CircuitSolverContext& c, int circuit);

// The rest's motion from the limb's end back to its start with the free columns at zero; the
// limb's own motion from its start to its end is its inverse. Named under `prefix`.
geometry::Pose<GiNaC::ex> rest_motion(const CircuitSolverContext& c, const LimbCircuit& lc,
                                      const std::string& prefix);

// The kernel group of a limb: ik_<pose driver>.
std::string limb_group_name(const CircuitSolverContext& c, const LimbCircuit& lc, int circuit);

geometry::Vec3<GiNaC::ex> named_vector(const CircuitSolverContext& c, const std::string& name,
                                       const geometry::Vec3<GiNaC::ex>& v);

// Paden-Kahan subproblem 1 on an axis through the origin (w unit): the angle about w that takes
// x to y (their components normal to w).
GiNaC::ex rotation_taking(const geometry::Vec3<GiNaC::ex>& w, const geometry::Vec3<GiNaC::ex>& x,
                          const geometry::Vec3<GiNaC::ex>& y);

// Builds one limb's closed form: named definitions under `prefix`, the discriminants in
// out.reach, and each square root's root chosen at run time, the one nearer the warm start.
struct LimbIk {
  const CircuitSolverContext& c;
  std::string prefix;
  CircuitClosedForm out;
  std::vector<int> branches;  // each choice at the assembly, for the plan

  // A limb angle theta = direction q of a column: its warm start (the previous call's, carried to
  // this call's time) and its value at the assembly.
  struct Target {
    GiNaC::ex warm;
    double assembly = 0;
  };
  Target target(size_t column, const GiNaC::ex& direction) const;
  // Chooses between the two roots of a square root at run time: the sign (+1 or -1, a named
  // branch_sign) of `indicator`, an expression of the warm starts that is positive where the warm
  // configuration is on the + root's side (an elbow's side, a link's spin): the root of the warm
  // start's family, which is also the nearer one.
  GiNaC::ex branch(const GiNaC::ex& indicator);
  // `value` named, unwound to the target's warm start (continuous along a sweep).
  GiNaC::ex angle(const std::string& name, const GiNaC::ex& value, const Target& target) const;
  // Subproblem 2: angles (a1, a2) about w1 then w2 (meeting) with R1(a1) R2(a2) u = v.
  std::vector<GiNaC::ex> two_axes(const std::string& name, const geometry::Vec3<GiNaC::ex>& w1,
                                  const geometry::Vec3<GiNaC::ex>& w2,
                                  const geometry::Vec3<GiNaC::ex>& u,
                                  const geometry::Vec3<GiNaC::ex>& v,
                                  const std::vector<Target>& targets);
  // The branch signs chosen at the assembly, as "+-+".
  std::string branch_signs() const;
};

}  // namespace mechgen::gen
