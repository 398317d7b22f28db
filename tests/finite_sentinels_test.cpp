// finite_sentinels (generator/finite_sentinels.hpp): an output is left out of its stage's
// finiteness sum only when another kept output carries its infinity or NaN, and the claim itself
// holds in IEEE arithmetic for the operations it relies on.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "finite_sentinels.hpp"

namespace mechgen::gen {
namespace {

using GiNaC::ex;
using GiNaC::symbol;

TEST(FiniteSentinels, KeepsOnlyOutputsNoOtherOutputCarries) {
  const symbol a("a"), b("b"), c("c"), d("d"), e("e"), p("p.l1"), q("in.q1");
  SymbolDefinitions defs;
  defs[a] = p * q;          // a = l1 q
  defs[b] = a * a + q;      // b reads a through a product: carries it
  defs[c] = 1 / a;          // c reads a through a division only: 1/inf = 0
  defs[d] = GiNaC::sin(b);  // a function stops the chain too
  defs[e] = -b + 2 * p;     // e carries b, hence a
  // Outputs: a, b, c, d, e and the input q itself.
  const std::vector<ex> values{a, b, c, d, e, q};
  const std::vector<size_t> kept = finite_sentinels(values, defs);
  // a and b are carried by e; q is a checked input; c, d, e stand alone.
  EXPECT_EQ(kept, (std::vector<size_t>{2, 3, 4}));
  // Without e, b is the sentinel that carries a.
  EXPECT_EQ(finite_sentinels({a, b, c}, defs), (std::vector<size_t>{1, 2}));
  // An output that is an expression (not a named intermediate) is always kept.
  EXPECT_EQ(finite_sentinels({a * 2 + 1, -e}, defs), (std::vector<size_t>{0, 1}));
}

// The arithmetic the rule relies on: +, -, * carry a non-finite operand whatever the other.
TEST(FiniteSentinels, IeeeArithmeticCarriesNonFiniteThroughSumsAndProducts) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const double bad : {inf, -inf, nan})
    for (const double other : {0.0, -1.5, 1e300, inf, -inf}) {
      EXPECT_FALSE(std::isfinite(bad + other));
      EXPECT_FALSE(std::isfinite(bad - other));
      EXPECT_FALSE(std::isfinite(other - bad));
      EXPECT_FALSE(std::isfinite(bad * other));
    }
  EXPECT_TRUE(std::isfinite(1.0 / inf));  // why division stops the chain
}

}  // namespace
}  // namespace mechgen::gen
