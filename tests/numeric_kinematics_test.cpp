// The reference solver's positions, velocities and accelerations against hand-derived closed forms:
// a four-bar (circle intersection, differentiated by hand) and the classic slider-crank.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "numeric/reference_solver.hpp"
#include "numeric_test_support.hpp"

namespace mechgen::numeric {
namespace {

using Eigen::Vector2d;
using testing::Columns;

Vector2d perp(const Vector2d& v) {
  return {-v.y(), v.x()};
}

// Angle of a vector u(t) and its first two time derivatives, by hand:
// th = atan2(uy, ux), th' = (ux uy' - uy ux') / |u|^2,
// th'' = (ux uy'' - uy ux'') / |u|^2 - 2 th' (u.u') / |u|^2.
struct Angle {
  double th, w, al;
};
Angle angle_of(const Vector2d& u, const Vector2d& ud, const Vector2d& udd) {
  const double n2 = u.squaredNorm();
  const double w = (u.x() * ud.y() - u.y() * ud.x()) / n2;
  const double al = (u.x() * udd.y() - u.y() * udd.x()) / n2 - 2 * w * u.dot(ud) / n2;
  return {std::atan2(u.y(), u.x()), w, al};
}

// ------------------------------------------------------------------------------------------------
// Four-bar: ground O2 = (0, 0), O4 = (d, 0); crank O2-P (a), coupler P-Q (b), rocker O4-Q (c).
// Driver: crank angle th = th0 + w t + e sin(2 t) (non-uniform, so alpha != 0).
constexpr double fa = 0.1, fb = 0.35, fc = 0.3, fd = 0.4, fth0 = 0.4, fw = 3, fe = 0.3;
// Coupler centre of mass off its axis; rocker centre of mass at 0.4 c on its axis.
constexpr double coupler_cx = 0.175, coupler_cy = 0.02, rocker_cx = 0.12;

const char* const four_bar_yaml = R"(
name: fourbar
parameters:
  a: 0.1
  b: 0.35
  c: 0.3
  d: 0.4
  th0: 0.4
  w: 3
  e: 0.3
bodies:
  - name: ground
    ground: true
    points: {O2: [0, 0], O4: [d, 0]}
  - name: crank
    points: {O2: [0, 0], P: [a, 0]}
    mass: {mass: 0.2, com: [a/2, 0], inertia: 2e-4}
    assembly: th0
  - name: coupler
    points: {P: [0, 0], Q: [b, 0]}
    mass: {mass: 0.5, com: [b/2, 0.02], inertia: 6e-3}
    assembly: 0.81
  - name: rocker
    points: {O4: [0, 0], Q: [c, 0]}
    mass: {mass: 0.4, com: [0.4*c, 0], inertia: 4e-3}
    assembly: 1.8
joints:
  - {name: jO2, type: revolute, first: ground, second: crank, point: O2}
  - {name: jP, type: revolute, first: crank, second: coupler, point: P}
  - {name: jQ, type: revolute, first: coupler, second: rocker, point: Q}
  - {name: jO4, type: revolute, first: ground, second: rocker, point: O4}
drivers:
  - {name: theta, joint: jO2, kind: angle, value: th0 + w*t + e*sin(2*t)}
step: {t0: 0, t1: 3, samples: 121}
)";

struct FourBarExpected {
  Vector2d p, pd, pdd;  // crank pin P
  Vector2d q, qd, qdd;  // coupler-rocker pin Q
};

// Q from the intersection of the circles |Q - P| = b and |Q - O4| = c, on the side of +perp(O4 -
// P):
//   e = O4 - P, s = |e|, f = e / s, x = (b^2 - c^2 + s^2) / (2 s), h = sqrt(b^2 - x^2),
//   Q = P + x f + h perp(f),
// and its derivatives by the chain rule through s, f, x and h.
FourBarExpected four_bar_closed_form(double t) {
  const double th = fth0 + fw * t + fe * std::sin(2 * t);
  const double thd = fw + 2 * fe * std::cos(2 * t);
  const double thdd = -4 * fe * std::sin(2 * t);
  FourBarExpected out;
  const Vector2d u(std::cos(th), std::sin(th));
  out.p = fa * u;
  out.pd = fa * thd * perp(u);
  out.pdd = fa * (thdd * perp(u) - thd * thd * u);
  const Vector2d e = Vector2d(fd, 0) - out.p, ed = -out.pd, edd = -out.pdd;
  const double s = e.norm();
  const double sd = e.dot(ed) / s;
  const double sdd = (ed.dot(ed) + e.dot(edd) - sd * sd) / s;
  const Vector2d f = e / s;
  const Vector2d fd_ = (ed - f * sd) / s;
  const Vector2d fdd = (edd - 2 * fd_ * sd - f * sdd) / s;
  const double k = fb * fb - fc * fc;
  const double x = k / (2 * s) + s / 2;
  const double xd = -k * sd / (2 * s * s) + sd / 2;
  const double xdd = -k / 2 * (sdd / (s * s) - 2 * sd * sd / (s * s * s)) + sdd / 2;
  const double h = std::sqrt(fb * fb - x * x);
  const double hd = -x * xd / h;
  const double hdd = -(xd * xd + x * xdd + hd * hd) / h;
  out.q = out.p + x * f + h * perp(f);
  out.qd = out.pd + xd * f + x * fd_ + hd * perp(f) + h * perp(fd_);
  out.qdd = out.pdd + xdd * f + 2 * xd * fd_ + x * fdd + hdd * perp(f) + 2 * hd * perp(fd_) +
            h * perp(fdd);
  return out;
}

// A point fixed in a body with origin o(t) and angle th(t), at local coordinates c.
void body_point(const Vector2d& o, const Vector2d& od, const Vector2d& odd, const Angle& a,
                const Vector2d& c, Vector2d& p, Vector2d& v, Vector2d& acc) {
  const Vector2d rc = Eigen::Rotation2Dd(a.th) * c;
  p = o + rc;
  v = od + a.w * perp(rc);
  acc = odd + a.al * perp(rc) - a.w * a.w * rc;
}

struct MaxError {
  double value = 0;
  std::string where;
  void update(double got, double want, double scale, const std::string& name) {
    const double err = std::abs(got - want) / scale;
    if (!(err <= value)) {
      value = err;
      where = name;
    }
  }
};

TEST(ReferenceSolverKinematics, FourBarMatchesCircleIntersection) {
  const Model model = read_model_text(four_bar_yaml, "fourbar.yaml");
  ReferenceSolver solver(model, model.default_parameters());
  solver.assemble(0);
  const Columns col(model);
  std::vector<double> row;
  // Scales: lengths 0.4 m, angles 1 rad; velocities and accelerations by their typical size.
  MaxError pos, vel, acc;
  for (int i = 0; i <= 240; ++i) {
    const double t = 3.0 * i / 240;
    ASSERT_EQ(solver.solve(t, row), Status::ok) << "t = " << t;
    const FourBarExpected ex = four_bar_closed_form(t);
    // Crank: origin O2, angle = driver.
    const double th = fth0 + fw * t + fe * std::sin(2 * t);
    const double thd = fw + 2 * fe * std::cos(2 * t), thdd = -4 * fe * std::sin(2 * t);
    const Angle crank{th, thd, thdd};
    // Coupler: origin P, x axis P -> Q. Rocker: origin O4, x axis O4 -> Q.
    const Angle coupler = angle_of(ex.q - ex.p, ex.qd - ex.pd, ex.qdd - ex.pdd);
    const Angle rocker = angle_of(ex.q - Vector2d(fd, 0), ex.qd, ex.qdd);
    struct BodyCase {
      const char* name;
      Vector2d o, od, odd;
      Angle a;
      Vector2d com;
    };
    const BodyCase bodies[] = {
        {"crank", Vector2d::Zero(), Vector2d::Zero(), Vector2d::Zero(), crank, {fa / 2, 0}},
        {"coupler", ex.p, ex.pd, ex.pdd, coupler, {coupler_cx, coupler_cy}},
        {"rocker", {fd, 0}, Vector2d::Zero(), Vector2d::Zero(), rocker, {rocker_cx, 0}},
    };
    for (const BodyCase& b : bodies) {
      Vector2d p, v, a;
      body_point(b.o, b.od, b.odd, b.a, b.com, p, v, a);
      const std::string n = b.name;
      pos.update(row[col(n + ".x")], p.x(), fd, n + ".x");
      pos.update(row[col(n + ".y")], p.y(), fd, n + ".y");
      pos.update(std::remainder(row[col(n + ".th")] - b.a.th, 2 * M_PI), 0, 1, n + ".th");
      vel.update(row[col(n + ".vx")], v.x(), fd * fw, n + ".vx");
      vel.update(row[col(n + ".vy")], v.y(), fd * fw, n + ".vy");
      vel.update(row[col(n + ".w")], b.a.w, fw, n + ".w");
      acc.update(row[col(n + ".ax")], a.x(), fd * fw * fw, n + ".ax");
      acc.update(row[col(n + ".ay")], a.y(), fd * fw * fw, n + ".ay");
      acc.update(row[col(n + ".al")], b.a.al, fw * fw, n + ".al");
    }
    pos.update(row[col("Q.x")], ex.q.x(), fd, "Q.x");
    pos.update(row[col("Q.y")], ex.q.y(), fd, "Q.y");
    pos.update(row[col("P.x")], ex.p.x(), fd, "P.x");
    pos.update(row[col("theta.q")], th, 1, "theta.q");
    vel.update(row[col("theta.qd")], thd, fw, "theta.qd");
    acc.update(row[col("theta.qdd")], thdd, fw * fw, "theta.qdd");
    // Frame origins and angles through poses().
    const auto& pose = solver.poses()[model.body_index("coupler")];
    pos.update(pose.x, ex.p.x(), fd, "pose coupler.x");
    pos.update(pose.y, ex.p.y(), fd, "pose coupler.y");
  }
  std::printf(
      "four-bar max relative errors: positions %.2e (%s), velocities %.2e (%s), "
      "accelerations %.2e (%s)\n",
      pos.value, pos.where.c_str(), vel.value, vel.where.c_str(), acc.value, acc.where.c_str());
  EXPECT_LT(pos.value, 1e-13) << pos.where;
  EXPECT_LT(vel.value, 1e-13) << vel.where;
  EXPECT_LT(acc.value, 1e-13) << acc.where;
}

// ------------------------------------------------------------------------------------------------
// In-line slider-crank: crank O-P (r), rod P-Q (L), slider Q on the x axis. Driver th = w t +
// e sin(3 t).  x = r cos th + sqrt(L^2 - r^2 sin^2 th); with S = sqrt(L^2 - r^2 sin^2 th):
//   dx/dth   = -r sin th - r^2 sin th cos th / S
//   d2x/dth2 = -r cos th - r^2 cos 2th / S - r^4 sin^2 th cos^2 th / S^3
//   xd = x' thd,  xdd = x'' thd^2 + x' thdd.
// Rod angle phi (P -> Q): sin phi = -r sin th / L,
//   phid = -r cos th thd / (L cos phi),
//   phidd = ((r sin th thd^2 - r cos th thdd) / L + sin phi phid^2) / cos phi.
constexpr double sr = 0.05, sL = 0.18, sw = 7, se = 0.2;

const char* const slider_crank_yaml = R"(
name: slider
parameters:
  r: 0.05
  L: 0.18
  w: 7
  e: 0.2
bodies:
  - name: ground
    ground: true
    points: {O: [0, 0]}
  - name: crank
    points: {O: [0, 0], P: [r, 0]}
    mass: {mass: 0.3, com: [r/2, 0], inertia: 1e-4}
    assembly: 0.2
  - name: rod
    points: {P: [0, 0], Q: [L, 0]}
    mass: {mass: 0.5, com: [L/2, 0], inertia: 2e-3}
    assembly: -0.05
  - name: slider
    points: {Q: [0, 0]}
    mass: {mass: 1, com: [0, 0], inertia: 1e-3}
joints:
  - {name: jO, type: revolute, first: ground, second: crank, point: O}
  - {name: jP, type: revolute, first: crank, second: rod, point: P}
  - {name: jQ, type: revolute, first: rod, second: slider, point: Q}
  - {name: slide, type: prismatic, first: ground, second: slider, point: Q,
     line: {through: [0, 0], direction: [1, 0]}, angle: 0}
drivers:
  - {name: theta, joint: jO, kind: angle, value: w*t + e*sin(3*t)}
step: {t0: 0, t1: 2, samples: 101}
)";

