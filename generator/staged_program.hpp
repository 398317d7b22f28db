// A straight-line program of named intermediate quantities, each defined by a small GiNaC
// expression of earlier ones. Time derivatives are staged too: the derivative of a quantity is a
// new named quantity defined from the derivatives of the symbols its expression uses (forward
// chain rule), so nothing is ever substituted into one large expression (no expression swell).
// Every definition is also evaluated at a few numeric sample configurations, which lets the
// generator pick branches and check pivots while it derives.
#pragma once

#include <ginac/ginac.h>

#include <map>
#include <string>
#include <vector>

namespace mechgen::gen {

struct Statement {
  enum class Kind { define, check_positive, check_nonzero };
  Kind kind = Kind::define;
  GiNaC::symbol symbol;  // define: the quantity; checks: the quantity checked
  GiNaC::ex value;       // define: its expression
  std::string failure;   // checks: the status returned otherwise ("unreachable", ...)
  int group = -1;        // checks: the solve group that fails
  // checks: emitted whenever the quantities it reads are computed, even though no output reads
  // it (an iterative group's final residual)
  bool keep = false;
};

class StagedProgram {
 public:
  // samples: numeric values of every parameter and input symbol, one map per configuration.
  explicit StagedProgram(std::vector<GiNaC::exmap> samples) : samples_(std::move(samples)) {}

  // A quantity given to the program (a parameter, a driver input): its time derivative is
  // `derivative` (0 for parameters, the next input for a driver coordinate).
  void declare(const GiNaC::symbol& s, const GiNaC::ex& derivative);
  // As above, for a symbol the samples do not hold yet: `value` at every sample (e.g. the start
  // of an iterative solve).
  void declare(const GiNaC::symbol& s, const GiNaC::ex& derivative, double value);

  // A new named quantity. Its time derivative is staged lazily as `<name>_d`, `<name>_dd`, unless
  // an explicit derivative expression is given (e.g. d/dt cos(th) = -sin(th) * th_d).
  GiNaC::symbol define(const std::string& name, const GiNaC::ex& value);
  GiNaC::symbol define(const std::string& name, const GiNaC::ex& value,
                       const GiNaC::ex& derivative);
  // Replaces the derivative of a defined quantity, for rules the chain rule cannot see through a
  // name (d/dt sqrt(x) = x_d / (2 sqrt(x)) written with the name of sqrt(x)).
  void set_derivative(const GiNaC::symbol& s, const GiNaC::ex& derivative);
  // The generated code returns `failure` for `group` unless `value` is > 0 (check_positive) or
  // nonzero (check_nonzero) here, before any later statement (e.g. a square root of it) runs.
  void check_positive(const GiNaC::symbol& value, const std::string& failure, int group);
  void check_nonzero(const GiNaC::symbol& value, const std::string& failure, int group);
  // check_positive, kept in the code whenever `value`'s own inputs are computed.
  void check_positive_kept(const GiNaC::symbol& value, const std::string& failure, int group);

  // Total time derivative of an expression of declared and defined symbols.
  GiNaC::ex derivative(const GiNaC::ex& e);

  double value(const GiNaC::ex& e, size_t sample) const;
  size_t sample_count() const { return samples_.size(); }
  const std::vector<Statement>& statements() const { return statements_; }
  bool is_defined(const GiNaC::symbol& s) const { return info_.count(s) > 0; }

 private:
  struct Info {
    std::string name;
    GiNaC::ex value;
    bool explicit_derivative = false;
    GiNaC::ex derivative;  // valid when explicit_derivative, or once the derivative is staged
    bool staged = false;
  };
  GiNaC::ex derivative_of_symbol(const GiNaC::symbol& s);
  GiNaC::ex structural_derivative(const GiNaC::ex& e);
  GiNaC::ex merged_like_terms(const GiNaC::ex& e);
  GiNaC::ex quotient_derivative(const GiNaC::symbol& s, const std::string& name,
                                const GiNaC::ex& value);
  void evaluate(const GiNaC::symbol& s, const GiNaC::ex& value);

  std::vector<GiNaC::exmap> samples_;
  std::map<GiNaC::ex, Info, GiNaC::ex_is_less> info_;
  std::map<GiNaC::ex, GiNaC::ex, GiNaC::ex_is_less> declared_;
  std::vector<Statement> statements_;
};

}  // namespace mechgen::gen
