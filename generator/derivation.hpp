// Symbolic derivation of one model along its solve plan: closed-form positions group by group in
// the reference body's frame, placement on the ground body, exact velocities and accelerations
// (staged time derivatives), and the Newton-Euler system A x = b with its structure-aware solution.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "model/model.hpp"
#include "model/solve_plan.hpp"
#include "staged_program.hpp"

namespace mechgen::gen {

struct BodyPose {  // a configuration to pick branches from: body frames in the ground frame
  double x, y, th;
};

struct Output {
  std::string target;  // C++ lvalue in the kernel, e.g. "s.l7.x"
  GiNaC::ex value;
};

// A closed-form group's two roots at the assembly (t0, default parameters): the ground-frame
// angles of its bodies on the branch taken (the numeric solver's assembly) and on the other.
struct BranchChoice {
  std::string group;
  int sign = 1;
  std::vector<int> bodies;
  std::vector<double> taken, other;
};

struct Derivation {
  // Symbols the kernel receives. Parameters keep the model's symbols.
  struct DriverInputs {
    GiNaC::symbol q, qd, qdd;
  };
  std::vector<DriverInputs> driver_inputs;

  std::vector<Output> kinematics;    // body, point and driver outputs
  std::vector<Output> dynamics;      // joint reactions and driver efforts
  size_t kinematics_statements = 0;  // statements needed by the kinematics outputs alone
  // The Newton-Euler system, dense row-major (equations: per moving body Fx, Fy, M about the
  // centre of mass; unknowns: per joint its reaction components, then per driver its effort).
  std::vector<std::string> ne_unknowns;
  std::vector<GiNaC::ex> ne_matrix;  // size n*n
  std::vector<GiNaC::ex> ne_rhs;
  std::vector<std::string> group_names;  // index = group number used in statements
  std::vector<std::string> notes;        // branch choices, for `check` and the banner
  std::vector<BranchChoice> branches;    // the same, with both branches' body angles
  // Iterative groups' start values kept in the kernel state: field name, default (the assembly).
  std::vector<std::pair<std::string, double>> warm_start;
};

std::vector<Derivation::DriverInputs> make_driver_inputs(const Model& model);

// Numeric samples for the staged program: default parameters and the model's driver values at
// each of `times` (the first should be t0, the assembly; every one a configuration the mechanism
// reaches, or the derivation meets square roots of negative numbers).
std::vector<GiNaC::exmap> make_samples(const Model& model,
                                       const std::vector<Derivation::DriverInputs>& inputs,
                                       const std::vector<double>& times);

// Derives everything; `pose` is the assembled configuration at the model's t0 with default
// parameters (from the numeric solver), used only to pick each group's branch. Throws
// std::runtime_error when the plan is incomplete or no stable pivot exists.
Derivation derive(const Model& model, const SolvePlan& plan, const std::vector<BodyPose>& pose,
                  const std::vector<Derivation::DriverInputs>& inputs, StagedProgram& program);

}  // namespace mechgen::gen
