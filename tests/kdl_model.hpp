// Orocos KDL chains and trees built from a spatial model's numbers, for the independent checks
// (tests/spatial_kdl_test.cpp) and the benchmark (bench/). KDL is a test dependency only.
// Every segment frame coincides with the ground frame at the reference pose (f_tip identity), so
// a joint is KDL's rotation (or translation) about the model's own screw axis s through s0, and
// each body's inertia is its reference-pose inertia: KDL's FK is then exactly the product of
// exponentials, computed by KDL's own code.
#pragma once

#include <kdl/chain.hpp>
#include <kdl/tree.hpp>
#include <stdexcept>
#include <string>

#include "spatial/spatial_solver.hpp"

namespace mechgen::kdl_model {

inline KDL::Vector vec(const spatial::V3& v) {
  return KDL::Vector(v[0], v[1], v[2]);
}

// The segment moved by joint j: its second body, with the joint's screw.
inline KDL::Segment segment(const spatial::SpatialSolver& solver, int j) {
  const SpatialModel& m = solver.model();
  const SpatialJoint& joint = m.joints[static_cast<size_t>(j)];
  const spatial::SpatialInstance& in = solver.instance();
  if (joint.columns.size() != 1 || joint.type == SpatialJointType::helical)
    throw std::invalid_argument("KDL segments: one revolute or prismatic coordinate per joint");
  const auto& axis =
      in.axes[static_cast<size_t>(solver.graph().joint_column[static_cast<size_t>(j)])];
  const KDL::Joint kj(
      joint.name, vec(axis.s0), vec(axis.s),
      joint.type == SpatialJointType::prismatic ? KDL::Joint::TransAxis : KDL::Joint::RotAxis);
  const auto b = static_cast<size_t>(joint.second);
  const spatial::Pose& frame = in.body_frame[b];
  const spatial::M3 I = frame.R * in.inertia[b] * geometry::transpose(frame.R);
  const KDL::RigidBodyInertia inertia(
      in.mass[b], vec(geometry::apply(frame, in.com[b])),
      KDL::RotationalInertia(I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)));
  return KDL::Segment(m.bodies[b].name, kj, KDL::Frame::Identity(), inertia);
}

// A serial chain (joints in model order, each the next body's), ending in a fixed segment whose
// frame origin is the named point of the last body.
inline KDL::Chain chain(const spatial::SpatialSolver& solver, const std::string& tip_point) {
  KDL::Chain c;
  const SpatialModel& m = solver.model();
  for (size_t j = 0; j < m.joints.size(); ++j) c.addSegment(segment(solver, static_cast<int>(j)));
  const auto last = static_cast<size_t>(m.joints.back().second);
  const SpatialBody& body = m.bodies[last];
  for (size_t k = 0; k < body.points.size(); ++k)
    if (body.points[k].name == tip_point) {
      const spatial::V3 x =
          geometry::apply(solver.instance().body_frame[last], solver.instance().points[last][k]);
      c.addSegment(KDL::Segment("tip", KDL::Joint(KDL::Joint::None), KDL::Frame(vec(x))));
      return c;
    }
  throw std::invalid_argument("no point " + tip_point);
}

// A tree rooted at the ground body, joints in model order (KDL numbers the coordinates so).
inline KDL::Tree tree(const spatial::SpatialSolver& solver) {
  const SpatialModel& m = solver.model();
  KDL::Tree t(m.bodies[static_cast<size_t>(m.ground)].name);
  for (size_t j = 0; j < m.joints.size(); ++j)
    if (!t.addSegment(segment(solver, static_cast<int>(j)),
                      m.bodies[static_cast<size_t>(m.joints[j].first)].name))
      throw std::invalid_argument("KDL tree: joint " + m.joints[j].name);
  return t;
}

}  // namespace mechgen::kdl_model
