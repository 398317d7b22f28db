// The Bioloid walking gait (issue 13 items 2-4) on the numeric solver: closure N q' = 0 along the
// gait, Davies' velocities against finite differences of positions, each leg's velocities against
// the inverse of KDL's Jacobian applied to the foot's twist relative to the waist, the
// single-support torques and floor wrench against KDL's recursive Newton-Euler on the tree rooted
// at the support foot, power balance, the two ZMPs.
#include <gtest/gtest.h>

#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include "kdl_model.hpp"
#include "spatial/floating_base.hpp"
#include "spatial/humanoid_gait.hpp"
#include "spatial/leg_ik.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_sweep.hpp"
#include "sweep/compiled_kernel.hpp"

namespace mechgen::spatial {
namespace {

struct Walk {
  SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/bioloid.yaml");
  SpatialSolver solver{model, {}};
  HumanoidGait gait{solver, gait_settings(solver)};
  // Samples strictly inside each step (no support switch within +-1e-3 s).
  std::vector<double> times(int per_step) const {
    std::vector<double> t;
    const double T = gait.settings().step_time;
    for (int k = 0; k < gait.settings().steps; ++k)
      for (int i = 0; i < per_step; ++i) t.push_back(k * T + T * (i + 0.5) / per_step);
    return t;
  }
  void solve(double t, SpatialState& s) const { gait.solve(t, s); }
  int column(const std::string& joint) const {
    return solver.graph().joint_column[static_cast<size_t>(model.joint_index(joint))];
  }
};

const char* const kLegs[2][6] = {{"RL1", "RL2", "RL3", "RL4", "RL5", "RL6"},
                                 {"LL1", "LL2", "LL3", "LL4", "LL5", "LL6"}};

TEST(BioloidGait, ClosureAndDaviesVelocitiesAgainstFiniteDifferences) {
  const Walk w;
  SpatialState s, a, b;
  double worst_closure = 0, worst_v = 0, worst_a = 0, worst_stance = 0;
  const double h = 1e-5;
  for (const double t : w.times(6)) {
    w.solve(t, s);
    worst_closure = std::max(worst_closure, (w.solver.network(s) * s.qd).cwiseAbs().maxCoeff());
    a = s, b = s;
    w.solve(t - h, a);
    w.solve(t + h, b);
    for (int c = 0; c < w.solver.graph().cols(); ++c) {
      worst_v = std::max(worst_v, std::abs((b.q[c] - a.q[c]) / (2 * h) - s.qd[c]));
      worst_a = std::max(worst_a, std::abs((b.qd[c] - a.qd[c]) / (2 * h) - s.qdd[c]));
    }
    // The support foot stands still.
    const int foot =
        w.model.pose_drivers[static_cast<size_t>(w.gait.foot_driver(w.gait.support(t)))].second;
    const Twist& V = s.V[static_cast<size_t>(foot)];
    const Twist& A = s.A[static_cast<size_t>(foot)];
    for (size_t i = 0; i < 3; ++i)
      worst_stance = std::max(
          {worst_stance, std::abs(V.w[i]), std::abs(V.v[i]), std::abs(A.w[i]), std::abs(A.v[i])});
  }
  EXPECT_LT(worst_closure, 1e-12);
  EXPECT_LT(worst_v, 1e-7);
  EXPECT_LT(worst_a, 1e-5);
  EXPECT_LT(worst_stance, 1e-12);
  std::cout << "gait: N q' " << worst_closure << ", velocity vs FD " << worst_v
            << ", acceleration vs FD " << worst_a << "\n";
}

// Each leg alone, waist to sole, as a KDL chain: q' = J^-1 (twist of the foot relative to the
// waist, in the waist's frame, at the sole point).
TEST(BioloidGait, LegVelocitiesAreKdlJacobianInverseOfTheFootTwist) {
  const Walk w;
  const SpatialInstance& in = w.solver.instance();
  const int waist = w.model.body_index("waist");
  const char* feet[2] = {"r_foot", "l_foot"};
  const char* soles[2] = {"RF", "LF"};
  double worst = 0;
  SpatialState s;
  for (int side = 0; side < 2; ++side) {
    KDL::Chain chain;
    for (const char* j : kLegs[side])
      chain.addSegment(kdl_model::segment(w.solver, w.model.joint_index(j)));
    const int foot = w.model.body_index(feet[side]);
    const SpatialBody& fb = w.model.bodies[static_cast<size_t>(foot)];
    V3 sole0{0, 0, 0};
    for (size_t k = 0; k < fb.points.size(); ++k)
      if (fb.points[k].name == soles[side]) sole0 = in.points[static_cast<size_t>(foot)][k];
    chain.addSegment(
        KDL::Segment("sole", KDL::Joint(KDL::Joint::None), KDL::Frame(kdl_model::vec(sole0))));
    KDL::ChainJntToJacSolver jac(chain);
    for (const double t : w.times(5)) {
      w.solve(t, s);
      KDL::JntArray q(6);
      Eigen::VectorXd qd(6);
      for (int i = 0; i < 6; ++i) {
        q(static_cast<unsigned>(i)) = s.q[w.column(kLegs[side][i])];
        qd[i] = s.qd[w.column(kLegs[side][i])];
      }
      KDL::Jacobian J(6);
      ASSERT_GE(jac.JntToJac(q, J), 0);
      // Relative twist, ground frame, then in the waist's frame at the sole point.
      const Twist rel = s.V[static_cast<size_t>(foot)] - s.V[static_cast<size_t>(waist)];
      const Pose& Dw = s.D[static_cast<size_t>(waist)];
      const V3 sole = geometry::apply(s.D[static_cast<size_t>(foot)], sole0);
      const M3 Rt = geometry::transpose(Dw.R);
      const V3 v = Rt * geometry::point_velocity(rel, sole), om = Rt * rel.w;
      Eigen::Matrix<double, 6, 1> x;
      x << v[0], v[1], v[2], om[0], om[1], om[2];
      const Eigen::VectorXd kdl_qd = J.data.fullPivLu().solve(x);
      worst = std::max(worst, (kdl_qd - qd).cwiseAbs().maxCoeff());
    }
  }
  EXPECT_LT(worst, 1e-10);
  std::cout << "legs: Davies vs KDL J^-1 foot twist " << worst << " rad/s\n";
}

// The tree of real bodies rooted at the support foot, as KDL sees it: a 3P3R chain from the floor
// to the foot (at zero: its torques are the floor's wrench), then every real joint outwards,
// reversed where it points towards the foot. Frames: the foot's reference frame (the floor frame
// mapped back by the foot's displacement), gravity rotated into it.
struct KdlSupportTree {
  KDL::Tree tree{"floor"};
  std::vector<int> joint_of_qnr;  // -1: virtual root coordinate k (0..5)
};

KdlSupportTree support_tree(const SpatialSolver& solver, int foot, const V3& at) {
  const SpatialModel& m = solver.model();
  const SpatialInstance& in = solver.instance();
  KdlSupportTree out;
  auto inertia = [&](int body) {
    const auto b = static_cast<size_t>(body);
    const M3& I = in.inertia[b];  // body frames are the reference ground frame here
    return KDL::RigidBodyInertia(
        in.mass[b], kdl_model::vec(in.com[b]),
        KDL::RotationalInertia(I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)));
  };
  const KDL::Vector axes[3] = {KDL::Vector(1, 0, 0), KDL::Vector(0, 1, 0), KDL::Vector(0, 0, 1)};
  std::string parent = "floor";
  for (int k = 0; k < 6; ++k) {
    const std::string name = "v" + std::to_string(k);
    const KDL::Joint j(name, kdl_model::vec(at), axes[k % 3],
                       k < 3 ? KDL::Joint::TransAxis : KDL::Joint::RotAxis);
    EXPECT_TRUE(out.tree.addSegment(KDL::Segment(name, j, KDL::Frame::Identity()), parent));
    parent = name;
  }
  const std::string foot_name = m.bodies[static_cast<size_t>(foot)].name;
  EXPECT_TRUE(out.tree.addSegment(
      KDL::Segment(foot_name, KDL::Joint(KDL::Joint::None), KDL::Frame::Identity(), inertia(foot)),
      parent));
  std::vector<bool> reached(m.bodies.size(), false);
  std::vector<int> queue{foot};
  reached[static_cast<size_t>(foot)] = true;
  for (size_t q = 0; q < queue.size(); ++q) {
    const int b = queue[q];
    for (size_t j = 0; j < m.joints.size(); ++j) {
      const SpatialJoint& joint = m.joints[j];
      if (joint.is_virtual || (joint.first != b && joint.second != b)) continue;
      const int child = joint.first == b ? joint.second : joint.first;
      if (reached[static_cast<size_t>(child)]) continue;
      reached[static_cast<size_t>(child)] = true;
      queue.push_back(child);
      const auto& axis = in.axes[static_cast<size_t>(solver.graph().joint_column[j])];
      const KDL::Vector s = kdl_model::vec(axis.s);
      const KDL::Joint kj(joint.name, kdl_model::vec(axis.s0), joint.second == child ? s : -s,
                          KDL::Joint::RotAxis);
      EXPECT_TRUE(out.tree.addSegment(KDL::Segment(m.bodies[static_cast<size_t>(child)].name, kj,
                                                   KDL::Frame::Identity(), inertia(child)),
                                      m.bodies[static_cast<size_t>(b)].name));
    }
  }
  out.joint_of_qnr.assign(out.tree.getNrOfJoints(), -1);
  for (const auto& [name, element] : out.tree.getSegments()) {
    const KDL::Joint& j = element.segment.getJoint();
    if (j.getType() == KDL::Joint::None) continue;
    out.joint_of_qnr[GetTreeElementQNr(element)] =
        name[0] == 'v' && name.size() == 2 ? -1 - (name[1] - '0') : m.joint_index(j.getName());
  }
  return out;
}

TEST(BioloidGait, SingleSupportTorquesAndFloorWrenchAgainstKdlAndPowerBalance) {
  const Walk w;
  double worst_tau = 0, worst_floor = 0, worst_zmp = 0, worst_power = 0, worst_wrist = 0;
  SpatialState s;
  for (const double t : w.times(4)) {
    w.solve(t, s);
    const int side = w.gait.support(t);
    const PoseDriver& pd = w.model.pose_drivers[static_cast<size_t>(w.gait.foot_driver(side))];
    const FloatingBaseLoads loads = single_support_dynamics(w.solver, s, pd.second);
    // Floor ZMP equals the momentum-rate ZMP of all bodies.
    const V3 z1 = zmp_of(loads.floor), z2 = zmp_of(loads.momentum_rate);
    worst_zmp = std::max({worst_zmp, std::abs(z1[0] - z2[0]), std::abs(z1[1] - z2[1])});
    // KDL in the foot's reference frame.
    const GiNaC::exmap subs = w.model.common.substitutions(w.solver.parameters());
    const V3 at{w.model.evaluate(pd.at.x, subs), w.model.evaluate(pd.at.y, subs),
                w.model.evaluate(pd.at.z, subs)};
    const KdlSupportTree kt = support_tree(w.solver, pd.second, at);
    const Pose& Df = s.D[static_cast<size_t>(pd.second)];
    const M3 Rt = geometry::transpose(Df.R);
    KDL::TreeIdSolver_RNE id(kt.tree, kdl_model::vec(Rt * w.solver.instance().gravity));
    const auto n = static_cast<unsigned>(kt.joint_of_qnr.size());
    KDL::JntArray q(n), qd(n), qdd(n), tau(n);
    for (unsigned k = 0; k < n; ++k)
      if (const int j = kt.joint_of_qnr[k]; j >= 0) {
        const int c = w.solver.graph().joint_column[static_cast<size_t>(j)];
        q(k) = s.q[c], qd(k) = s.qd[c], qdd(k) = s.qdd[c];
      }
    ASSERT_GE(id.CartToJnt(q, qd, qdd, KDL::WrenchMap(), tau), 0);
    V3 f{0, 0, 0}, m_at{0, 0, 0};
    for (unsigned k = 0; k < n; ++k) {
      const int j = kt.joint_of_qnr[k];
      if (j >= 0) {
        worst_tau = std::max(worst_tau, std::abs(tau(k) - loads.torque[static_cast<size_t>(j)]));
      } else if (-1 - j < 3) {
        f[static_cast<size_t>(-1 - j)] = tau(k);
      } else {
        m_at[static_cast<size_t>(-4 - j)] = tau(k);
      }
    }
    const V3 fw = Df.R * f, at_w = geometry::apply(Df, at);
    const V3 mw = Df.R * m_at + geometry::cross(at_w, fw);
    for (size_t i = 0; i < 3; ++i)
      worst_floor = std::max(
          {worst_floor, std::abs(fw[i] - loads.floor.f[i]), std::abs(mw[i] - loads.floor.m[i])});
    // Power balance: the joints' power is the rate of kinetic plus potential energy.
    double power = 0;
    for (size_t j = 0; j < w.model.joints.size(); ++j)
      if (!w.model.joints[j].is_virtual)
        power += loads.torque[j] * s.qd[w.solver.graph().joint_column[j]];
    const Energy e = energy(w.solver, s);
    worst_power = std::max(worst_power, std::abs(power - e.kinetic_rate - e.potential_rate));
    // The seed's added wrist joints carry massless bodies: free, no torque.
    for (const char* j : {"RA4", "RA5", "RA6", "LA4", "LA5", "LA6"})
      worst_wrist = std::max(worst_wrist,
                             std::abs(loads.torque[static_cast<size_t>(w.model.joint_index(j))]));
  }
  EXPECT_LT(worst_tau, 1e-12);
  EXPECT_LT(worst_floor, 1e-11);
  EXPECT_LT(worst_zmp, 1e-12);
  EXPECT_LT(worst_power, 1e-12);
  EXPECT_LT(worst_wrist, 1e-15);
  std::cout << "single support vs KDL: torques " << worst_tau << " N m, floor wrench "
            << worst_floor << "; ZMP floor vs momentum " << worst_zmp << " m; power balance "
            << worst_power << " W\n";
}

// The planner's pendulum: LIP-3D of the planned centre of mass is the planned ZMP (the support
// foot's centre) at every instant, its velocity continuous across support switches.
TEST(BioloidGait, PlannedPendulumHasItsZmpOnTheSupportFoot) {
  const Walk w;
  const double g = -w.solver.instance().gravity[2], h = 1e-6;
  double worst = 0;
  for (const double t : w.times(7)) {
    const V3 c = w.gait.planned_com(t);
    const V3 cp = w.gait.planned_com(t + h), cm = w.gait.planned_com(t - h);
    const V3 acc = (1 / (h * h)) * (cp - 2.0 * c + cm);
    const V3 p = lip_zmp(c, acc, g), target = w.gait.planned_zmp(t);
    worst = std::max({worst, std::abs(p[0] - target[0]), std::abs(p[1] - target[1])});
  }
  EXPECT_LT(worst, 1e-5);
  const double T = w.gait.settings().step_time, e = 1e-7;
  for (int k = 1; k < w.gait.settings().steps; ++k) {
    const V3 v1 = (1 / e) * (w.gait.planned_com(k * T - e) - w.gait.planned_com(k * T - 2 * e));
    const V3 v2 = (1 / e) * (w.gait.planned_com(k * T + 2 * e) - w.gait.planned_com(k * T + e));
    EXPECT_NEAR(v1[0], v2[0], 1e-5);
    EXPECT_NEAR(v1[1], v2[1], 1e-5);
  }
}

// The whole-body centre of mass follows the planned pendulum: positions, velocities and
// accelerations, so that the LIP-3D ZMP of the real centre of mass is the support foot's centre.
TEST(BioloidGait, CentreOfMassFollowsThePendulum) {
  const Walk w;
  const double g = -w.solver.instance().gravity[2], h = 1e-6;
  SpatialState s;
  double worst_p = 0, worst_v = 0, worst_a = 0, worst_zmp = 0;
  for (const double t : w.times(5)) {
    w.solve(t, s);
    const CentreOfMass c = centre_of_mass(w.solver, s);
    const V3 p = w.gait.planned_com(t);
    const V3 v = (1 / (2 * h)) * (w.gait.planned_com(t + h) - w.gait.planned_com(t - h));
    const V3 a = (1 / (h * h)) * (w.gait.planned_com(t + h) - 2.0 * p + w.gait.planned_com(t - h));
    const V3 zmp = lip_zmp(c.p, c.a, g), planned = w.gait.planned_zmp(t);
    for (size_t i = 0; i < 3; ++i) {
      worst_p = std::max(worst_p, std::abs(c.p[i] - p[i]));
      worst_v = std::max(worst_v, std::abs(c.v[i] - v[i]));
      worst_a = std::max(worst_a, std::abs(c.a[i] - a[i]));
    }
    worst_zmp = std::max({worst_zmp, std::abs(zmp[0] - planned[0]), std::abs(zmp[1] - planned[1])});
  }
  EXPECT_LT(worst_p, 1e-12);
  EXPECT_LT(worst_v, 1e-8);
  EXPECT_LT(worst_a, 1e-3);
  EXPECT_LT(worst_zmp, 1e-12);
  std::cout << "centre of mass vs pendulum: " << worst_p << " m, " << worst_v << " m/s (FD), "
            << worst_a << " m/s^2 (FD); LIP ZMP vs planned " << worst_zmp << " m\n";
}

// Each leg's six angles in closed form from the waist's and the foot's poses (the seed solved
// them numerically) equal the solver's Newton closure of the whole-body circuits.
TEST(BioloidGait, ClosedFormLegAnglesEqualTheCircuitClosure) {
  const Walk w;
  std::array<LegGeometry, 2> legs;
  for (size_t side = 0; side < 2; ++side) {
    std::array<std::string, 6> names;
    for (size_t k = 0; k < 6; ++k) names[k] = kLegs[side][k];
    legs[side] = leg_geometry(w.solver, names);
    EXPECT_NEAR(legs[side].thigh, 0.075, 1e-15);
    EXPECT_NEAR(legs[side].calf, 0.075, 1e-15);
  }
  SpatialState s;
  double worst = 0;
  for (const double t : w.times(8)) {
    w.solve(t, s);
    for (size_t side = 0; side < 2; ++side) {
      const LegGeometry& leg = legs[side];
      const std::array<double, 6> q = leg_inverse_kinematics(
          leg, s.D[static_cast<size_t>(leg.waist)], s.D[static_cast<size_t>(leg.foot)]);
      for (size_t k = 0; k < 6; ++k)
        worst = std::max(worst, std::abs(q[k] - s.q[w.column(kLegs[side][k])]));
    }
  }
  EXPECT_LT(worst, 1e-12);
  std::cout << "closed-form leg angles vs circuit closure: " << worst << " rad\n";
  // The reference pose (straight leg) gives zeros; a foot 0.2 m lower is out of reach.
  Pose lower;
  lower.p = {0, 0, -0.2};
  for (const double q : leg_inverse_kinematics(legs[0], Pose{}, Pose{})) EXPECT_NEAR(q, 0, 1e-12);
  EXPECT_THROW(leg_inverse_kinematics(legs[0], Pose{}, lower), ModelError);
  // Another layout is refused.
  EXPECT_THROW(leg_geometry(w.solver, {"RL2", "RL1", "RL3", "RL4", "RL5", "RL6"}), ModelError);
}

TEST(BioloidGait, PolygonMarginIsTheDistanceToTheNearestEdge) {
  const std::vector<V3> square{{0, 0, 0}, {0.1, 0, 0}, {0.1, 0.06, 0}, {0, 0.06, 0}};
  EXPECT_NEAR(polygon_margin(square, {0.05, 0.02, 0}), 0.02, 1e-15);
  std::vector<V3> clockwise(square.rbegin(), square.rend());
  EXPECT_NEAR(polygon_margin(clockwise, {0.09, 0.03, 0}), 0.01, 1e-15);
  EXPECT_NEAR(polygon_margin(square, {0.13, 0.03, 0}), -0.03, 1e-15);
  // The hull of the corners and an inner point is the four corners, counter-clockwise.
  std::vector<V3> pts = clockwise;
  pts.push_back({0.05, 0.03, 0});
  const std::vector<V3> hull = convex_hull_xy(pts);
  ASSERT_EQ(hull.size(), 4u);
  double area = 0;
  for (size_t i = 0; i < 4; ++i)
    area += hull[i][0] * hull[(i + 1) % 4][1] - hull[(i + 1) % 4][0] * hull[i][1];
  EXPECT_NEAR(area / 2, 0.006, 1e-15);
}

// The generated whole-body kernel (bioloid compiled in: four 6R limbs in closed form from the
// virtual chains' poses, Davies' rates through the block-diagonal N_s) driven by the gait's
// primary motion equals the numeric gait: every real joint's angle, velocity and acceleration.
TEST(BioloidGait, GeneratedWholeBodyKernelEqualsTheNumericGait) {
  const Walk w;
  const CompiledKernel* kernel = find_compiled_kernel("bioloid");
  ASSERT_NE(kernel, nullptr);
  const std::vector<std::string> columns = spatial_column_names(w.model);
  auto at = [&](const std::string& name) {
    const auto it = std::find(columns.begin(), columns.end(), name);
    EXPECT_NE(it, columns.end()) << name;
    return static_cast<size_t>(it - columns.begin());
  };
  // The kernel's inputs: joint drivers, then each pose driver's prescribed coordinates (absolute
  // values: the virtual coordinate plus its reference), in the sweep's driver column order.
  std::vector<std::pair<std::string, int>> inputs;  // column prefix, graph column
  const SpatialGraph& g = w.solver.graph();
  for (const SpatialDriver& d : w.model.drivers)
    inputs.emplace_back(d.name, g.joint_column[static_cast<size_t>(d.joint)] + d.column);
  for (const PoseDriver& pd : w.model.pose_drivers)
    for (const PoseCoordinate& pc : pd.coordinates)
      if (pc.value)
        inputs.emplace_back(pd.name + "." + pc.name, g.joint_column[static_cast<size_t>(pc.joint)]);
  ASSERT_EQ(static_cast<int>(inputs.size()), kernel->driver_count);
  // The references, from the model's own motion at t0: absolute (kernel) minus coordinate.
  const std::vector<double> parameters = w.model.common.default_parameters();
  std::vector<double> row(columns.size());
  int group = -1;
  SpatialState s;
  w.solver.solve(0, s);
  ASSERT_EQ(kernel->evaluate_double(parameters.data(), 0, row.data(), &group), 0);
  std::vector<double> reference;
  for (const auto& [prefix, c] : inputs) reference.push_back(row[at(prefix + ".q")] - s.q[c]);
  double worst_q = 0, worst_qd = 0, worst_qdd = 0;
  for (const double t : w.times(8)) {
    w.solve(t, s);
    std::vector<double> drivers;
    for (size_t i = 0; i < inputs.size(); ++i) {
      const int c = inputs[i].second;
      drivers.insert(drivers.end(), {s.q[c] + reference[i], s.qd[c], s.qdd[c]});
    }
    ASSERT_EQ(
        kernel->evaluate_driven_double(parameters.data(), t, drivers.data(), row.data(), &group), 0)
        << t;
    for (const SpatialJoint& j : w.model.joints) {
      if (j.is_virtual || j.columns.size() != 1) continue;
      const int c = g.joint_column[static_cast<size_t>(w.model.joint_index(j.name))];
      worst_q = std::max(worst_q, std::abs(row[at(j.name + ".q")] - s.q[c]));
      worst_qd = std::max(worst_qd, std::abs(row[at(j.name + ".qd")] - s.qd[c]));
      worst_qdd = std::max(worst_qdd, std::abs(row[at(j.name + ".qdd")] - s.qdd[c]));
    }
  }
  EXPECT_LT(worst_q, 1e-9);
  EXPECT_LT(worst_qd, 1e-9);
  EXPECT_LT(worst_qdd, 1e-8);
  std::cout << "gait through the generated bioloid kernel against the numeric gait: q " << worst_q
            << ", q' " << worst_qd << ", q'' " << worst_qdd << "\n";
}

}  // namespace
}  // namespace mechgen::spatial
