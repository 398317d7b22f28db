// The solve groups beyond the dyads, each against an independent expectation: the RPR cylinder
// leg's foot-end against a hand closed form (law of cosines), the quick-return's slot-on-lever and
// PRP ram against the textbook formula and its derivative, the inverted slider-crank's passive RPR
// against the rocker angle worked by hand, and the Assur triad's iterative solve against its own
// loop constraints (residual ~1e-12), with a warm start giving the same answer.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "assur_triad/assur_triad.hpp"
#include "cylinder_leg/cylinder_leg.hpp"
#include "inverted_slider/inverted_slider.hpp"
#include "quick_return/quick_return.hpp"

namespace {

using std::cos;
using std::sin;

struct Xy {
  double x, y;
};
Xy rotate(double th, Xy v) {
  return {cos(th) * v.x - sin(th) * v.y, sin(th) * v.x + cos(th) * v.y};
}

// Thigh angle from the triangle hip H, torso pin G, thigh pin T with |GT| = l1 + r1:
// |R(th) (0, -ty) - (-gx, 0)|^2 = ty^2 + gx^2 + 2 gx ty sin(th).
// Knee angle phi (shank relative to thigh) from |K + R(phi) s - F| = l2 + r2 in the thigh frame,
// e = K - F, s = S in the shank frame: |e|^2 + |s|^2 + 2 (A cos(phi) + B sin(phi)) = d^2, on the
// branch near the assembly's -1 rad.
Xy hand_foot(const mechgen::gen::cylinder_leg::Params<double>& p, double l1, double l2) {
  const double d1 = l1 + p.r1, d2 = l2 + p.r2;
  const double th = std::asin((d1 * d1 - p.ty * p.ty - p.gx * p.gx) / (2 * p.gx * p.ty));
  const Xy e{p.fx, p.fy - p.l_th}, s{-p.sx, -p.sy};
  const double a = e.x * s.x + e.y * s.y, b = e.x * -s.y + e.y * s.x;
  const double c = (d2 * d2 - (e.x * e.x + e.y * e.y) - (s.x * s.x + s.y * s.y)) / 2;
  const double phi = std::atan2(b, a) - std::acos(c / std::hypot(a, b));
  const Xy knee = rotate(th, {0, -p.l_th}), shank = rotate(th + phi, {0, -p.l_sh});
  return {knee.x + shank.x, knee.y + shank.y};
}

TEST(RprCylinderLeg, FootEndMatchesHandClosedForm) {
  namespace k = mechgen::gen::cylinder_leg;
  k::Params<double> p;
  int checked = 0;
  for (double t = 0; t < 2 * M_PI / p.w; t += 0.05) {
    k::Inputs<double> in;
    k::driver_inputs(p, t, in);
    k::State<double> s;
    ASSERT_EQ(k::kinematics(p, in, s), k::Status::ok) << "t=" << t;
    const Xy foot = hand_foot(p, in.l1, in.l2);
    EXPECT_NEAR(s.points.D.x, foot.x, 1e-12) << "t=" << t;
    EXPECT_NEAR(s.points.D.y, foot.y, 1e-12) << "t=" << t;
    ++checked;
  }
  EXPECT_GT(checked, 30);
}

TEST(RprCylinderLeg, StrokeBeyondReachIsUnreachableNamingTheKneeGroup) {
  namespace k = mechgen::gen::cylinder_leg;
  k::Params<double> p;
  k::Inputs<double> in;
  k::driver_inputs(p, 0.0, in);
  // |F K| + |K S| = 0.308 + 0.117: a pin distance of 0.5 m cannot close the knee triangle.
  in.l2 = 0.5 - p.r2;
  k::State<double> s;
  EXPECT_EQ(k::kinematics(p, in, s), k::Status::unreachable);
  EXPECT_STREQ(k::group_names[s.failed_group], "g2_shank_rod2_barrel2");
}

// The textbook crank-shaper: the lever through Q and the crank pin P = O + r (cos a, sin a) makes
// tan(phi) = (d + r sin a) / (r cos a); the ram's pin C on y = h is at x = h r cos a / (d + r sin
// a).
TEST(SlotOnLeverAndPrp, RamFollowsTextbookFormulaAndItsDerivative) {
  namespace k = mechgen::gen::quick_return;
  k::Params<double> p;
  for (double t = 0; t < 2 * M_PI / p.w; t += 0.037) {
    k::Inputs<double> in;
    k::driver_inputs(p, t, in);
    k::State<double> s{};
    ASSERT_EQ(k::evaluate(p, in, s), k::Status::ok) << "t=" << t;
    const double a = in.crank_angle, ad = in.crank_angle_d;
    const double num = p.h * p.r * cos(a), den = p.d + p.r * sin(a);
    EXPECT_NEAR(s.points.C.x, num / den, 1e-12) << "t=" << t;
    EXPECT_NEAR(s.points.C.y, p.h, 1e-12) << "t=" << t;
    EXPECT_NEAR(s.bodies.lever.th(), std::atan2(den, p.r * cos(a)), 1e-12) << "t=" << t;
    // The ram translates: its centre of mass moves with C.
    const double rate = (-p.h * p.r * sin(a) * den - num * p.r * cos(a)) / (den * den) * ad;
    EXPECT_NEAR(s.bodies.ram.vx, rate, 1e-12) << "t=" << t;
    EXPECT_NEAR(s.bodies.ram.vy, 0.0, 1e-12) << "t=" << t;
  }
}

// A body's point from its reported centre of mass and angle.
Xy body_point(double x, double y, double th, Xy com, Xy local) {
  const Xy arm = rotate(th, {local.x - com.x, local.y - com.y});
  return {x + arm.x, y + arm.y};
}

// Inverted slider-crank: in the rocker's frame (origin at its pivot B, x along the slide) the
// block's slider point is S = (s, 0) and its pin A = S + R(alpha) (0, -h) = (s + h sin(alpha),
// -h cos(alpha)). With A - B = R(phi) A_r and rho = |A - B|: s + h sin(alpha) = +sqrt(rho^2 -
// h^2 cos(alpha)^2) on the assembled branch (the rocker points from B towards A), so phi = atan2(A
// - B) - atan2(-h cos(alpha), sqrt(rho^2 - h^2 cos(alpha)^2)); the block turns with it, at alpha.
TEST(PassiveRpr, InvertedSliderRockerFollowsTheHandFormula) {
  namespace k = mechgen::gen::inverted_slider;
  k::Params<double> p;
  auto wrap = [](double a) { return std::remainder(a, 2 * M_PI); };
  int samples = 0;
  for (double t = 0; t < 2 * M_PI / p.w; t += 0.011, ++samples) {
    k::Inputs<double> in;
    k::driver_inputs(p, t, in);
    k::State<double> s{};
    ASSERT_EQ(k::evaluate(p, in, s), k::Status::ok) << "t=" << t;
    const double ax = p.r * cos(in.crank_angle), ay = p.r * sin(in.crank_angle);
    const double dx = ax - p.d, dy = ay, rho2 = dx * dx + dy * dy;
    const double normal = p.h * cos(p.alpha);
    const double phi = std::atan2(dy, dx) - std::atan2(-normal, std::sqrt(rho2 - normal * normal));
    EXPECT_NEAR(wrap(s.bodies.rocker.th() - phi), 0, 1e-12) << "t=" << t;
    EXPECT_NEAR(wrap(s.bodies.block.th() - phi - p.alpha), 0, 1e-12) << "t=" << t;
    EXPECT_NEAR(s.points.A.x, ax, 1e-14) << "t=" << t;
    EXPECT_NEAR(s.points.A.y, ay, 1e-14) << "t=" << t;
  }
  EXPECT_GT(samples, 100);
}

template <class T>
double triad_residual(const mechgen::gen::assur_triad::State<T>& s) {
  const auto& b = s.bodies;
  const Xy plate_com{0.233, 0.148};
  const Xy c2_plate = body_point(b.plate.x, b.plate.y, b.plate.th(), plate_com, {0.108, -0.028});
  const Xy c3_plate = body_point(b.plate.x, b.plate.y, b.plate.th(), plate_com, {0.386, 0.326});
  const Xy c2_link =
      body_point(b.link2.x, b.link2.y, b.link2.th(), {0.214, -0.1505}, {0.108, -0.028});
  const Xy c3_link = body_point(b.link3.x, b.link3.y, b.link3.th(), {0.412, 0.253}, {0.386, 0.326});
  const Xy b_link =
      body_point(b.link2.x, b.link2.y, b.link2.th(), {0.214, -0.1505}, {0.32, -0.273});
  const Xy d_link = body_point(b.link3.x, b.link3.y, b.link3.th(), {0.412, 0.253}, {0.438, 0.18});
  return std::max({std::hypot(c2_plate.x - c2_link.x, c2_plate.y - c2_link.y),
                   std::hypot(c3_plate.x - c3_link.x, c3_plate.y - c3_link.y),
                   std::hypot(b_link.x - 0.32, b_link.y + 0.273),
                   std::hypot(d_link.x - 0.438, d_link.y - 0.18)});
}

TEST(IterativeTriad, LoopConstraintsHoldToRoundOff) {
  namespace k = mechgen::gen::assur_triad;
  k::Params<double> p;
  double worst = 0;
  for (double t = 0; t < 2 * M_PI / p.w; t += 0.01) {
    k::Inputs<double> in;
    k::driver_inputs(p, t, in);
    k::State<double> s;  // a new state: Newton-Raphson starts from the assembly
    ASSERT_EQ(k::kinematics(p, in, s), k::Status::ok) << "t=" << t;
    worst = std::max(worst, triad_residual(s));
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(IterativeTriad, WarmStartAlongASweepGivesTheSameState) {
  namespace k = mechgen::gen::assur_triad;
  k::Params<double> p;
  k::State<double> warm;  // reused: each call starts from the previous solution
  for (double t = 0; t < 2 * M_PI / p.w; t += 0.05) {
    k::Inputs<double> in;
    k::driver_inputs(p, t, in);
    k::State<double> fresh;
    ASSERT_EQ(k::evaluate(p, in, warm), k::Status::ok);
    ASSERT_EQ(k::evaluate(p, in, fresh), k::Status::ok);
    EXPECT_NEAR(warm.bodies.plate.th(), fresh.bodies.plate.th(), 1e-13) << "t=" << t;
    EXPECT_NEAR(warm.bodies.plate.al, fresh.bodies.plate.al, 1e-9) << "t=" << t;
    EXPECT_NEAR(warm.joints.jC2.fx, fresh.joints.jC2.fx, 1e-9) << "t=" << t;
  }
}

TEST(IterativeTriad, FloatConvergesAndAFarStartFailsCleanly) {
  namespace k = mechgen::gen::assur_triad;
  k::Params<float> pf;
  k::Inputs<float> inf;
  k::driver_inputs(pf, 0.3f, inf);
  k::State<float> sf;
  ASSERT_EQ(k::kinematics(pf, inf, sf), k::Status::ok);
  EXPECT_LT(triad_residual(sf), 1e-5);
  // A crank pin 0.8 m out: link1 (0.21 m) cannot reach the plate from there (its pin C1 is
  // 0.25 m from the crank pivot): no configuration, a status and the group, no NaN out.
  k::Params<double> p;
  k::Inputs<double> in;
  k::driver_inputs(p, 0.0, in);
  k::State<double> s;
  ASSERT_EQ(k::kinematics(p, in, s), k::Status::ok);
  const auto warm = s.warm;  // the solution just found: the next call's start
  p.r = 0.8;
  EXPECT_NE(k::kinematics(p, in, s), k::Status::ok);
  EXPECT_STREQ(k::group_names[s.failed_group], "g2_link1_plate_link2_link3");
  // The failed call cleared the State but kept the warm start of the last success.
  EXPECT_EQ(std::memcmp(&warm, &s.warm, sizeof warm), 0);
  EXPECT_EQ(s.bodies.plate.x, 0.0);
  EXPECT_EQ(s.bodies.plate.cos_th, 0.0);
}

}  // namespace
