// Seed 002's hybrid serial-parallel quadruped leg (issue 12) on the numeric spatial solver:
// the seed's own formulas for theta1, theta2, theta10 and the foot, written out here, against the
// solved model over the stroke box; the corrected global mapping (the seed's printed Y_D, Z_D put
// x_D where z_D belongs); inverse kinematics through the foot pose driver, IK(FK(l)) = l; the
// foot Jacobian against the seed's J = J1 J3^-1 J2^-1; foot force -> cylinder forces through J^T
// against Newton-Euler statics; the seed's swing: cylinder rates against J^-1 X'.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "analysis/follow.hpp"
#include "analysis/workspace.hpp"
#include "quadruped_seed.hpp"
#include "spatial/driven_solve.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

const std::string kLeg = std::string(MECHGEN_SOURCE_DIR) + "/models/quadruped_leg.yaml";
const std::string kSwing = std::string(MECHGEN_SOURCE_DIR) + "/models/quadruped_leg_swing.yaml";

// The primary position of each driver (by name) or pose coordinate, in graph().primary order.
int primary_index(const SpatialSolver& s, const std::string& driver) {
  const SpatialGraph& g = s.graph();
  for (size_t k = 0; k < g.primary.size(); ++k) {
    const SpatialColumn& col = g.columns[static_cast<size_t>(g.primary[k])];
    if (col.driver >= 0 && s.model().drivers[static_cast<size_t>(col.driver)].name == driver)
      return static_cast<int>(k);
    if (col.pose_driver >= 0 && "foot." + s.model()
                                              .pose_drivers[static_cast<size_t>(col.pose_driver)]
                                              .coordinates[static_cast<size_t>(col.pose_coordinate)]
                                              .name ==
                                    driver)
      return static_cast<int>(k);
  }
  ADD_FAILURE() << "no primary " << driver;
  return 0;
}

V3 point(const SpatialSolver& s, const SpatialState& st, const std::string& body,
         const std::string& name) {
  const int b = s.model().body_index(body);
  const SpatialBody& sb = s.model().bodies[static_cast<size_t>(b)];
  for (size_t k = 0; k < sb.points.size(); ++k)
    if (sb.points[k].name == name)
      return s.point_position(st, b, s.instance().points[static_cast<size_t>(b)][k]);
  ADD_FAILURE() << "no point " << name;
  return {};
}

Eigen::Vector3d E(const V3& v) {
  return {v[0], v[1], v[2]};
}

double dist(const V3& p, const V3& q) {
  return (E(p) - E(q)).norm();
}

// The FK model at cylinder lengths l from the model's t0 state (one Newton run per target).
struct Leg {
  SpatialModel model = read_spatial_model(kLeg);
  SpatialSolver solver{model, {}};
  Seed seed{model};
  SpatialState start;
  Leg() { solver.solve(0, start); }
  SpatialState at(const Eigen::Vector3d& l) const {
    SpatialState st = start;
    const Eigen::Vector3d q = l - seed.reference_lengths();
    Eigen::VectorXd qp(3);
    qp[primary_index(solver, "l1")] = q[0];
    qp[primary_index(solver, "l2")] = q[1];
    qp[primary_index(solver, "l3")] = q[2];
    solve_at(solver, qp, Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(3), st);
    return st;
  }
  Eigen::Vector3d lengths(const SpatialState& st) const {
    return {dist(point(solver, st, "barrel1", "H"), point(solver, st, "rod1", "G")),
            dist(point(solver, st, "barrel2", "F"), point(solver, st, "rod2", "C")),
            dist(point(solver, st, "barrel3", "M"), point(solver, st, "rod3", "N"))};
  }
};

std::vector<Eigen::Vector3d> stroke_grid(int n) {
  std::vector<Eigen::Vector3d> out;
  for (int u = 0; u < n; ++u)
    for (int v = 0; v < n; ++v)
      for (int w = 0; w < n; ++w)
        out.push_back(
            {0.35 + 0.15 * u / (n - 1), 0.35 + 0.15 * v / (n - 1), 0.28 + 0.06 * w / (n - 1)});
  return out;
}

