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

// The multiple of 2 pi that brings `value` nearest to `target`, and `e` plus k turns.
double turns(double target, double value);
GiNaC::ex plus_turns(const GiNaC::ex& e, double k);

geometry::Vec3<GiNaC::ex> named_vector(const CircuitSolverContext& c, const std::string& name,
                                       const geometry::Vec3<GiNaC::ex>& v);

// Paden-Kahan subproblem 1 on an axis through the origin (w unit): the angle about w that takes
// x to y (their components normal to w).
GiNaC::ex rotation_taking(const geometry::Vec3<GiNaC::ex>& w, const geometry::Vec3<GiNaC::ex>& x,
                          const geometry::Vec3<GiNaC::ex>& y);

// Builds one limb's closed form: named definitions under `prefix`, the discriminants in
// out.reach, and each square root's branch chosen from the assembly.
struct LimbIk {
  const CircuitSolverContext& c;
  std::string prefix;
  CircuitClosedForm out;
  std::vector<int> branches;

  // Chooses between the two branches of a square root by the assembly: the one whose angles
  // `angles(sign)` are nearest (modulo 2 pi) to the assembly's `target`.
  int branch(const std::function<std::vector<GiNaC::ex>(int)>& angles,
             const std::vector<double>& target);
  // `value` named, plus the turns that bring it to the assembly's `target`.
  GiNaC::ex angle(const std::string& name, const GiNaC::ex& value, double target);
  // Subproblem 2: angles (a1, a2) about w1 then w2 (meeting) with R1(a1) R2(a2) u = v.
  std::vector<GiNaC::ex> two_axes(const std::string& name, const geometry::Vec3<GiNaC::ex>& w1,
                                  const geometry::Vec3<GiNaC::ex>& w2,
                                  const geometry::Vec3<GiNaC::ex>& u,
                                  const geometry::Vec3<GiNaC::ex>& v,
                                  const std::vector<double>& target);
  // The branch signs chosen so far, as "+-+".
  std::string branch_signs() const;
};

}  // namespace mechgen::gen
