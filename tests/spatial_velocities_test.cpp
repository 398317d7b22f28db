// The velocity-only entry of generated spatial kernels (velocities(): positions and first rates,
// issue 13's velocity solve): along each model's step, every position and velocity column equals
// kinematics()' to 1e-15 (relative), the columns it does not compute (accelerations, efforts,
// reactions) stay untouched, and a closed chain's Davies velocities equal the numeric solver's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "bioloid/bioloid.hpp"
#include "leg6/leg6.hpp"
#include "quadruped_leg/quadruped_leg.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"

namespace mechgen::spatial {
namespace {

// A column velocities() leaves alone: a second rate or a force.
bool not_a_velocity_column(const std::string& name) {
  const std::string field = name.substr(name.rfind('.') + 1);
  return field == "ax" || field == "ay" || field == "az" || field.rfind("al", 0) == 0 ||
         (field.size() > 2 && field.compare(field.size() - 2, 2, "dd") == 0) || field == "effort" ||
         field == "fx" || field == "fy" || field == "fz" || field == "mx" || field == "my" ||
         field == "mz";
}

// Walks the model's step through both entries and the numeric solver; returns the largest
// difference of a secondary coordinate's rate from the solver's.
template <class Kernel>
double velocities_equal_kinematics(const std::string& name) {
  using State = typename Kernel::State;
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/" + name + ".yaml");
  SpatialSolver solver(model, model.common.default_parameters());
  const SpatialSweepOptions step = default_spatial_sweep(model);
  const std::vector<std::string> names(Kernel::names(), Kernel::names() + Kernel::count);
  typename Kernel::Params p;
  SpatialState numeric;
  double worst_qd = 0;
  for (int i = 0; i < step.samples; i += 7) {
    const double t = step.t0 + (step.t1 - step.t0) * i / (step.samples - 1);
    typename Kernel::Inputs in;
    Kernel::driver_inputs(p, t, in);
    State fast{}, full{};
    EXPECT_EQ(Kernel::velocities(p, in, fast), 0) << name << " t = " << t;
    EXPECT_EQ(Kernel::kinematics(p, in, full), 0) << name << " t = " << t;
    std::vector<double> a(names.size()), b(names.size()), untouched(names.size());
    Kernel::to_columns(in, fast, a.data());
    Kernel::to_columns(in, full, b.data());
    Kernel::to_columns(in, State{}, untouched.data());
    for (size_t c = 0; c < names.size(); ++c) {
      if (not_a_velocity_column(names[c]))
        EXPECT_EQ(a[c], untouched[c]) << name << " " << names[c] << " t = " << t;
      else
        EXPECT_LE(std::abs(a[c] - b[c]), 1e-15 * std::max(1.0, std::abs(b[c])))
            << name << " " << names[c] << " t = " << t;
    }
    solver.solve(t, numeric);
    for (const int k : solver.graph().secondary) {
      // A joint's columns are q, or q1, q2, ... when it has several coordinates.
      const int j = solver.graph().columns[static_cast<size_t>(k)].joint;
      const SpatialJoint& joint = model.joints[static_cast<size_t>(j)];
      const int within = k - solver.graph().joint_column[static_cast<size_t>(j)];
      const std::string column =
          joint.name +
          (joint.columns.size() == 1 ? ".qd" : ".q" + std::to_string(within + 1) + "d");
      const auto at = std::find(names.begin(), names.end(), column);
      EXPECT_NE(at, names.end()) << column;
      if (at == names.end()) continue;
      worst_qd = std::max(worst_qd, std::abs(a[static_cast<size_t>(at - names.begin())] -
                                             numeric.qd[static_cast<Eigen::Index>(k)]));
    }
  }
  return worst_qd;
}

// One generated kernel's entries behind one interface.
#define MECHGEN_KERNEL_TRAITS(traits, ns)                                   \
  struct traits {                                                           \
    using State = gen::ns::State<double>;                                   \
    using Params = gen::ns::Params<double>;                                 \
    using Inputs = gen::ns::Inputs<double>;                                 \
    static constexpr int count = gen::ns::column_count;                     \
    static const char* const* names() { return gen::ns::column_names; }     \
    static void driver_inputs(const Params& p, double t, Inputs& in) {      \
      gen::ns::driver_inputs(p, t, in);                                     \
    }                                                                       \
    static int velocities(const Params& p, const Inputs& in, State& s) {    \
      return static_cast<int>(gen::ns::velocities(p, in, s));               \
    }                                                                       \
    static int kinematics(const Params& p, const Inputs& in, State& s) {    \
      return static_cast<int>(gen::ns::kinematics(p, in, s));               \
    }                                                                       \
    static void to_columns(const Inputs& in, const State& s, double* row) { \
      gen::ns::to_columns(in, s, row);                                      \
    }                                                                       \
  };
MECHGEN_KERNEL_TRAITS(Leg6, leg6)
MECHGEN_KERNEL_TRAITS(QuadrupedLeg, quadruped_leg)
MECHGEN_KERNEL_TRAITS(Bioloid, bioloid)
#undef MECHGEN_KERNEL_TRAITS

TEST(SpatialVelocities, Leg6SerialChainEqualsKinematics) {
  velocities_equal_kinematics<Leg6>("leg6");  // no secondary coordinates
}

TEST(SpatialVelocities, QuadrupedLegDaviesVelocitiesEqualKinematicsAndTheNumericSolver) {
  EXPECT_LT(velocities_equal_kinematics<QuadrupedLeg>("quadruped_leg"), 1e-9);
}

TEST(SpatialVelocities, BioloidDaviesVelocitiesEqualKinematicsAndTheNumericSolver) {
  EXPECT_LT(velocities_equal_kinematics<Bioloid>("bioloid"), 1e-9);
}

}  // namespace
}  // namespace mechgen::spatial
