// Fast double evaluation of a GiNaC expression of one symbol (time): the expression is compiled
// once into a flat postfix program (constants, t, sums, products, powers and the elementary
// functions of the model format), so that a sample costs a few hundred floating-point operations
// instead of a symbolic substitution and an arbitrary-precision evalf. Expressions outside that
// set fall back to GiNaC's own evaluation.
#pragma once

#include <ginac/ginac.h>

#include <memory>
#include <vector>

#include "model/cubic_spline.hpp"

namespace mechgen::numeric {

class TimeExpression {
 public:
  TimeExpression() = default;
  // `e` may contain no symbol but `t` (substitute the parameters first).
  TimeExpression(const GiNaC::ex& e, const GiNaC::symbol& t);
  // A table driver's motion: the spline's value (derivative 0) or its first or second derivative;
  // throws std::domain_error outside the table's time range (model/cubic_spline.hpp).
  TimeExpression(std::shared_ptr<const CubicSpline> spline, int derivative);

  // The value at time t; NaN when it is not a finite real number. Throws what GiNaC throws on the
  // fallback path.
  double operator()(double t) const;
  bool compiled() const { return compiled_; }
  bool depends_on_time() const { return depends_on_time_; }
  const GiNaC::ex& expression() const { return ex_; }

 private:
  enum class Op : unsigned char {
    constant,
    time,
    add,
    mul,
    powi,
    pow,
    sqrt,
    atan2,
    sin,
    cos,
    tan,
    asin,
    acos,
    atan,
    exp,
    log,
    abs,
    sinh,
    cosh,
    tanh,
  };
  struct Instruction {
    Op op;
    int n = 0;     // operand count (add, mul), exponent (powi)
    double c = 0;  // constant
  };
  bool compile(const GiNaC::ex& e, int& depth);
  void emit(Op op, int n, double c, int pops, int& depth);

  GiNaC::ex ex_;
  GiNaC::symbol t_;
  bool compiled_ = false, depends_on_time_ = false;
  std::shared_ptr<const CubicSpline> spline_;
  int derivative_ = 0;
  std::vector<Instruction> program_;
  int max_depth_ = 0;
};

}  // namespace mechgen::numeric