TEST(ReferenceSolverKinematics, SliderCrankMatchesClassicClosedForm) {
  const Model model = read_model_text(slider_crank_yaml, "slider.yaml");
  ReferenceSolver solver(model, model.default_parameters());
  solver.assemble(0);
  const Columns col(model);
  std::vector<double> row;
  MaxError pos, vel, acc;
  for (int i = 0; i <= 300; ++i) {
    const double t = 2.0 * i / 300;
    ASSERT_EQ(solver.solve(t, row), Status::ok) << "t = " << t;
    const double th = sw * t + se * std::sin(3 * t);
    const double thd = sw + 3 * se * std::cos(3 * t), thdd = -9 * se * std::sin(3 * t);
    const double s = std::sin(th), c = std::cos(th);
    const double S = std::sqrt(sL * sL - sr * sr * s * s);
    const double x = sr * c + S;
    const double x1 = -sr * s - sr * sr * s * c / S;
    const double x2 =
        -sr * c - sr * sr * std::cos(2 * th) / S - std::pow(sr, 4) * s * s * c * c / (S * S * S);
    const double xd = x1 * thd, xdd = x2 * thd * thd + x1 * thdd;
    const double phi = std::asin(-sr * s / sL);
    const double phid = -sr * c * thd / (sL * std::cos(phi));
    const double phidd =
        ((sr * s * thd * thd - sr * c * thdd) / sL + std::sin(phi) * phid * phid) / std::cos(phi);
    pos.update(row[col("slider.x")], x, sL, "slider.x");
    pos.update(row[col("slider.y")], 0, sL, "slider.y");
    pos.update(row[col("Q.x")], x, sL, "Q.x");
    pos.update(row[col("rod.th")], phi, 1, "rod.th");
    pos.update(row[col("slider.th")], 0, 1, "slider.th");
    vel.update(row[col("slider.vx")], xd, sr * sw, "slider.vx");
    vel.update(row[col("slider.vy")], 0, sr * sw, "slider.vy");
    vel.update(row[col("rod.w")], phid, sw, "rod.w");
    acc.update(row[col("slider.ax")], xdd, sr * sw * sw, "slider.ax");
    acc.update(row[col("rod.al")], phidd, sw * sw, "rod.al");
    acc.update(row[col("slider.al")], 0, sw * sw, "slider.al");
    // Rod centre of mass: midpoint of P and Q.
    const double px = sr * c, py = sr * s;
    pos.update(row[col("rod.x")], (px + x) / 2, sL, "rod.x");
    pos.update(row[col("rod.y")], py / 2, sL, "rod.y");
    vel.update(row[col("rod.vx")], (-sr * s * thd + xd) / 2, sr * sw, "rod.vx");
    acc.update(row[col("rod.ax")], (-sr * c * thd * thd - sr * s * thdd + xdd) / 2, sr * sw * sw,
               "rod.ax");
    acc.update(row[col("rod.ay")], (-sr * s * thd * thd + sr * c * thdd) / 2, sr * sw * sw,
               "rod.ay");
  }
  std::printf(
      "slider-crank max relative errors: positions %.2e (%s), velocities %.2e (%s), "
      "accelerations %.2e (%s)\n",
      pos.value, pos.where.c_str(), vel.value, vel.where.c_str(), acc.value, acc.where.c_str());
  EXPECT_LT(pos.value, 1e-13) << pos.where;
  EXPECT_LT(vel.value, 1e-13) << vel.where;
  EXPECT_LT(acc.value, 1e-13) << acc.where;
}

// A coarse sweep (the crank turning 0.7 rad per sample, beyond branch_jump_angle) still follows the
// same branch: the jump test compares with the second-order prediction, and continuation sub-steps
// rescue a Newton that strays.
TEST(ReferenceSolverKinematics, CoarseStepsStayOnTheBranch) {
  const Model model = read_model_text(four_bar_yaml, "fourbar.yaml");
  ReferenceSolver solver(model, model.default_parameters());
  solver.assemble(0);
  const Columns col(model);
  std::vector<double> row;
  for (int i = 0; i <= 30; ++i) {
    const double t = 0.2 * i;
    ASSERT_EQ(solver.solve(t, row), Status::ok) << "t = " << t;
    const FourBarExpected ex = four_bar_closed_form(t);
    EXPECT_NEAR(row[col("Q.x")], ex.q.x(), 1e-12);
    EXPECT_NEAR(row[col("Q.y")], ex.q.y(), 1e-12);
  }
}

}  // namespace
}  // namespace mechgen::numeric
