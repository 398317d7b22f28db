// The spatial reference solver against Orocos KDL, built from the same numbers
// (tests/kdl_model.hpp): forward kinematics, the Jacobian and recursive Newton-Euler inverse
// dynamics on random configurations, velocities and accelerations, for the serial leg6 and a
// two-branch tree.
#include <gtest/gtest.h>

#include <kdl/chaindynparam.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/treefksolverpos_recursive.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <random>

#include "kdl_model.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_mass_matrix.hpp"
#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {
namespace {

struct Sample {
  Eigen::VectorXd q, qd, qdd;
};

Sample random_sample(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(-1, 1);
  Sample s{Eigen::VectorXd(n), Eigen::VectorXd(n), Eigen::VectorXd(n)};
  for (int i = 0; i < n; ++i) s.q[i] = 1.5 * u(rng), s.qd[i] = 2 * u(rng), s.qdd[i] = 5 * u(rng);
  return s;
}

KDL::JntArray jnt(const Eigen::VectorXd& x) {
  KDL::JntArray a(static_cast<unsigned>(x.size()));
  a.data = x;
  return a;
}

// Our state at a given configuration and rates of an all-driven tree.
SpatialState state_at(const SpatialSolver& solver, const Sample& x) {
  SpatialState s;
  s.q = x.q;
  solver.place(s);
  solver.rates(s, x.qd, x.qdd);
  return s;
}

TEST(SpatialKdl, Leg6ForwardKinematicsJacobianAndInverseDynamics) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/leg6.yaml");
  const SpatialSolver solver(model, {});
  const KDL::Chain chain = kdl_model::chain(solver, "foot");
  ASSERT_EQ(chain.getNrOfJoints(), 6u);
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainJntToJacSolver jac(chain);
  KDL::ChainIdSolver_RNE id(chain, kdl_model::vec(solver.instance().gravity));
  const int foot = model.body_index("foot_link");
  const V3 foot_local = solver.instance().points[static_cast<size_t>(foot)][0];
  std::mt19937 rng(7);
  double worst_fk = 0, worst_jac = 0, worst_id = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const Sample x = random_sample(rng, 6);
    const SpatialState s = state_at(solver, x);
    KDL::Frame frame;
    ASSERT_GE(fk.JntToCart(jnt(x.q), frame), 0);
    const V3 p = solver.point_position(s, foot, foot_local);
    const Pose pose = solver.body_pose(s, foot);
    for (int i = 0; i < 3; ++i) {
      worst_fk = std::max(worst_fk, std::abs(frame.p(i) - p[static_cast<size_t>(i)]));
      for (int k = 0; k < 3; ++k)
        worst_fk = std::max(worst_fk, std::abs(frame.M(i, k) - pose.R(i, k)));
    }
    KDL::Jacobian J(6);
    ASSERT_GE(jac.JntToJac(jnt(x.q), J), 0);
    const Eigen::MatrixXd Jv = solver.point_jacobian(s, foot, p);
    const Eigen::MatrixXd Jw = solver.body_jacobian(s, foot).topRows(3);
    worst_jac = std::max(worst_jac, (J.data.topRows(3) - Jv).cwiseAbs().maxCoeff());
    worst_jac = std::max(worst_jac, (J.data.bottomRows(3) - Jw).cwiseAbs().maxCoeff());
    KDL::JntArray torque(6);
    KDL::Wrenches external(chain.getNrOfSegments(), KDL::Wrench::Zero());
    ASSERT_GE(id.CartToJnt(jnt(x.q), jnt(x.qd), jnt(x.qdd), external, torque), 0);
    const SpatialLoads loads = inverse_dynamics(solver, s);
    worst_id = std::max(worst_id, (torque.data - loads.effort).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst_fk, 1e-12);
  EXPECT_LT(worst_jac, 1e-12);
  EXPECT_LT(worst_id, 1e-12);
  std::cout << "leg6 against KDL over 50 random samples: FK " << worst_fk << ", Jacobian "
            << worst_jac << ", inverse dynamics " << worst_id << " N m\n";
}

// The mass matrix and bias by unit accelerations against KDL's ChainDynParam (composite rigid
// bodies): M = JntToMass, h = JntToCoriolis + JntToGravity.
TEST(SpatialKdl, Leg6MassMatrixAndBias) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/leg6.yaml");
  const SpatialSolver solver(model, {});
  const KDL::Chain chain = kdl_model::chain(solver, "foot");
  KDL::ChainDynParam dyn(chain, kdl_model::vec(solver.instance().gravity));
  std::mt19937 rng(11);
  double worst_m = 0, worst_h = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const Sample x = random_sample(rng, 6);
    const SpatialState s = state_at(solver, x);
    const MassBias mb = mass_matrix_bias(solver, s, x.qd);
    KDL::JntSpaceInertiaMatrix M(6);
    KDL::JntArray coriolis(6), gravity(6);
    ASSERT_GE(dyn.JntToMass(jnt(x.q), M), 0);
    ASSERT_GE(dyn.JntToCoriolis(jnt(x.q), jnt(x.qd), coriolis), 0);
    ASSERT_GE(dyn.JntToGravity(jnt(x.q), gravity), 0);
    worst_m = std::max(worst_m, (M.data - mb.M).cwiseAbs().maxCoeff());
    worst_h = std::max(worst_h, (coriolis.data + gravity.data - mb.h).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst_m, 1e-12);
  EXPECT_LT(worst_h, 1e-12);
  std::cout << "leg6 against KDL ChainDynParam over 50 random samples: M " << worst_m << ", h "
            << worst_h << "\n";
}

