#include "latency_schedule.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <queue>
#include <stdexcept>

namespace mechgen::gen {

using GiNaC::ex;

namespace {

// Rough latencies in cycles of one core (assumption: a recent x86-64; only their ratios matter):
// add and multiply 4, division 14, square root 18, the kernels' own sin, cos, atan2 about 40.
constexpr int kArithmetic = 4, kDivision = 14, kRoot = 18, kFunction = 40;

// Latency of an expression once its symbols are known. Sums and products evaluate left to right
// (no reassociation without -ffast-math), a chain of n - 1 operations.
int expression_latency(const ex& e) {
  if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::symbol>(e) ||
      GiNaC::is_a<GiNaC::constant>(e))
    return 0;
  if (GiNaC::is_a<GiNaC::power>(e)) {
    const int base = expression_latency(e.op(0));
    const ex exponent = e.op(1);
    if (exponent.is_equal(GiNaC::numeric(1, 2))) return base + kRoot;
    if (exponent.is_equal(-1)) return base + kDivision;
    return base + kArithmetic + (exponent.info(GiNaC::info_flags::negint) ? kDivision : 0);
  }
  // A factor +-1 is not counted: GiNaC prints -(b - a) c or (a - b) c depending on its
  // run-dependent term order, and the order must be the same in every process.
  int slowest = 0, operands = 0;
  for (size_t i = 0; i < e.nops(); ++i) {
    const ex op = e.op(i);
    if (GiNaC::is_a<GiNaC::mul>(e) && GiNaC::is_a<GiNaC::numeric>(op) &&
        GiNaC::abs(GiNaC::ex_to<GiNaC::numeric>(op)).is_equal(1))
      continue;
    slowest = std::max(slowest, expression_latency(op));
    ++operands;
  }
  if (GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e))
    return slowest + kArithmetic * std::max(0, operands - 1);
  return slowest + kFunction;
}

}  // namespace

std::vector<size_t> latency_order(const std::vector<Statement>& statements,
                                  const std::set<ex, GiNaC::ex_is_less>& needed) {
  const size_t n = statements.size();
  std::map<ex, size_t, GiNaC::ex_is_less> definition;  // symbol -> index of its definition
  std::vector<std::vector<size_t>> users(n);
  std::vector<int> missing(n, 0), latency(n, 1);
  std::vector<bool> used(n, false);
  size_t previous_check = n;
  for (size_t i = 0; i < n; ++i) {
    const Statement& st = statements[i];
    if (!needed.count(st.symbol)) continue;
    used[i] = true;
    std::set<size_t> reads;
    if (st.kind == Statement::Kind::define) {
      latency[i] = std::max(1, expression_latency(st.value));
      for (auto it = st.value.preorder_begin(); it != st.value.preorder_end(); ++it)
        if (auto d = definition.find(*it); d != definition.end()) reads.insert(d->second);
      definition[st.symbol] = i;
    } else {
      if (auto d = definition.find(st.symbol); d != definition.end()) reads.insert(d->second);
      if (previous_check < n) reads.insert(previous_check);
      previous_check = i;
    }
    for (size_t r : reads) users[r].push_back(i);
    missing[i] = static_cast<int>(reads.size());
  }
  // Users always come later in the original order: heights in one backward pass.
  std::vector<long> height(n, 0);
  for (size_t i = n; i-- > 0;) {
    if (!used[i]) continue;
    long tallest = 0;
    for (size_t u : users[i]) tallest = std::max(tallest, height[u]);
    height[i] = latency[i] + tallest;
  }
  // Highest first; equal heights in the original order (deterministic).
  auto lower = [&](size_t a, size_t b) {
    return height[a] != height[b] ? height[a] < height[b] : a > b;
  };
  std::priority_queue<size_t, std::vector<size_t>, decltype(lower)> ready(lower);
  for (size_t i = 0; i < n; ++i)
    if (used[i] && missing[i] == 0) ready.push(i);
  std::vector<size_t> order;
  while (!ready.empty()) {
    const size_t i = ready.top();
    ready.pop();
    order.push_back(i);
    for (size_t u : users[i])
      if (--missing[u] == 0) ready.push(u);
  }
  return order;
}