TEST(QuadrupedLeg, DriverRangesAreTheSeedStrokes) {
  const Leg leg;
  const Eigen::Vector3d ref = leg.seed.reference_lengths();
  const GiNaC::exmap subs = leg.model.common.substitutions(leg.solver.parameters());
  const double lo[3] = {0.35, 0.35, 0.28}, hi[3] = {0.5, 0.5, 0.34};
  for (int k = 0; k < 3; ++k) {
    const SpatialDriver& d = leg.model.drivers[static_cast<size_t>(k)];
    ASSERT_TRUE(d.range);
    EXPECT_NEAR(leg.model.evaluate(d.range->at(0), subs) + ref[k], lo[k], 1e-15) << d.name;
    EXPECT_NEAR(leg.model.evaluate(d.range->at(1), subs) + ref[k], hi[k], 1e-15) << d.name;
  }
  // The reference lengths are the reference pose's pin distances.
  SpatialState st;
  st.q = Eigen::VectorXd::Zero(leg.solver.graph().cols());
  leg.solver.place(st);
  EXPECT_LT((leg.lengths(st) - ref).norm(), 1e-15);
}

TEST(QuadrupedLeg, SeedFormulasHoldOverTheStrokeBox) {
  const Leg leg;
  int count = 0;
  for (const Eigen::Vector3d& l : stroke_grid(5)) {
    const SpatialState st = leg.at(l);
    ++count;
    EXPECT_LT((leg.lengths(st) - l).norm(), 1e-12);
    // theta1, theta1 + theta2 from the solved thigh and lower link, in the swing frame.
    const Pose frame = leg.solver.body_pose(st, leg.model.body_index("frame"));
    auto local = [&](const V3& x) {
      const V3 p = geometry::apply(geometry::inverse(frame), x);
      return Eigen::Vector2d(p[0], p[2]);
    };
    const Eigen::Vector2d Q = local(point(leg.solver, st, "thigh", "Q"));
    const Eigen::Vector2d A = local(point(leg.solver, st, "thigh", "A"));
    const Eigen::Vector2d D = local(point(leg.solver, st, "shank", "D"));
    const double t1 = std::atan2(A[1] - Q[1], A[0] - Q[0]);
    const double t12 = std::atan2(D[1] - A[1], D[0] - A[0]);
    const double s1 = leg.seed.theta1(l[0]), s2 = leg.seed.theta2(l[0], l[1]);
    EXPECT_NEAR(std::remainder(t1 - s1, 2 * M_PI), 0, 1e-12);
    EXPECT_NEAR(std::remainder(t12 - t1 - s2, 2 * M_PI), 0, 1e-12);
    // theta2 stays off the parallelogram's change points (0, pi) by more than 20 deg.
    const double t2 = std::remainder(s2, 2 * M_PI);
    EXPECT_GT(t2, 20 * M_PI / 180);
    EXPECT_LT(t2, 160 * M_PI / 180);
    // theta10: the swing frame's rotation about X.
    EXPECT_NEAR(std::atan2(frame.R(2, 1), frame.R(1, 1)), leg.seed.theta10(l[2]), 1e-12);
    // The foot: the seed's x_D, z_D and the correct global mapping.
    EXPECT_NEAR(D[0], leg.seed.xD(s1, s2), 1e-12);
    EXPECT_NEAR(D[1], leg.seed.zD(s1, s2), 1e-12);
    const Eigen::Vector3d foot = E(point(leg.solver, st, "shank", "D"));
    EXPECT_LT((foot - leg.seed.foot(l)).norm(), 1e-12);
    // The seed's printed Y_D = -x_D sin theta10, Z_D = x_D cos theta10 is not the foot.
    const double x = leg.seed.xD(s1, s2), t10 = leg.seed.theta10(l[2]);
    EXPECT_GT(std::hypot(foot[1] + x * std::sin(t10), foot[2] - x * std::cos(t10)), 0.1);
  }
  EXPECT_EQ(count, 125);
}

TEST(QuadrupedLeg, EveryCornerOfTheStrokeBoxAssemblesFromTheDefaultStart) {
  const Leg leg;
  for (const Eigen::Vector3d& l : stroke_grid(2)) {
    const SpatialState st = leg.at(l);
    EXPECT_LT((leg.lengths(st) - l).norm(), 1e-12);
    EXPECT_LT((leg.solver.network(st) * st.qd).norm(), 1e-14);
  }
}

