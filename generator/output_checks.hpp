// The finiteness check of a kernel's outputs: one test per stage (positions, rates, forces), so
// that `ok` never comes with an infinite or NaN output, at the cost of one addition per output and
// one comparison per stage, with no branch per output.
//
// The outputs of a stage are summed pairwise (a tree, so the additions do not form one long
// dependency chain) into `_sum_<stage>`; the sum is finite exactly when every output is, or when
// it overflows (outputs beyond about 1e305, or 1e36 in float: meaningless, and a failure either
// way). The check is `_sum - _sum == T(0)`, false for an infinite or NaN sum, and valid for any
// scalar type (no std::isfinite, no -ffast-math assumption).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace mechgen::gen {

// The stages a kernel's outputs belong to, in the order they are checked; `inputs` is the check
// of the driver inputs that precedes every computation.
enum class OutputStage { inputs = 0, positions, rates, forces, none };
inline constexpr const char* kStageNames[] = {"inputs", "positions", "rates", "forces"};
inline constexpr int kStageCount = 4;

// The stage of a State field as the emitter writes it: `s.bodies.<b>.<f>`, `s.points.<p>.<f>`,
// `s.joints.<j>.<f>`, `s.drivers.<d>.<f>` (a body's `th()` is a position); anything else (the warm
// start, the inputs) is `none`.
OutputStage stage_of(const std::string& source);
// The same for a spatial kernel's State (generator/spatial_emitter.cpp): a body's x, y, z and R[k],
// a point's x, y, z, a joint's or driver's coordinates (q, q1, ...) and every screw Jacobian entry
// (`s.body_jacobians.`, `s.point_jacobians.`) are positions; wrenches (fx ... mz) and driver
// efforts are forces; every other State field (velocities, accelerations, qd, qdd) is a rate.
OutputStage spatial_stage_of(const std::string& target);

struct CheckedOutput {
  OutputStage stage;
  std::string expression;  // what to read, e.g. `s.points.A.x` or `out[3 * stride + i]`
};

// For each stage that has outputs, in stage order: the lines defining `_sum_<stage>` and then
// `check_line(stage, condition)`, where condition is true when the stage is finite. Each line is
// prefixed with `indent` and ends with '\n'.
std::string output_checks(
    const std::vector<CheckedOutput>& outputs, const std::string& indent,
    const std::function<std::string(OutputStage, const std::string& condition)>& check_line);

}  // namespace mechgen::gen
