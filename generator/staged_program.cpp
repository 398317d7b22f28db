#include "staged_program.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace mechgen::gen {

namespace {

// The distinct symbols of e, in the order of a preorder walk.
std::vector<GiNaC::symbol> symbols_in(const GiNaC::ex& e) {
  std::vector<GiNaC::symbol> symbols;
  for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it) {
    if (!GiNaC::is_a<GiNaC::symbol>(*it)) continue;
    const GiNaC::symbol& s = GiNaC::ex_to<GiNaC::symbol>(*it);
    bool seen = false;
    for (const GiNaC::symbol& other : symbols) seen = seen || other.is_equal(s);
    if (!seen) symbols.push_back(s);
  }
  return symbols;
}

}  // namespace

using GiNaC::ex;

void StagedProgram::declare(const GiNaC::symbol& s, const ex& derivative) {
  declared_[s] = derivative;
}

void StagedProgram::declare(const GiNaC::symbol& s, const ex& derivative, double value) {
  declared_[s] = derivative;
  for (GiNaC::exmap& sample : samples_) sample[s] = value;
}

GiNaC::symbol StagedProgram::define(const std::string& name, const ex& value) {
  GiNaC::symbol s(name);
  info_[s] = Info{name, value, false, ex(0), false};
  statements_.push_back({Statement::Kind::define, s, value, "", -1, false});
  evaluate(s, value);
  return s;
}

GiNaC::symbol StagedProgram::define(const std::string& name, const ex& value,
                                    const ex& derivative) {
  GiNaC::symbol s = define(name, value);
  set_derivative(s, derivative);
  return s;
}

void StagedProgram::set_derivative(const GiNaC::symbol& s, const ex& derivative) {
  // A derivative that is an expression is named (<name>_d), so that the next derivative
  // differentiates a name and its definition (with the quotient rule for d/dt sqrt(x) =
  // x_d / (2 sqrt(x))) instead of the expression inlined wherever it occurs.
  ex named = derivative;
  if (!GiNaC::is_a<GiNaC::symbol>(derivative) && !GiNaC::is_a<GiNaC::numeric>(derivative))
    named = define(info_.at(s).name + "_d", derivative);
  Info& info = info_.at(s);  // define() may have rebalanced the map: look up again
  info.explicit_derivative = true;
  info.derivative = named;
}

void StagedProgram::check_nonzero(const GiNaC::symbol& value, const std::string& failure,
                                  int group) {
  statements_.push_back({Statement::Kind::check_nonzero, value, ex(0), failure, group, false});
}

void StagedProgram::check_positive(const GiNaC::symbol& value, const std::string& failure,
                                   int group) {
  statements_.push_back({Statement::Kind::check_positive, value, ex(0), failure, group, false});
}

void StagedProgram::check_positive_kept(const GiNaC::symbol& value, const std::string& failure,
                                        int group) {
  check_positive(value, failure, group);
  statements_.back().keep = true;
}

// The samples map symbols only: exact lookups (GiNaC's default matches every key as a pattern at
// every node, quadratic in the parameter and statement count).
constexpr unsigned kSymbolSubs =
    GiNaC::subs_options::no_pattern | GiNaC::subs_options::pattern_is_not_product;

void StagedProgram::evaluate(const GiNaC::symbol& s, const ex& value) {
  for (GiNaC::exmap& sample : samples_) {
    const ex v = value.subs(sample, kSymbolSubs).evalf();
    double number = std::numeric_limits<double>::quiet_NaN();
    if (GiNaC::is_a<GiNaC::numeric>(v) && GiNaC::ex_to<GiNaC::numeric>(v).is_real())
      number = GiNaC::ex_to<GiNaC::numeric>(v).to_double();
    sample[s] = number;
  }
}

double StagedProgram::value(const ex& e, size_t sample) const {
  const ex v = e.subs(samples_.at(sample), kSymbolSubs).evalf();
  if (GiNaC::is_a<GiNaC::numeric>(v) && GiNaC::ex_to<GiNaC::numeric>(v).is_real())
    return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
  return std::numeric_limits<double>::quiet_NaN();
}

ex StagedProgram::derivative_of_symbol(const GiNaC::symbol& s) {
  if (auto d = declared_.find(s); d != declared_.end()) return d->second;
  auto it = info_.find(s);
  if (it == info_.end())
    throw std::logic_error("time derivative of an undeclared symbol '" + s.get_name() + "'");
  if (it->second.explicit_derivative || it->second.staged) return it->second.derivative;
  // Stage d/dt of the definition as a new named quantity, <name>_d (or <base>_dd).
  const std::string name = it->second.name;
  const std::string derived_name =
      name.size() > 2 && name.compare(name.size() - 2, 2, "_d") == 0 ? name + "d" : name + "_d";
  const ex value = quotient_derivative(s, name, it->second.value);
  ex staged;
  if (GiNaC::is_a<GiNaC::numeric>(value) || GiNaC::is_a<GiNaC::symbol>(value)) {
    staged = value;  // nothing to name
  } else {
    staged = define(derived_name, value);
  }
  Info& info = info_.at(s);  // define() may have rebalanced the map: look up again
  info.staged = true;
  info.derivative = staged;
  return staged;
}