// The IK model: the same bodies and joints, the foot on a pose driver.
struct Ik {
  SpatialModel model = read_spatial_model(kSwing);
  SpatialSolver solver{model, {}};
  SpatialState start;
  Eigen::Vector3d reference;  // D at the reference pose
  Ik() {
    solver.solve(0, start);
    SpatialState zero;
    zero.q = Eigen::VectorXd::Zero(solver.graph().cols());
    solver.place(zero);
    reference = E(point(solver, zero, "shank", "D"));
  }
  SpatialState at(const Eigen::Vector3d& foot, const Eigen::Vector3d& v = {0, 0, 0},
                  const Eigen::Vector3d& acc = {0, 0, 0}) const {
    SpatialState st = start;
    Eigen::VectorXd qp(3), qpd(3), qpdd(3);
    const char* names[3] = {"foot.x", "foot.y", "foot.z"};
    for (int k = 0; k < 3; ++k) {
      const int p = primary_index(solver, names[k]);
      qp[p] = foot[k] - reference[k], qpd[p] = v[k], qpdd[p] = acc[k];
    }
    solve_at(solver, qp, qpd, qpdd, st, 0.02);
    return st;
  }
  Eigen::Vector3d cylinders(const SpatialState& st, int which) const {  // q, qd or qdd
    Eigen::Vector3d out;
    const char* names[3] = {"cyl1", "cyl2", "cyl3"};
    for (int k = 0; k < 3; ++k) {
      const int c = solver.graph().joint_column[static_cast<size_t>(model.joint_index(names[k]))];
      out[k] = which == 0 ? st.q[c] : which == 1 ? st.qd[c] : st.qdd[c];
    }
    return out;
  }
};

TEST(QuadrupedLeg, SwingModelHasTheSameBodiesAndJoints) {
  auto section = [](const std::string& text) {
    return text.substr(text.find("\nbodies:"), text.find("\ndrivers:") - text.find("\nbodies:"));
  };
  EXPECT_EQ(section(read_text(kLeg)), section(read_text(kSwing)));
}

