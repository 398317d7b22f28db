// latency_order (generator/latency_schedule.cpp): the printed order of a kernel's statements is a
// valid program order (every definition after what it reads, every check after its quantity,
// checks in their original relative order) and puts the long chain first. emission_order: the
// same guarantees with the outputs placed among the statements, each value computed right before
// its first use and each output written as soon as it is known.
#include "latency_schedule.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace mechgen::gen {
namespace {

using GiNaC::ex;
using GiNaC::symbol;

Statement define(const symbol& s, const ex& value) {
  return {Statement::Kind::define, s, value, "", -1, false};
}
Statement check(const symbol& s, int group) {
  return {Statement::Kind::check_positive, s, ex(0), "unreachable", group, false};
}

size_t position(const std::vector<size_t>& order, size_t statement) {
  return static_cast<size_t>(std::find(order.begin(), order.end(), statement) - order.begin());
}

TEST(LatencySchedule, ValidOrderLongChainFirstChecksKept) {
  const symbol x("x"), y("y"), a("a"), root("root"), b("b"), c("c"), e("e"), d("d"), unused("u");
  // 0..2: a short independent sum and its check (group 0), written first; 3..6: a chain through
  // a square root and a division (long) with the check of a (group 1), which must stay after
  // group 0's; 7: both joined; 8: a statement nobody needs.
  const std::vector<Statement> statements = {
      define(c, x + y),              // 0
      define(e, c - 1),              // 1
      check(e, 0),                   // 2
      define(a, x * y),              // 3
      check(a, 1),                   // 4
      define(root, GiNaC::sqrt(a)),  // 5
      define(b, root / (a + x)),     // 6
      define(d, b * e),              // 7
      define(unused, x - y),         // 8
  };
  const std::set<ex, GiNaC::ex_is_less> needed = {x, y, a, root, b, c, e, d};
  const std::vector<size_t> order = latency_order(statements, needed);

  ASSERT_EQ(order.size(), 8u);  // every needed statement once, the unused one left out
  EXPECT_EQ(position(order, 8), order.size());
  // Reads before uses.
  EXPECT_LT(position(order, 0), position(order, 1));
  EXPECT_LT(position(order, 3), position(order, 5));
  EXPECT_LT(position(order, 5), position(order, 6));
  EXPECT_LT(position(order, 6), position(order, 7));
  EXPECT_LT(position(order, 1), position(order, 7));
  // Checks after their quantity and in their original order.
  EXPECT_LT(position(order, 1), position(order, 2));
  EXPECT_LT(position(order, 3), position(order, 4));
  EXPECT_LT(position(order, 2), position(order, 4));
  // The chain through sqrt and the division (about 48 cycles by the latency model) starts before
  // the short sum written ahead of it (about 12).
  EXPECT_LT(position(order, 3), position(order, 0));
  EXPECT_LT(position(order, 5), position(order, 0));
  EXPECT_LT(position(order, 6), position(order, 0));
}

size_t step_position(const std::vector<Step>& order, bool output, size_t index) {
  for (size_t k = 0; k < order.size(); ++k)
    if (order[k].output == output && order[k].index == index) return k;
  return order.size();
}

TEST(EmissionOrder, OutputsAsSoonAsKnownValuesJustBeforeUseWarmStartLast) {
  const symbol x("x"), y("y"), a("a"), b("b"), c("c"), e("e"), f("f"), unused("u");
  const std::vector<Statement> statements = {
      define(a, x + y),           // 0: only output 0 reads it
      define(b, x * y),           // 1
      check(b, 0),                // 2
      define(c, GiNaC::sqrt(b)),  // 3
      check(c, 1),                // 4
      define(e, c / (b + x)),     // 5
      define(f, e * e),           // 6
      define(unused, x - y),      // 7: needed by nobody
  };
  const std::set<ex, GiNaC::ex_is_less> needed = {x, y, a, b, c, e, f};
  // Output 0 reads a, output 1 reads f, output 2 (a warm start) reads c, output 3 is constant.
  const std::vector<ex> outputs = {a, f, c, ex(2)};
  const std::vector<bool> after_checks = {false, false, true, false};
  for (const Readiness readiness : {Readiness::latency, Readiness::program}) {
    const std::vector<Step> order =
        emission_order(statements, needed, outputs, after_checks, readiness);
    ASSERT_EQ(order.size(), 7u + 4u);  // statements 0-6 and the four outputs, 7 left out
    EXPECT_EQ(step_position(order, false, 7), order.size());
    auto at = [&](size_t statement) { return step_position(order, false, statement); };
    auto out = [&](size_t output) { return step_position(order, true, output); };
    // A valid program: reads before uses, checks after their quantity and in their order.
    EXPECT_LT(at(1), at(2));
    EXPECT_LT(at(1), at(3));
    EXPECT_LT(at(3), at(4));
    EXPECT_LT(at(2), at(4));
    EXPECT_LT(at(3), at(5));
    EXPECT_LT(at(5), at(6));
    // Each output right after what it reads (a constant one first); a is computed right
    // before output 0 rather than at the top.
    EXPECT_EQ(out(3), 0u);
    EXPECT_EQ(out(0), at(0) + 1);
    EXPECT_EQ(out(1), at(6) + 1);
    // The warm start only after every check, at the very end.
    EXPECT_GT(out(2), at(4));
    EXPECT_EQ(out(2), order.size() - 1);
  }
}

}  // namespace
}  // namespace mechgen::gen