// Two 3-DOF branches on one waist, with a prismatic joint, off-diagonal inertia and rotated body
// frames: KDL's tree solvers against ours.
const char* const kTree = R"(name: two_branch
dimension: spatial
gravity: [0.5, -1, -9.81]
bodies:
  - {name: waist, ground: true}
  - {name: r1, mass: {mass: 0.3, com: [0.01, -0.05, -0.02], inertia: [[1e-3, 1e-4, 0], [1e-4, 2e-3, -2e-4], [0, -2e-4, 1.5e-3]]}}
  - {name: r2, origin: [0, -0.05, -0.1], rotation: {axis: [0, 0.6, 0.8], angle: 0.7},
     mass: {mass: 0.2, com: [0.02, 0, -0.05], inertia: [[2e-3, 0, 3e-4], [0, 2e-3, 0], [3e-4, 0, 1e-3]]}}
  - {name: r3, points: {tip: [0.03, -0.05, -0.3]},
     mass: {mass: 0.1, com: [0.01, -0.05, -0.25], inertia: [1e-4, 2e-4, 3e-4]}}
  - {name: l1, mass: {mass: 0.25, com: [0, 0.05, -0.03], inertia: [1e-3, 1e-3, 5e-4]}}
  - {name: l2, mass: {mass: 0.15, com: [0.01, 0.06, -0.12], inertia: [[1e-3, -1e-4, 0], [-1e-4, 1e-3, 0], [0, 0, 4e-4]]}}
joints:
  - {name: rj1, type: revolute, first: waist, second: r1, s: [0, 0, 1], s0: [0, -0.05, 0]}
  - {name: rj2, type: revolute, first: r1, second: r2, s: [1, 0, 0], s0: [0, -0.05, -0.1]}
  - {name: rj3, type: prismatic, first: r2, second: r3, s: [0, 0.6, -0.8], s0: [0, -0.05, -0.2]}
  - {name: lj1, type: revolute, first: waist, second: l1, s: [0, 1, 0], s0: [0, 0.05, 0]}
  - {name: lj2, type: revolute, first: l1, second: l2, s: [0.6, 0, 0.8], s0: [0.01, 0.05, -0.1]}
drivers:
  - {name: d1, joint: rj1, kind: angle, value: t}
  - {name: d2, joint: rj2, kind: angle, value: t}
  - {name: d3, joint: rj3, kind: length, value: t}
  - {name: d4, joint: lj1, kind: angle, value: t}
  - {name: d5, joint: lj2, kind: angle, value: t}
step: {t0: 0, t1: 1}
)";

TEST(SpatialKdl, TreeForwardKinematicsAndInverseDynamics) {
  const SpatialModel model = read_spatial_model_text(kTree, "two_branch.yaml");
  const SpatialSolver solver(model, {});
  const KDL::Tree tree = kdl_model::tree(solver);
  ASSERT_EQ(tree.getNrOfJoints(), 5u);
  KDL::TreeFkSolverPos_recursive fk(tree);
  KDL::TreeIdSolver_RNE id(tree, kdl_model::vec(solver.instance().gravity));
  std::mt19937 rng(11);
  double worst_fk = 0, worst_id = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const Sample x = random_sample(rng, 5);
    const SpatialState s = state_at(solver, x);
    for (const char* body : {"r3", "l2", "r2"}) {
      KDL::Frame frame;
      ASSERT_GE(fk.JntToCart(jnt(x.q), frame, body), 0);
      // KDL's segment frame is the ground frame at the reference pose, moved: our D.
      const Pose& D = s.D[static_cast<size_t>(model.body_index(body))];
      for (int i = 0; i < 3; ++i) {
        worst_fk = std::max(worst_fk, std::abs(frame.p(i) - D.p[static_cast<size_t>(i)]));
        for (int k = 0; k < 3; ++k)
          worst_fk = std::max(worst_fk, std::abs(frame.M(i, k) - D.R(i, k)));
      }
    }
    KDL::JntArray torque(5);
    ASSERT_GE(id.CartToJnt(jnt(x.q), jnt(x.qd), jnt(x.qdd), KDL::WrenchMap(), torque), 0);
    worst_id = std::max(worst_id,
                        (torque.data - inverse_dynamics(solver, s).effort).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst_fk, 1e-12);
  EXPECT_LT(worst_id, 1e-12);
  std::cout << "two-branch tree against KDL: FK " << worst_fk << ", inverse dynamics " << worst_id
            << "\n";
}

}  // namespace
}  // namespace mechgen::spatial
