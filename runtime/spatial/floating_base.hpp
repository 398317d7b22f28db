// Inverse dynamics of a floating-base humanoid in single support (issue 13): the support foot is
// the ground, every real joint is actuated, nothing else touches the robot. The whole-body
// kinematics (positions, twists, twist rates of every body) come from Davies' method on the
// virtual-chain mechanism; the dynamics are those of the tree of real bodies rooted at the
// support foot, the virtual chains playing no part:
//  - each body's wrench W_b = (m (a - g), I al + w x I w + c x m (a - g)) about the ground origin;
//  - the wrench a joint passes to the part of the tree beyond it (away from the support foot) is
//    the sum of that part's W_b; the joint's torque (force for a prismatic coordinate) is its
//    reciprocal product with the joint's screw, signed as the first body's effort on the second;
//  - the floor's wrench on the support foot is W_foot plus what the foot passes through its
//    joint, which equals the momentum rate of all bodies minus gravity (a check).
// ZMP two ways: exact, where the floor wrench has no horizontal moment on the floor plane; and
// Kajita's LIP-3D from the centre of mass alone (seed 001 appendix B):
//   p = c - (c_z / g) c''   (horizontal components; the floor at z = 0, gravity along -z).
#pragma once

#include <string>
#include <vector>

#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {

struct FloatingBaseLoads {
  std::vector<double> torque;  // per joint (0 for virtual joints and multi-coordinate joints)
  Wrench floor;                // on the support foot, about the ground origin
  Wrench momentum_rate;        // sum over bodies of W_b (equals `floor`)
};

// Throws ModelError when a real joint has more than one coordinate or the real bodies do not
// form a tree containing `support`.
FloatingBaseLoads single_support_dynamics(const SpatialSolver& solver, const SpatialState& state,
                                          int support);

// The point of the floor plane z = floor_z where the wrench (force f, moment m about the ground
// origin) has no horizontal moment. NaN when f_z = 0.
V3 zmp_of(const Wrench& w, double floor_z = 0);
// Kajita's LIP-3D ZMP from the centre of mass position and acceleration (gravity magnitude g).
V3 lip_zmp(const V3& com, const V3& com_acceleration, double g, double floor_z = 0);

// The convex hull of points projected on the x-y plane (Andrew's monotone chain), counter-
// clockwise: a foot's support polygon from its sole points.
std::vector<V3> convex_hull_xy(std::vector<V3> points);

// Signed distance from a point to the edge of a convex polygon in the x-y plane (positive
// inside), the vertices in either winding order.
double polygon_margin(const std::vector<V3>& polygon, const V3& point);

}  // namespace mechgen::spatial