TEST(QuadrupedLeg, InverseOfForwardIsIdentityOverTheStrokeBox) {
  const Leg leg;
  const Ik ik;
  const Eigen::Vector3d ref = leg.seed.reference_lengths();
  double worst = 0;
  for (const Eigen::Vector3d& l : stroke_grid(5)) {
    const Eigen::Vector3d foot = E(point(leg.solver, leg.at(l), "shank", "D"));
    const SpatialState st = ik.at(foot);
    worst = std::max(worst, (ik.cylinders(st, 0) + ref - l).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-12);
}

// The closed-form inverse the seed outlines: theta10 from the lateral plane, then the planar
// two-link part (thigh b, lower link a + c from Q) analytically, then the seed's l1, l2, l3
// formulas. With the foot below the hip (z_D < 0) the seed's theta10 = atan2(-Y_D, Z_D) is off by
// pi: theta10 = atan2(Y_D, -Z_D), z_D = -sqrt(Y_D^2 + Z_D^2).
Eigen::Vector3d closed_form_ik(const Seed& s, const Eigen::Vector3d& D) {
  const double t10 = std::atan2(D[1], -D[2]);
  const double x = D[0], z = -std::hypot(D[1], D[2]) + s.h;  // relative to Q
  const double L = s.a + s.c;
  const double t2 = std::acos((x * x + z * z - s.b * s.b - L * L) / (2 * s.b * L));  // > 0 branch
  const double t1 = std::atan2(z, x) - std::atan2(L * std::sin(t2), s.b + L * std::cos(t2));
  const double t3 = t1 - s.th5, t4 = 2 * M_PI - t1 - t2;
  return {std::sqrt(s.f * s.f + s.d * s.d - 2 * s.f * s.d * std::cos(t3 - s.th8)),
          std::sqrt(s.a * s.a + s.e * s.e - 2 * s.a * s.e * std::cos(t4 + s.th7)),
          std::sqrt(s.i * s.i + s.j * s.j - 2 * s.i * s.j * std::cos(t10 - s.th11 + M_PI / 2))};
}

TEST(QuadrupedLeg, ClosedFormInverseEqualsTheSolversOverTheStrokeBox) {
  const Leg leg;
  const Ik ik;
  const Eigen::Vector3d ref = leg.seed.reference_lengths();
  for (const Eigen::Vector3d& l : stroke_grid(4)) {
    const Eigen::Vector3d foot = E(point(leg.solver, leg.at(l), "shank", "D"));
    EXPECT_LT((closed_form_ik(leg.seed, foot) - l).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT(
        (ik.cylinders(ik.at(foot), 0) + ref - closed_form_ik(leg.seed, foot)).cwiseAbs().maxCoeff(),
        1e-12);
    // The seed's printed theta10 = atan2(-Y_D, Z_D) is the supplement here.
    EXPECT_NEAR(
        std::abs(std::remainder(std::atan2(-foot[1], foot[2]) - leg.seed.theta10(l[2]), 2 * M_PI)),
        M_PI, 1e-12);
  }
}

TEST(QuadrupedLeg, JacobianIsTheSeedsProductAndForcesMapThroughItsTranspose) {
  // Statics: only the foot carries a mass (a point mass at D), every other body massless; the
  // gravity vector is turned so the foot force has all three components.
  std::string text = read_text(kLeg);
  auto replace = [&](const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  replace("gravity: [0, 0, -9.81]", "gravity: [3, -4, -9]");
  replace("mass: {bar: [A, D], radius: r, density: rho}",
          "mass: {mass: 2, com: [a + c, 0, 0], inertia: [0, 0, 0]}");
  for (const char* p : {"rho: {value: 2700", "m_frame: {value: 1.5", "m_barrel: {value: 0.8",
                        "m_rod: {value: 0.25"}) {
    const std::string from(p);
    replace(from, from.substr(0, from.find("value: ") + 7) + "0");
  }
  replace("inertia: [0.01, 0.01, 0.01]", "inertia: [0, 0, 0]");
  for (int k = 0; k < 3; ++k) replace("inertia: [1e-3, 1e-3, 1e-3]", "inertia: [0, 0, 0]");
  for (int k = 0; k < 3; ++k) replace("inertia: [1e-4, 1e-4, 1e-4]", "inertia: [0, 0, 0]");
  ASSERT_EQ(text.find("rho: {value: 2700"), std::string::npos);
  const SpatialModel model = read_spatial_model_text(text, "quadruped_statics.yaml");
  const SpatialSolver solver(model, {});
  const Seed seed(model);
  SpatialState start;
  solver.solve(0, start);
  const Eigen::Vector3d force(2 * 3.0, 2 * -4.0, 2 * -9.0);
  const int shank = model.body_index("shank");
  for (const Eigen::Vector3d& l : stroke_grid(3)) {
    SpatialState st = start;
    Eigen::VectorXd qp(3);
    const Eigen::Vector3d q = l - seed.reference_lengths();
    for (int k = 0; k < 3; ++k) qp[primary_index(solver, std::string("l") + char('1' + k))] = q[k];
    solve_at(solver, qp, Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(3), st);
    const V3 D = point(solver, st, "shank", "D");
    const Eigen::MatrixXd Js = solver.point_jacobian(st, shank, D);
    Eigen::Matrix3d J;  // columns l1, l2, l3
    for (int k = 0; k < 3; ++k)
      J.col(k) = Js.col(primary_index(solver, std::string("l") + char('1' + k)));
    const Eigen::Matrix3d Jseed = seed.jacobian(l);
    EXPECT_LT((J - Jseed).norm(), 1e-9 * Jseed.norm());
    // The seed's J1 as printed (x_D in the theta10 column) is a different matrix.
    EXPECT_GT((seed.jacobian(l, true) - J).norm(), 1e-2 * Jseed.norm());
    // Static equilibrium: cylinder forces + J^T F = 0.
    const SpatialLoads loads = inverse_dynamics(solver, st);
    Eigen::Vector3d effort;
    for (int k = 0; k < 3; ++k)
      effort[k] = loads.effort[primary_index(solver, std::string("l") + char('1' + k))];
    const Eigen::Vector3d expected = -Jseed.transpose() * force;
    EXPECT_LT((effort - expected).norm(), 1e-9 * expected.norm());
  }
}

TEST(QuadrupedLeg, SwingCylinderRatesAreTheInverseJacobianOfTheFootVelocity) {
  const Ik ik;
  const Seed seed(ik.model);
  const Swing sw{param(ik.model, "S"),  param(ik.model, "H"),  param(ik.model, "T"),
                 param(ik.model, "x0"), param(ik.model, "Y0"), param(ik.model, "z0")};
  const Eigen::Vector3d ref = seed.reference_lengths();
  SpatialState st;
  double lo[3] = {1, 1, 1}, hi[3] = {0, 0, 0}, worst_rate = 0, worst_acc = 0, t_exit = -1;
  const int n = 200;
  for (int k = 0; k <= n; ++k) {
    const double t = sw.T * k / n;
    ik.solver.solve(t, st);
    const Eigen::Vector3d l = ik.cylinders(st, 0) + ref;
    // The foot follows the law; the solver's rates equal J^-1 X'.
    EXPECT_LT((E(point(ik.solver, st, "shank", "D")) - sw.x(t)).norm(), 1e-12);
    const Eigen::Matrix3d J = seed.jacobian(l);
    const Eigen::Vector3d ld = J.inverse() * sw.v(t);
    worst_rate = std::max(worst_rate, (ik.cylinders(st, 1) - ld).cwiseAbs().maxCoeff());
    // Accelerations: central differences of the exact rates.
    if (k > 0 && k < n) {
      const double dt = 1e-5;
      const Eigen::Vector3d up = ik.cylinders(ik.at(sw.x(t + dt), sw.v(t + dt)), 1);
      const Eigen::Vector3d down = ik.cylinders(ik.at(sw.x(t - dt), sw.v(t - dt)), 1);
      const Eigen::Vector3d fd = (up - down) / (2 * dt);
      worst_acc = std::max(worst_acc, (ik.cylinders(st, 2) - fd).cwiseAbs().maxCoeff());
    }
    for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], l[c]), hi[c] = std::max(hi[c], l[c]);
    if (t_exit < 0 && (l[0] < 0.35 || l[1] < 0.35 || l[0] > 0.5 || l[1] > 0.5)) t_exit = t;
  }
  EXPECT_LT(worst_rate, 1e-9);
  EXPECT_LT(worst_acc, 1e-6);
  std::printf(
      "seed swing S = %.3f H = %.3f: l1 in [%.4f, %.4f], l2 in [%.4f, %.4f], l3 in "
      "[%.4f, %.4f] m; leaves the strokes first at t = %.3f s; rates vs J^-1 X' %.2e m/s, "
      "accelerations vs central differences %.2e m/s^2\n",
      sw.S, sw.H, lo[0], hi[0], lo[1], hi[1], lo[2], hi[2], t_exit, worst_rate, worst_acc);
  // The seed's H = 0.3 m lift needs cylinder 1 shorter than its 350 mm stroke end.
  EXPECT_LT(lo[0], 0.35);
}

}  // namespace
}  // namespace mechgen::spatial