// d/dt of a definition `value` = R + N/D (D time-dependent, N/D every term over D): stages
// q = N/D with the quotient rule q_d = (N_d - q D_d)/D, whose own derivative follows the same rule,
// instead of differentiating N/D as a whole (which doubles the terms at each order: PASIBOT's
// second derivatives of dyad points had some 60 operations each). Falls back to derivative()
// unless exactly one time-dependent denominator occurs (a name must not depend on GiNaC's
// run-dependent term order).
ex StagedProgram::quotient_derivative(const GiNaC::symbol& s, const std::string& name,
                                      const ex& value) {
  std::vector<ex> terms;
  if (GiNaC::is_a<GiNaC::add>(value)) {
    for (size_t i = 0; i < value.nops(); ++i) terms.push_back(value.op(i));
  } else {
    terms.push_back(value);
  }
  ex denominator;
  bool found = false;
  ex numerator = 0, rest = 0;
  for (const ex& term : terms) {
    ex base;
    int count = 0;
    const size_t factors = GiNaC::is_a<GiNaC::mul>(term) ? term.nops() : 1;
    for (size_t i = 0; i < factors; ++i) {
      const ex f = GiNaC::is_a<GiNaC::mul>(term) ? term.op(i) : term;
      if (GiNaC::is_a<GiNaC::power>(f) && f.op(1).is_equal(-1) &&
          !GiNaC::is_a<GiNaC::numeric>(f.op(0)) && !derivative(f.op(0)).is_zero()) {
        base = f.op(0);
        ++count;
      }
    }
    if (count > 1) return derivative(value);
    if (count == 0) {
      rest += term;
      continue;
    }
    if (found && !base.is_equal(denominator)) return derivative(value);
    denominator = base;
    found = true;
    numerator += term * denominator;  // GiNaC cancels D^-1 * D
  }
  if (!found) return derivative(value);
  const ex d_d = derivative(denominator);
  // s = N/D itself: its derivative (N_d - s D_d)/D, named by the caller.
  if (rest.is_zero()) return (derivative(numerator) - s * d_d) * GiNaC::pow(denominator, -1);
  const GiNaC::symbol q = define(name + "_q", numerator * GiNaC::pow(denominator, -1));
  const ex q_d = (derivative(numerator) - q * d_d) * GiNaC::pow(denominator, -1);
  const std::string derived = name + "_q_d";
  set_derivative(q, GiNaC::is_a<GiNaC::numeric>(q_d) ? q_d : ex(define(derived, q_d)));
  return derivative(rest) + derivative_of_symbol(q);
}

ex StagedProgram::derivative(const ex& e) {
  // Visit the symbols by name, not in GiNaC's order (hash based, different in every process): the
  // derivatives staged on the way are named and emitted in this order.
  std::vector<GiNaC::symbol> symbols = symbols_in(e);
  std::stable_sort(
      symbols.begin(), symbols.end(),
      [](const GiNaC::symbol& a, const GiNaC::symbol& b) { return a.get_name() < b.get_name(); });
  for (const GiNaC::symbol& s : symbols) derivative_of_symbol(s);
  return merged_like_terms(structural_derivative(e));
}

// Terms equal up to the orientation of their sums ((a - b) c and -(b - a) c), which GiNaC merges
// or not depending on its run-dependent term order, merged here: 2 t either way, so the printed
// code is the same in every process.
ex StagedProgram::merged_like_terms(const ex& e) {
  if (!GiNaC::is_a<GiNaC::add>(e)) return e;
  std::vector<ex> terms;
  std::vector<GiNaC::numeric> counts;
  for (size_t i = 0; i < e.nops(); ++i) {
    const ex t = e.op(i);
    bool merged = false;
    for (size_t k = 0; k < terms.size() && !merged; ++k) {
      if ((t - terms[k]).expand().is_zero()) {
        counts[k] += 1;
        merged = true;
      } else if ((t + terms[k]).expand().is_zero()) {
        counts[k] -= 1;
        merged = true;
      }
    }
    if (!merged) {
      terms.push_back(t);
      counts.push_back(1);
    }
  }
  ex sum = 0;
  for (size_t k = 0; k < terms.size(); ++k) sum += counts[k] * terms[k];
  return sum;
}

// d/dt by the structure of e, every symbol's derivative already staged: a product keeps its
// factors, (c A)' = c_d A + c A_d with the sum A and A_d intact (shared by the printer), where the
// chain rule symbol by symbol would multiply c into every term of A_d.
ex StagedProgram::structural_derivative(const ex& e) {
  if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::constant>(e)) return 0;
  if (GiNaC::is_a<GiNaC::symbol>(e)) return derivative_of_symbol(GiNaC::ex_to<GiNaC::symbol>(e));
  if (GiNaC::is_a<GiNaC::add>(e)) {
    ex sum = 0;
    for (size_t i = 0; i < e.nops(); ++i) sum += structural_derivative(e.op(i));
    return sum;
  }
  if (GiNaC::is_a<GiNaC::mul>(e)) {
    ex sum = 0;
    for (size_t i = 0; i < e.nops(); ++i) {
      const ex d = structural_derivative(e.op(i));
      if (d.is_zero()) continue;
      ex others = 1;
      for (size_t j = 0; j < e.nops(); ++j)
        if (j != i) others *= e.op(j);
      sum += others * d;
    }
    return sum;
  }
  if (GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(1))) {
    const ex d = structural_derivative(e.op(0));
    return d.is_zero() ? ex(0) : e.op(1) * GiNaC::pow(e.op(0), e.op(1) - 1) * d;
  }
  // Functions and other powers: the chain rule through each symbol, as GiNaC differentiates.
  ex result = 0;
  const std::vector<GiNaC::symbol> symbols = symbols_in(e);
  for (const GiNaC::symbol& s : symbols) {
    const ex partial = e.diff(s);
    if (partial.is_zero()) continue;
    const ex ds = derivative_of_symbol(s);
    if (ds.is_zero()) continue;
    result += partial * ds;
  }
  return result;
}

}  // namespace mechgen::gen
