// Closed-form position groups of spatial closed chains (generator/spatial_link_loops.hpp): the
// quadruped leg's four link groups (no Newton-Raphson in its kernel) reach Status::unreachable
// naming the group where a cylinder cannot close, never NaN; the positions-only entry equals
// evaluate(); the workspace through the generated kernel equals the numeric solver's.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "analysis/workspace.hpp"
#include "quadruped_leg/quadruped_leg.hpp"
#include "spatial/spatial_solver.hpp"
#include "sweep/compiled_kernel.hpp"

namespace mechgen::spatial {
namespace {

namespace k = gen::quadruped_leg;

// Cylinder l1 drawn out far beyond any length the hip can take: the hip's group has no real
// angle (its discriminant is negative). Unreachable, named and the State cleared (no NaN).
TEST(SpatialClosedForm, QuadrupedCylinderTooLongIsUnreachableNamingTheGroup) {
  const k::Params<double> p;
  k::State<double> s;
  k::Inputs<double> in;
  k::driver_inputs(p, 0.4, in);
  ASSERT_EQ(k::evaluate(p, in, s), k::Status::ok);
  k::Inputs<double> far = in;
  far.l1 = 1.0;
  using Entry =
      k::Status (*)(const k::Params<double>&, const k::Inputs<double>&, k::State<double>&);
  const Entry entries[] = {&k::evaluate<double>, &k::kinematics<double>, &k::control<double>,
                           &k::point_positions<double>};
  for (const Entry entry : entries) {
    ASSERT_EQ(entry(p, far, s), k::Status::unreachable);
    ASSERT_GE(s.failed_group, 0);
    EXPECT_EQ(std::string(k::group_names[s.failed_group]).rfind("hip", 0), 0u)
        << k::group_names[s.failed_group];
    EXPECT_EQ(s.points.D.x, 0.0);
    EXPECT_FALSE(std::isnan(s.bodies.shank.x));
  }
  // Back in range: ok again.
  EXPECT_EQ(k::evaluate(p, in, s), k::Status::ok);
}

// The positions-only entry gives evaluate()'s named points, from a fresh State each time (it
// needs no warm start: the groups are closed form), over the whole stroke box.
TEST(SpatialClosedForm, QuadrupedPointPositionsEqualEvaluate) {
  const k::Params<double> p;
  double worst = 0;
  for (int i = 0; i < 27; ++i) {
    k::Inputs<double> in;
    in.l1 = -0.06 + 0.06 * (i % 3);
    in.l2 = -0.06 + 0.06 * (i / 3 % 3);
    in.l3 = -0.02 + 0.02 * (i / 9);
    in.t = 0.1 * (i + 1);
    k::State<double> full, placed;
    ASSERT_EQ(k::evaluate(p, in, full), k::Status::ok) << i;
    ASSERT_EQ(k::point_positions(p, in, placed), k::Status::ok) << i;
    for (const auto& [a, b] :
         {std::pair{full.points.D, placed.points.D}, std::pair{full.points.A, placed.points.A}}) {
      worst = std::max({worst, std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)});
      EXPECT_NE(b.x, 0.0);
    }
  }
  EXPECT_LT(worst, 1e-14);
}

// `mechgen workspace`: the generated kernel's batch and the numeric solver draw the same
// samples, so the extents and the images' chords agree.
TEST(SpatialClosedForm, WorkspaceGeneratedEqualsNumeric) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/quadruped_leg.yaml");
  analysis::WorkspaceOptions o;
  o.samples = 1500;
  o.threads = 2;
  const analysis::WorkspaceResult numeric = analysis::run_workspace(model, o);
  o.kernel = find_compiled_kernel("quadruped_leg");
  ASSERT_NE(o.kernel, nullptr);
  const analysis::WorkspaceResult generated = analysis::run_workspace(model, o);
  EXPECT_TRUE(generated.generated);
  EXPECT_FALSE(numeric.generated);
  EXPECT_EQ(generated.assembled, numeric.assembled);
  EXPECT_EQ(generated.assembled, 1500);
  for (size_t c = 0; c < 3; ++c) {
    EXPECT_NEAR(generated.lo[c], numeric.lo[c], 1e-9) << c;
    EXPECT_NEAR(generated.hi[c], numeric.hi[c], 1e-9) << c;
    EXPECT_GT(generated.hi[c] - generated.lo[c], 0.1) << c;
  }
  EXPECT_EQ(generated.sagittal.h_chord, numeric.sagittal.h_chord);
  EXPECT_EQ(generated.sagittal.v_chord, numeric.sagittal.v_chord);
}

}  // namespace
}  // namespace mechgen::spatial
