// latency_order (generator/latency_schedule.cpp): the printed order of a kernel's statements is a
// valid program order (every definition after what it reads, every check after its quantity,
// checks in their original relative order) and puts the long chain first.
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

}  // namespace
}  // namespace mechgen::gen