namespace mechgen::analysis {
namespace {

TEST(QuadrupedWorkspace, MonteCarloExtentsMatchTheSeedFormulasAndDoNotDependOnThreads) {
  const SpatialModel model = read_spatial_model(spatial::kLeg);
  const spatial::Seed seed(model);
  // The extents from the seed's formulas on a fine grid of the stroke box (X and Z: theta10 only
  // turns the leg plane, X does not depend on it).
  std::array<double, 3> lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
  const int n = 61;
  for (int u = 0; u < n; ++u)
    for (int v = 0; v < n; ++v)
      for (int w = 0; w < 7; ++w) {
        const Eigen::Vector3d x =
            seed.foot({0.35 + 0.15 * u / (n - 1), 0.35 + 0.15 * v / (n - 1), 0.28 + 0.06 * w / 6});
        for (size_t c = 0; c < 3; ++c)
          lo[c] = std::min(lo[c], x[static_cast<Eigen::Index>(c)]),
          hi[c] = std::max(hi[c], x[static_cast<Eigen::Index>(c)]);
      }
  WorkspaceOptions o;
  o.samples = 4000;
  o.threads = 1;
  const WorkspaceResult one = run_workspace(model, o);
  o.threads = 2;
  const WorkspaceResult two = run_workspace(model, o);
  EXPECT_EQ(one.point, "D");
  EXPECT_EQ(one.assembled, 4000);
  for (size_t c = 0; c < 3; ++c) {
    EXPECT_EQ(one.lo[c], two.lo[c]);
    EXPECT_EQ(one.hi[c], two.hi[c]);
    // Inside the grid's extents (to the grid's own resolution) and close to them.
    EXPECT_GT(one.lo[c], lo[c] - 2e-3);
    EXPECT_LT(one.hi[c], hi[c] + 2e-3);
    EXPECT_LT(one.lo[c], lo[c] + 0.03);
    EXPECT_GT(one.hi[c], hi[c] - 0.03);
  }
  long total = 0;
  for (const long k : one.sagittal.counts) total += k;
  EXPECT_EQ(total, 4000);
  // A driver held fixed: l3 = 0 is theta10 = 0, the leg's own plane (Y = 0).
  o.fixed = {{"l3", 0.0}};
  const WorkspaceResult plane = run_workspace(model, o);
  EXPECT_LT(std::max(std::abs(plane.lo[1]), std::abs(plane.hi[1])), 1e-15);
  EXPECT_NE(density_svg(one.sagittal, "t").find("<svg"), std::string::npos);
  // That plane seen from the front is a line: the image keeps a fifth of its height as width and
  // the canvas fits the title (before: 103 x 660 px, the title clipped), with a viewBox.
  EXPECT_GE(plane.frontal.nh * 5, plane.frontal.nv);
  const std::string title = "quadruped_leg: point foot, frontal projection (Y-Z), 4000 samples";
  const std::string svg = density_svg(plane.frontal, title);
  const double width = std::stod(svg.substr(svg.find("width=\"") + 7));
  const double height = std::stod(svg.substr(svg.find("height=\"") + 8));
  EXPECT_GE(width, 70 + 8.0 * static_cast<double>(title.size()));
  EXPECT_GE(width, 0.2 * height);
  std::ostringstream box;
  box << "viewBox=\"0 0 " << width << " " << height << "\"";
  EXPECT_NE(svg.find(box.str()), std::string::npos) << svg.substr(0, 200);

  // A colour scale from 1 sample to the densest cell's count, and the mechanism over the image
  // where its points are: (h, v) at left + (h - h_min) / cell * scale, top + height - ...
  const Projection& p = one.sagittal;
  long most = 0;
  for (const long k : p.counts) most = std::max(most, k);
  const Outline outline{{{{p.h_min + 10 * p.cell, 0.0, p.v_min + 20 * p.cell},
                          {p.h_min + 30 * p.cell, 0.0, p.v_min + 5 * p.cell}}},
                        "at its reference pose, t = 0 s"};
  const std::string drawn = density_svg(p, "t", outline);
  const size_t bar = drawn.find("<g class=\"colour-scale\">");
  ASSERT_NE(bar, std::string::npos);
  EXPECT_NE(drawn.find(">" + std::to_string(most) + "</text>", bar), std::string::npos);
  EXPECT_NE(drawn.find(">1</text>", bar), std::string::npos);
  EXPECT_NE(drawn.find("grey: the mechanism at its reference pose, t = 0 s"), std::string::npos);
  const size_t at = drawn.find("points=\"", drawn.find("<g class=\"outline\""));
  ASSERT_NE(at, std::string::npos);
  std::istringstream points(drawn.substr(at + 8, drawn.find('"', at + 8) - at - 8));
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  char comma = 0;
  points >> x0 >> comma >> y0 >> x1 >> comma >> y1;
  const double scale = 560.0 / std::max(p.nh, p.nv), left = 70, top = 40;
  EXPECT_NEAR(x0, left + 10 * scale, 1e-6);
  EXPECT_NEAR(y0, top + (p.nv - 20) * scale, 1e-6);
  EXPECT_NEAR(x1, left + 30 * scale, 1e-6);
  EXPECT_NEAR(y1, top + (p.nv - 5) * scale, 1e-6);
}

TEST(QuadrupedWorkspace, CylinderForcesAlongTheSwingAreJTransposeOfTheFootForce) {
  // Route 1: the actuated leg following the swing (follow). Route 2: the pose-driven leg's own
  // Newton-Euler gives the force its foot driver needs; the cylinders realising the same motion
  // carry J^T of it (virtual power, J = the seed's product at the solved lengths).
  const SpatialModel driven = read_spatial_model(spatial::kSwing);
  const SpatialModel twin = read_spatial_model(spatial::kLeg);
  FollowOptions o;
  o.samples = 41;
  const FollowResult r = follow(driven, twin, o);
  ASSERT_EQ(r.rows.size(), 41U);
  ASSERT_EQ(r.columns[4], "l1.effort");
  const spatial::Seed seed(twin);
  const spatial::SpatialSolver ik(driven, {});
  const Eigen::Vector3d ref = seed.reference_lengths();
  spatial::SpatialState s;
  double peak[3] = {0, 0, 0}, worst = 0;
  for (const auto& row : r.rows) {
    ik.solve(row[0], s);
    const spatial::SpatialLoads loads = spatial::inverse_dynamics(ik, s);
    Eigen::Vector3d foot_force;
    for (int k = 0; k < 3; ++k)
      foot_force[k] = loads.effort[spatial::primary_index(ik, std::string("foot.") + "xyz"[k])];
    const Eigen::Vector3d l(row[1] + ref[0], row[5] + ref[1], row[9] + ref[2]);
    const Eigen::Vector3d expected = seed.jacobian(l).transpose() * foot_force;
    const Eigen::Vector3d effort(row[4], row[8], row[12]);
    worst = std::max(worst, (effort - expected).norm() / std::max(1.0, expected.norm()));
    for (int k = 0; k < 3; ++k) peak[k] = std::max(peak[k], std::abs(effort[k]));
  }
  EXPECT_LT(worst, 1e-9);
  std::printf(
      "swing cylinder forces (stated masses): peak |F1| %.1f N, |F2| %.1f N, |F3| %.2e N; "
      "vs J^T F_foot %.1e (relative)\n",
      peak[0], peak[1], peak[2], worst);
}

// Does the swing (S, H) at the model's stance point keep every cylinder inside its stroke?
bool inside_strokes(const SpatialModel& m, double S, double H, double* first_exit = nullptr) {
  std::vector<double> p = m.common.default_parameters();
  for (size_t k = 0; k < p.size(); ++k) {
    if (m.common.parameters[k].name == "S") p[k] = S;
    if (m.common.parameters[k].name == "H") p[k] = H;
  }
  const spatial::SpatialSolver ik(m, p);
  const Eigen::Vector3d ref = spatial::Seed(m).reference_lengths();
  const double lo[3] = {0.35, 0.35, 0.28}, hi[3] = {0.5, 0.5, 0.34};
  const char* names[3] = {"cyl1", "cyl2", "cyl3"};
  spatial::SpatialState s;
  const double T = spatial::param(m, "T");
  for (int k = 0; k <= 100; ++k) {
    ik.solve(T * k / 100, s);
    for (int c = 0; c < 3; ++c) {
      const double l =
          s.q[ik.graph().joint_column[static_cast<size_t>(m.joint_index(names[c]))]] + ref[c];
      if (l < lo[c] || l > hi[c]) {
        if (first_exit) *first_exit = T * k / 100;
        return false;
      }
    }
  }
  return true;
}

TEST(QuadrupedWorkspace, NearestFeasibleSwing) {
  const SpatialModel m = read_spatial_model(spatial::kSwing);
  double exit_t = -1;
  EXPECT_FALSE(inside_strokes(m, 0.5, 0.3, &exit_t));
  // Largest H at S = 0.5 and largest S at H = 0.3 (bisection to 1 mm), each checked on both sides.
  auto largest = [&](bool vary_h) {
    double ok = 0.0, bad = vary_h ? 0.3 : 0.5;
    while (bad - ok > 1e-3) {
      const double mid = (ok + bad) / 2;
      (vary_h ? inside_strokes(m, 0.5, mid) : inside_strokes(m, mid, 0.3)) ? ok = mid : bad = mid;
    }
    return ok;
  };
  const double H = largest(true), S = largest(false);
  EXPECT_TRUE(inside_strokes(m, 0.5, H));
  EXPECT_FALSE(inside_strokes(m, 0.5, H + 2e-3));
  std::printf(
      "seed swing S = 0.5, H = 0.3 leaves the strokes at t = %.2f s; feasible at this "
      "stance: H <= %.3f m with S = 0.5 m, S <= %.3f m with H = 0.3 m\n",
      exit_t, H, S);
}

}  // namespace
}  // namespace mechgen::analysis
