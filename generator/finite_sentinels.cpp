#include "finite_sentinels.hpp"

#include <set>
#include <string>

namespace mechgen::gen {

namespace {

using GiNaC::ex;
using GiNaC::is_a;

// The symbols a non-finite value of which makes e non-finite: reached through sums, products
// and positive integer powers only.
void propagating_symbols(const ex& e, std::vector<ex>& out) {
  if (is_a<GiNaC::symbol>(e)) {
    out.push_back(e);
  } else if (is_a<GiNaC::add>(e) || is_a<GiNaC::mul>(e)) {
    for (size_t i = 0; i < e.nops(); ++i) propagating_symbols(e.op(i), out);
  } else if (is_a<GiNaC::power>(e) && e.op(1).info(GiNaC::info_flags::posint)) {
    propagating_symbols(e.op(0), out);
  }
}

// x for a value x or -x (a symbol), else an empty ex.
ex plain_symbol(const ex& value) {
  if (is_a<GiNaC::symbol>(value)) return value;
  if (is_a<GiNaC::symbol>(-value)) return -value;
  return ex();
}

bool is_input(const ex& symbol) {
  return GiNaC::ex_to<GiNaC::symbol>(symbol).get_name().rfind("in.", 0) == 0;
}

}  // namespace

std::vector<size_t> finite_sentinels(const std::vector<ex>& values,
                                     const SymbolDefinitions& definitions) {
  // Every symbol some output's value carries a non-finite value from, not counting an output's
  // own symbol (only what its definition reads).
  std::set<ex, GiNaC::ex_is_less> reached;
  std::vector<ex> pending, found;
  auto reach_from = [&](const ex& e) {
    found.clear();
    propagating_symbols(e, found);
    for (const ex& x : found)
      if (reached.insert(x).second) pending.push_back(x);
  };
  for (const ex& value : values) {
    const ex x = plain_symbol(value);
    if (x.is_zero()) {
      reach_from(value);
    } else if (const auto it = definitions.find(x); it != definitions.end()) {
      reach_from(it->second);
    }
  }
  while (!pending.empty()) {
    const ex x = pending.back();
    pending.pop_back();
    if (const auto it = definitions.find(x); it != definitions.end()) reach_from(it->second);
  }
  std::vector<size_t> kept;
  for (size_t i = 0; i < values.size(); ++i) {
    const ex x = plain_symbol(values[i]);
    if (!x.is_zero() && (reached.count(x) || is_input(x))) continue;
    kept.push_back(i);
  }
  return kept;
}

}  // namespace mechgen::gen
