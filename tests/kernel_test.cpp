// Properties of the generated kernels themselves: PASIBOT's angles equal the seed's closed forms,
// float agrees with double, and evaluating allocates nothing.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include "assur_triad/assur_triad.hpp"
#include "chebyshev/chebyshev.hpp"
#include "cylinder_leg/cylinder_leg.hpp"
#include "leg3/leg3.hpp"
#include "pasibot/pasibot.hpp"
#include "quick_return/quick_return.hpp"
#include "slider_crank/slider_crank.hpp"

// Every heap allocation of this test binary is counted. AddressSanitizer replaces operator new
// itself, so the sanitizer build leaves it alone and skips the allocation test.
static std::atomic<long> g_allocations{0};
#if !defined(__SANITIZE_ADDRESS__)
void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
#endif

namespace {

namespace pb = mechgen::gen::pasibot;

double wrap(double a) {
  return std::remainder(a, 2 * M_PI);
}

// Seed eq. (6): coupler theta7 and rocker theta9 from the crank angle theta8 (hip frame).
void seed_eq6(double th8, double& th7, double& th9) {
  const double c = std::cos(th8), s = std::sin(th8);
  const double root = std::sqrt(-16 * c * c - 60 * c + 100);
  th7 = std::acos((-4 * c * c + 13 * c - 10 + s * root) / (25 - 20 * c));
  th9 = std::acos((-4 * c * c + 13 * c - 10 - s * root) / (-25 + 20 * c));
}

// Seed eq. (7), femur theta3 and upper tendon theta6, with the two misplaced parentheses of the
// printed equation corrected (see models/pasibot.yaml): v = 2.5 (sin th7 + sin th9) - 12.
void seed_eq7(double th7, double th9, double& th6, double& th3) {
  const double u = 2.5 * (std::cos(th7) + std::cos(th9));
  const double v = 2.5 * (std::sin(th7) + std::sin(th9)) - 12;
  const double a = u * u + v * v;
  th6 = std::acos((u * (-27 - a) - v * std::sqrt(144 * a - (27 + a) * (27 + a))) / (12 * a));
  th3 = std::acos((u * (27 - a) + v * std::sqrt(36 * a - (27 - a) * (27 - a))) / (6 * a));
}

// Seed eq. (8): stabiliser theta10.
double seed_eq8(double th7, double th8) {
  return std::asin((5 * std::sin(th7) - std::sin(th8) - 4) / 4.2);
}

TEST(PasibotKernel, AnglesEqualTheSeedsClosedForms) {
  const pb::Params<double> p;
  double worst = 0;
  const int samples = 400;
  for (int i = 0; i <= samples; ++i) {
    const double t = (M_PI / p.w8) * i / samples;  // the support phase: th8 from pi/2 to 3 pi/2
    pb::Inputs<double> in;
    pb::driver_inputs(p, t, in);
    pb::State<double> s;
    ASSERT_EQ(pb::kinematics(p, in, s), pb::Status::ok) << "t=" << t;
    const double hip = s.bodies.l13.th();  // seed eq. (11): hip-frame angle = ground angle - hip's
    double th7, th9, th6, th3;
    seed_eq6(in.theta8, th7, th9);
    seed_eq7(th7, th9, th6, th3);
    const double th10 = seed_eq8(th7, in.theta8);
    const double errors[] = {
        wrap(s.bodies.l7.th() - hip - th7), wrap(s.bodies.l9.th() - hip - th9),
        wrap(s.bodies.l6.th() - hip - th6), wrap(s.bodies.l3.th() - hip - th3),
        wrap(s.bodies.l10.th() - hip - th10),
        // eq. (9): the parallel links share the angles
        wrap(s.bodies.l1p.th() - s.bodies.l5p.th()), wrap(s.bodies.l5.th() - s.bodies.l10.th()),
        wrap(s.bodies.l12.th() - s.bodies.l3.th()), wrap(s.bodies.l4.th() - s.bodies.l3.th()),
        wrap(s.bodies.l2.th() - s.bodies.l6.th()), wrap(s.bodies.l11.th() - s.bodies.l6.th()),
        // the support foot is the ground: link 1 parallel to link 10 means the hip tilts by -th10
        wrap(hip + th10)};
    for (double e : errors) worst = std::max(worst, std::abs(e));
    // The orientation is kept as its cosine and sine, each taken from the closed form's joint
    // positions divided by the link's length: a unit vector only if the loop closes.
    for (const auto* b : {&s.bodies.l7, &s.bodies.l9, &s.bodies.l6, &s.bodies.l3, &s.bodies.l10,
                          &s.bodies.l2, &s.bodies.l11, &s.bodies.l1p, &s.bodies.l13})
      worst = std::max(worst, std::abs(std::hypot(b->cos_th, b->sin_th) - 1));
  }
  EXPECT_LE(worst, 1e-12);
}

// The flying leg is the support leg half a crank turn later (seed eq. 10).
TEST(PasibotKernel, FlyingLegIsTheSupportLegPhasedByPi) {
  const pb::Params<double> p;
  for (double th8 : {1.7, 2.3, 3.1, 4.4}) {
    pb::Inputs<double> a, b;
    a.theta8 = th8;
    b.theta8 = th8 + M_PI;
    pb::State<double> sa, sb;
    ASSERT_EQ(pb::kinematics(p, a, sa), pb::Status::ok);
    ASSERT_EQ(pb::kinematics(p, b, sb), pb::Status::ok);
    const double hip_a = sa.bodies.l13.th(), hip_b = sb.bodies.l13.th();
    EXPECT_NEAR(wrap(sa.bodies.l7p.th() - hip_a - (sb.bodies.l7.th() - hip_b)), 0, 1e-12);
    EXPECT_NEAR(wrap(sa.bodies.l3p.th() - hip_a - (sb.bodies.l3.th() - hip_b)), 0, 1e-12);
    EXPECT_NEAR(wrap(sa.bodies.l10p.th() - hip_a - (sb.bodies.l10.th() - hip_b)), 0, 1e-12);
  }
}

// float and double instantiations agree to float precision on every output column.
TEST(PasibotKernel, FloatAgreesWithDouble) {
  const pb::Params<double> pd;
  const pb::Params<float> pf;
  double worst = 0;
  for (int i = 0; i <= 50; ++i) {
    const double t = (M_PI / pd.w8) * i / 50;
    pb::Inputs<double> ind;
    pb::Inputs<float> inf;
    pb::driver_inputs(pd, t, ind);
    pb::driver_inputs(pf, static_cast<float>(t), inf);
    pb::State<double> sd;
    pb::State<float> sf;
    ASSERT_EQ(pb::evaluate(pd, ind, sd), pb::Status::ok);
    ASSERT_EQ(pb::evaluate(pf, inf, sf), pb::Status::ok);
    double rd[pb::column_count];
    float rf[pb::column_count];
    pb::to_columns(ind, sd, rd);
    pb::to_columns(inf, sf, rf);
    // Scale: the largest magnitude of the column's kind in this row keeps near-zero columns fair.
    double scale_force = 0, scale_other = 0;
    for (int c = 0; c < pb::column_count; ++c) {
      const std::string name = pb::column_names[c];
      const bool force =
          name.find(".f") != std::string::npos || name.find("effort") != std::string::npos;
      (force ? scale_force : scale_other) =
          std::max(force ? scale_force : scale_other, std::abs(rd[c]));
    }
    for (int c = 0; c < pb::column_count; ++c) {
      const std::string name = pb::column_names[c];
      const bool force =
          name.find(".f") != std::string::npos || name.find("effort") != std::string::npos;
      double diff = rf[c] - rd[c];
      if (name.size() > 3 && name.substr(name.size() - 3) == ".th") diff = wrap(diff);
      const double scale = std::max(std::abs(rd[c]), 1e-3 * (force ? scale_force : scale_other));
      worst = std::max(worst, std::abs(diff) / scale);
    }
  }
  // float has 24 bits (6e-8); a chain of 23 bodies and the differentiation through it lose about
  // four decimal digits on the smallest accelerations and reactions (measured: 2.9e-3).
  EXPECT_LE(worst, 1e-2);
  EXPECT_GT(worst, 1e-9);  // and it really ran in float
}

// A crank longer than its connecting rod cannot reach the slider's line at right angles: the
// kernel says which group failed instead of returning NaN.
TEST(SliderCrankKernel, UnreachableIsAStatusNotNaN) {
  namespace sc = mechgen::gen::slider_crank;
  sc::Params<double> p;
  p.r = 1.5 * p.L;
  sc::Inputs<double> in;
  sc::State<double> s;
  in.crank_angle = 0.1;  // near the line: reachable
  ASSERT_EQ(sc::evaluate(p, in, s), sc::Status::ok);
  in.crank_angle = M_PI / 2;  // |r sin| > L: the rod cannot reach
  EXPECT_EQ(sc::evaluate(p, in, s), sc::Status::unreachable);
  ASSERT_GE(s.failed_group, 0);
  EXPECT_EQ(std::string(sc::group_names[s.failed_group]).rfind("g2_", 0), 0u);
  // The State of a failed evaluation is cleared: no part of a configuration, no NaN of the
  // failed square root (the entries write each output as soon as it is known).
  double row[sc::column_count];
  sc::to_columns(in, s, row);
  for (int c = 1; c < sc::column_count; ++c)  // column 0 is the input time
    EXPECT_EQ(row[c], 0.0) << sc::column_names[c];
  in.crank_angle = std::nan("");
  EXPECT_EQ(sc::evaluate(p, in, s), sc::Status::unreachable);
}

TEST(Kernels, EvaluateAllocatesNothing) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "allocations are counted in the build without AddressSanitizer";
#endif
  namespace cb = mechgen::gen::chebyshev;
  namespace sc = mechgen::gen::slider_crank;
  namespace lg = mechgen::gen::leg3;
  const pb::Params<double> pp;
  const cb::Params<double> cp;
  const sc::Params<double> sp;
  const lg::Params<double> lp;
  pb::State<double> ps;
  cb::State<double> cs;
  sc::State<double> ss;
  lg::State<double> ls;
  pb::Inputs<double> pi;
  cb::Inputs<double> ci;
  sc::Inputs<double> si;
  lg::Inputs<double> li;
  double sink = 0;
  const long before = g_allocations.load();
  for (int i = 0; i < 10000; ++i) {
    const double t = 1e-4 * i;
    pb::driver_inputs(pp, t, pi);
    cb::driver_inputs(cp, t, ci);
    sc::driver_inputs(sp, t, si);
    lg::driver_inputs(lp, t, li);
    sink += static_cast<int>(pb::evaluate(pp, pi, ps)) + ps.drivers.theta8.effort;
    sink += static_cast<int>(cb::evaluate(cp, ci, cs)) +
            static_cast<int>(sc::evaluate(sp, si, ss)) + static_cast<int>(lg::evaluate(lp, li, ls));
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_TRUE(std::isfinite(sink));
}

// The RPR, slot-on-body, PRP and iterative (Newton-Raphson, warm-started from the state) kernels.
TEST(Kernels, NewGroupKindsAllocateNothing) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "allocations are counted in the build without AddressSanitizer";
#endif
  namespace cl = mechgen::gen::cylinder_leg;
  namespace qr = mechgen::gen::quick_return;
  namespace at = mechgen::gen::assur_triad;
  const cl::Params<double> cp;
  const qr::Params<double> qp;
  const at::Params<double> ap;
  cl::State<double> cs;
  qr::State<double> qs;
  at::State<double> as;
  cl::Inputs<double> ci;
  qr::Inputs<double> qi;
  at::Inputs<double> ai;
  double sink = 0;
  int failures = 0;
  const long before = g_allocations.load();
  for (int i = 0; i < 10000; ++i) {
    const double t = 1e-4 * i;
    cl::driver_inputs(cp, t, ci);
    qr::driver_inputs(qp, t, qi);
    at::driver_inputs(ap, t, ai);
    failures += static_cast<int>(cl::evaluate(cp, ci, cs)) +
                static_cast<int>(qr::evaluate(qp, qi, qs)) +
                static_cast<int>(at::evaluate(ap, ai, as));
    sink += cs.points.D.x + qs.points.C.x + as.bodies.plate.th();
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_EQ(failures, 0);
  EXPECT_TRUE(std::isfinite(sink));
}

}  // namespace
