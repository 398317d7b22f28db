// TimeExpression: the compiled double evaluation of driver and load expressions agrees with
// GiNaC's own evaluation, and falls back to it outside the compiled set.
#include <gtest/gtest.h>

#include <cmath>

#include "numeric/time_expression.hpp"

namespace mechgen::numeric {
namespace {

double ginac_value(const GiNaC::ex& e, const GiNaC::symbol& t, double tv) {
  return GiNaC::ex_to<GiNaC::numeric>(e.subs(t == tv).evalf()).to_double();
}

TEST(TimeExpression, MatchesGinacEvaluation) {
  GiNaC::symbol t("t");
  const GiNaC::ex eta =
      GiNaC::numeric(99, 100) - GiNaC::numeric(1, 5) * GiNaC::pow((1 + GiNaC::sin(4 * t)) / 2, 2);
  const GiNaC::ex cases[] = {
      GiNaC::Pi / 2 + 3 * t,
      0.3 * GiNaC::cos(4 * t) - GiNaC::acos(eta),
      (0.3 * GiNaC::cos(4 * t) - GiNaC::acos(eta)).diff(t, 2),  // powers -1/2, -3/2, products
      GiNaC::sqrt(1 + t * t) * GiNaC::exp(-t) / (2 + GiNaC::tan(t / 3)),
      GiNaC::atan2(GiNaC::sin(t), 2 + GiNaC::cos(t)) + GiNaC::log(1 + t) + GiNaC::pow(t, 7),
      GiNaC::abs(t - 0.5) + GiNaC::asin(t / 4) + GiNaC::atan(t) + GiNaC::pow(2, t),
      GiNaC::ex(2.5),
  };
  for (const GiNaC::ex& e : cases) {
    const TimeExpression f(e, t);
    EXPECT_TRUE(f.compiled()) << e;
    for (double tv : {0.0, 0.1, 0.7, 1.3, 2.9}) {
      const double want = ginac_value(e, t, tv);
      EXPECT_NEAR(f(tv), want, 1e-14 * (1 + std::abs(want))) << e << " at t = " << tv;
    }
  }
}

TEST(TimeExpression, FallsBackAndReportsNonReal) {
  GiNaC::symbol t("t");
  const GiNaC::ex unusual = GiNaC::zeta(GiNaC::ex(2) + t);  // not in the compiled set
  const TimeExpression f(unusual, t);
  EXPECT_FALSE(f.compiled());
  EXPECT_NEAR(f(1.0), 1.2020569031595942, 1e-15);  // zeta(3)
  const TimeExpression g(GiNaC::sqrt(t - 1), t);
  EXPECT_TRUE(std::isnan(g(0.0)));  // complex: not a number
  EXPECT_NEAR(g(5.0), 2.0, 1e-15);
  EXPECT_FALSE(TimeExpression(GiNaC::ex(3), t).depends_on_time());
}

}  // namespace
}  // namespace mechgen::numeric
