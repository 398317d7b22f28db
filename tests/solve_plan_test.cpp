// The planner picks the new group kinds from the joint graph alone, prefers closed forms (from any
// reference frame) to the iterative fallback, and leaves the shipped closed-form plans alone.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "model/model.hpp"
#include "model/solve_plan.hpp"

namespace mechgen {
namespace {

SolvePlan plan_of(const std::string& name) {
  return make_solve_plan(read_model(std::string(MECHGEN_SOURCE_DIR) + "/models/" + name + ".yaml"));
}

std::vector<GroupKind> kinds(const SolvePlan& plan) {
  std::vector<GroupKind> result;
  for (const SolveGroup& g : plan.groups) result.push_back(g.kind);
  return result;
}

TEST(SolvePlan, CylinderLegIsTwoRprTriangles) {
  const SolvePlan plan = plan_of("cylinder_leg");
  ASSERT_TRUE(plan.complete());
  EXPECT_EQ(kinds(plan), (std::vector<GroupKind>{GroupKind::rpr, GroupKind::rpr}));
  EXPECT_EQ(plan.groups[0].name, "g1_thigh_barrel1_rod1");
  EXPECT_EQ(plan.groups[1].name, "g2_shank_rod2_barrel2");  // the rod side is pinned to the thigh
  EXPECT_GE(plan.groups[0].driver, 0);
}

TEST(SolvePlan, QuickReturnHasSlotOnTheLeverAndAPrpDyad) {
  const SolvePlan plan = plan_of("quick_return");
  ASSERT_TRUE(plan.complete());
  EXPECT_EQ(kinds(plan), (std::vector<GroupKind>{GroupKind::driven_revolute,
                                                 GroupKind::slot_on_body, GroupKind::prp}));
  EXPECT_TRUE(has_branch(GroupKind::slot_on_body));
  EXPECT_FALSE(has_branch(GroupKind::prp));
}

TEST(SolvePlan, InvertedSliderIsOnePassiveRprDyad) {
  const SolvePlan plan = plan_of("inverted_slider");
  ASSERT_TRUE(plan.complete());
  EXPECT_EQ(kinds(plan),
            (std::vector<GroupKind>{GroupKind::driven_revolute, GroupKind::passive_rpr}));
  EXPECT_EQ(plan.groups[1].name, "g2_rocker_block");  // the slide's first body is the link
  EXPECT_TRUE(has_branch(GroupKind::passive_rpr));
  EXPECT_FALSE(is_iterative(GroupKind::passive_rpr));
}

TEST(SolvePlan, TriadFallsBackToOneIterativeGroupOfFourBodies) {
  const SolvePlan plan = plan_of("assur_triad");
  ASSERT_TRUE(plan.complete());
  ASSERT_EQ(kinds(plan),
            (std::vector<GroupKind>{GroupKind::driven_revolute, GroupKind::iterative}));
  const SolveGroup& triad = plan.groups[1];
  EXPECT_EQ(triad.bodies.size(), 4u);
  EXPECT_EQ(triad.joints.size(), 6u);  // four tree joints, then the two closing ones
  EXPECT_TRUE(is_iterative(triad.kind));
  EXPECT_EQ(plan.reference, 0);  // the fallback plans from the ground
}

TEST(SolvePlan, ShippedClosedFormModelsNeedNoIteration) {
  for (const char* name : {"chebyshev", "slider_crank", "leg3", "pasibot"}) {
    const SolvePlan plan = plan_of(name);
    EXPECT_TRUE(plan.complete()) << name;
    for (const SolveGroup& g : plan.groups)
      EXPECT_FALSE(is_iterative(g.kind)) << name << " " << g.name;
  }
}

}  // namespace
}  // namespace mechgen