std::vector<Step> emission_order(const std::vector<Statement>& statements,
                                 const std::set<ex, GiNaC::ex_is_less>& needed,
                                 const std::vector<ex>& outputs,
                                 const std::vector<bool>& after_checks, Readiness readiness) {
  if (after_checks.size() != outputs.size())
    throw std::logic_error("emission_order: one after_checks flag per output");
  const size_t n = statements.size();
  std::map<ex, size_t, GiNaC::ex_is_less> definition;  // symbol -> index of its definition
  for (size_t i = 0; i < n; ++i)
    if (statements[i].kind == Statement::Kind::define && needed.count(statements[i].symbol))
      definition[statements[i].symbol] = i;
  auto reads = [&](const ex& e) {
    std::set<size_t> found;
    for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it)
      if (auto d = definition.find(*it); d != definition.end()) found.insert(d->second);
    return found;
  };
  std::vector<std::set<size_t>> statement_reads(n);
  for (size_t i = 0; i < n; ++i) {
    if (!needed.count(statements[i].symbol)) continue;
    const Statement& st = statements[i];
    statement_reads[i] = st.kind == Statement::Kind::define ? reads(st.value) : reads(st.symbol);
    statement_reads[i].erase(i);
  }

  std::vector<long> position(n, -1);
  if (readiness == Readiness::latency) {
    const std::vector<size_t> latency = latency_order(statements, needed);
    for (size_t k = 0; k < latency.size(); ++k) position[latency[k]] = static_cast<long>(k);
  } else {
    for (size_t i = 0; i < n; ++i) position[i] = static_cast<long>(i);
  }

  // Roots with the position at which they become ready; ties keep checks before outputs and
  // each in its own order (deterministic).
  struct Root {
    long ready;
    int rank;  // 0 check, 1 output, 2 output after the checks
    size_t index;
  };
  std::vector<Root> roots;
  for (size_t i = 0; i < n; ++i)
    if (needed.count(statements[i].symbol) && statements[i].kind != Statement::Kind::define)
      roots.push_back({position[i], 0, i});
  constexpr long kLast = std::numeric_limits<long>::max();
  for (size_t o = 0; o < outputs.size(); ++o) {
    long ready = -1;
    for (size_t r : reads(outputs[o])) ready = std::max(ready, position[r]);
    roots.push_back({after_checks[o] ? kLast : ready, after_checks[o] ? 2 : 1, o});
  }
  std::stable_sort(roots.begin(), roots.end(), [](const Root& a, const Root& b) {
    return a.ready != b.ready ? a.ready < b.ready
           : a.rank != b.rank ? a.rank < b.rank
                              : a.index < b.index;
  });

  std::vector<Step> order;
  std::vector<bool> emitted(n, false);
  // Depth first without recursion (chains are thousands of statements long): a statement is
  // printed once everything it reads is, its reads visited the most recently written first.
  auto emit = [&](const std::set<size_t>& first_reads) {
    std::vector<std::pair<size_t, bool>> stack;  // (statement, its reads already pushed)
    for (size_t r : first_reads) stack.push_back({r, false});
    while (!stack.empty()) {
      auto [i, expanded] = stack.back();
      stack.pop_back();
      if (emitted[i]) continue;
      if (expanded) {
        emitted[i] = true;
        order.push_back({false, i});
        continue;
      }
      stack.push_back({i, true});
      for (size_t r : statement_reads[i])
        if (!emitted[r]) stack.push_back({r, false});
    }
  };
  for (const Root& root : roots) {
    if (root.rank == 0) {
      emit(statement_reads[root.index]);
      emitted[root.index] = true;
      order.push_back({false, root.index});
    } else {
      emit(reads(outputs[root.index]));
      order.push_back({true, root.index});
    }
  }
  return order;
}

}  // namespace mechgen::gen
