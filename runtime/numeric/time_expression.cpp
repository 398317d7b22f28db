#include "numeric/time_expression.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>

namespace mechgen::numeric {

namespace {

// GiNaC orders the operands of a sum or product by hashes seeded with type_info addresses, which
// move with address-space randomisation: the same model gives a different operand order in each
// process, and floating-point sums depend on order. Accumulating in the order of the values
// themselves makes the result the same in every run (issue 27 item 3). NaN sorts last so that
// the order stays a strict weak one.
void order_operands(double* first, int n) {
  std::sort(first, first + n, [](double a, double b) {
    if (std::isnan(a)) return false;
    if (std::isnan(b)) return true;
    return a < b || (a == b && std::signbit(a) && !std::signbit(b));
  });
}

}  // namespace

TimeExpression::TimeExpression(const GiNaC::ex& e, const GiNaC::symbol& t)
    : ex_(e), t_(t), depends_on_time_(e.has(t)) {
  int depth = 0;
  compiled_ = compile(ex_, depth) && depth == 1;
  if (!compiled_) program_.clear();
}

TimeExpression::TimeExpression(std::shared_ptr<const CubicSpline> spline, int derivative)
    : compiled_(true),
      depends_on_time_(true),
      spline_(std::move(spline)),
      derivative_(derivative) {}

void TimeExpression::emit(Op op, int n, double c, int pops, int& depth) {
  program_.push_back({op, n, c});
  depth += 1 - pops;
  max_depth_ = std::max(max_depth_, depth);
}

bool TimeExpression::compile(const GiNaC::ex& e, int& depth) {
  if (GiNaC::is_a<GiNaC::numeric>(e)) {
    const GiNaC::numeric& n = GiNaC::ex_to<GiNaC::numeric>(e);
    if (!n.is_real()) return false;
    emit(Op::constant, 0, n.to_double(), 0, depth);
    return true;
  }
  if (GiNaC::is_a<GiNaC::constant>(e)) {
    const GiNaC::ex v = e.evalf();
    if (!GiNaC::is_a<GiNaC::numeric>(v)) return false;
    emit(Op::constant, 0, GiNaC::ex_to<GiNaC::numeric>(v).to_double(), 0, depth);
    return true;
  }
  if (GiNaC::is_a<GiNaC::symbol>(e)) {
    if (!e.is_equal(t_)) return false;
    emit(Op::time, 0, 0, 0, depth);
    return true;
  }
  if (GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e)) {
    const int n = static_cast<int>(e.nops());
    for (int i = 0; i < n; ++i)
      if (!compile(e.op(static_cast<size_t>(i)), depth)) return false;
    emit(GiNaC::is_a<GiNaC::add>(e) ? Op::add : Op::mul, n, 0, n, depth);
    return true;
  }
  if (GiNaC::is_a<GiNaC::power>(e)) {
    const GiNaC::ex base = e.op(0), exponent = e.op(1);
    if (!compile(base, depth)) return false;
    if (GiNaC::is_a<GiNaC::numeric>(exponent)) {
      const GiNaC::numeric& k = GiNaC::ex_to<GiNaC::numeric>(exponent);
      if (k.is_integer() && std::abs(k.to_double()) <= 64) {
        emit(Op::powi, static_cast<int>(k.to_int()), 0, 1, depth);
        return true;
      }
      if (k.is_rational() && (k * 2).is_integer() && std::abs(k.to_double()) <= 64) {
        // x^(m/2) = sqrt(x)^m
        emit(Op::sqrt, 0, 0, 1, depth);
        emit(Op::powi, static_cast<int>((k * 2).to_int()), 0, 1, depth);
        return true;
      }
    }
    if (!compile(exponent, depth)) return false;
    emit(Op::pow, 0, 0, 2, depth);
    return true;
  }
  if (GiNaC::is_a<GiNaC::function>(e)) {
    static const std::map<std::string, Op> unary = {
        {"sin", Op::sin},   {"cos", Op::cos},   {"tan", Op::tan},   {"asin", Op::asin},
        {"acos", Op::acos}, {"atan", Op::atan}, {"exp", Op::exp},   {"log", Op::log},
        {"abs", Op::abs},   {"sinh", Op::sinh}, {"cosh", Op::cosh}, {"tanh", Op::tanh},
    };
    const std::string name = GiNaC::ex_to<GiNaC::function>(e).get_name();
    if (name == "atan2" && e.nops() == 2) {
      if (!compile(e.op(0), depth) || !compile(e.op(1), depth)) return false;
      emit(Op::atan2, 0, 0, 2, depth);
      return true;
    }
    const auto it = unary.find(name);
    if (it == unary.end() || e.nops() != 1) return false;
    if (!compile(e.op(0), depth)) return false;
    emit(it->second, 0, 0, 1, depth);
    return true;
  }
  return false;
}

double TimeExpression::operator()(double t) const {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  if (spline_) return (*spline_)(t, derivative_);
  if (!compiled_) {
    const GiNaC::ex v = ex_.subs(t_ == GiNaC::numeric(t)).evalf();
    if (!GiNaC::is_a<GiNaC::numeric>(v)) return nan;
    const GiNaC::numeric& n = GiNaC::ex_to<GiNaC::numeric>(v);
    if (!n.is_real()) return nan;
    const double d = n.to_double();
    return std::isfinite(d) ? d : nan;
  }
  constexpr int small = 32;
  double local[small];
  std::vector<double> heap;
  double* stack = local;
  if (max_depth_ > small) {
    heap.resize(static_cast<size_t>(max_depth_));
    stack = heap.data();
  }
  int top = 0;  // number of values on the stack
  for (const Instruction& in : program_) {
    switch (in.op) {
      case Op::constant:
        stack[top++] = in.c;
        break;
      case Op::time:
        stack[top++] = t;
        break;
      case Op::add: {
        order_operands(stack + top - in.n, in.n);
        double s = 0;
        for (int i = top - in.n; i < top; ++i) s += stack[i];
        top -= in.n;
        stack[top++] = s;
        break;
      }
      case Op::mul: {
        order_operands(stack + top - in.n, in.n);
        double p = 1;
        for (int i = top - in.n; i < top; ++i) p *= stack[i];
        top -= in.n;
        stack[top++] = p;
        break;
      }
      case Op::powi: {
        const double x = stack[top - 1];
        int k = in.n < 0 ? -in.n : in.n;
        double r = 1, b = x;
        while (k) {
          if (k & 1) r *= b;
          b *= b;
          k >>= 1;
        }
        stack[top - 1] = in.n < 0 ? 1 / r : r;
        break;
      }
      case Op::pow:
        stack[top - 2] = std::pow(stack[top - 2], stack[top - 1]);
        --top;
        break;
      case Op::atan2:
        stack[top - 2] = std::atan2(stack[top - 2], stack[top - 1]);
        --top;
        break;
      case Op::sqrt:
        stack[top - 1] = std::sqrt(stack[top - 1]);
        break;
      case Op::sin:
        stack[top - 1] = std::sin(stack[top - 1]);
        break;
      case Op::cos:
        stack[top - 1] = std::cos(stack[top - 1]);
        break;
      case Op::tan:
        stack[top - 1] = std::tan(stack[top - 1]);
        break;
      case Op::asin:
        stack[top - 1] = std::asin(stack[top - 1]);
        break;
      case Op::acos:
        stack[top - 1] = std::acos(stack[top - 1]);
        break;
      case Op::atan:
        stack[top - 1] = std::atan(stack[top - 1]);
        break;
      case Op::exp:
        stack[top - 1] = std::exp(stack[top - 1]);
        break;
      case Op::log:
        stack[top - 1] = std::log(stack[top - 1]);
        break;
      case Op::abs:
        stack[top - 1] = std::abs(stack[top - 1]);
        break;
      case Op::sinh:
        stack[top - 1] = std::sinh(stack[top - 1]);
        break;
      case Op::cosh:
        stack[top - 1] = std::cosh(stack[top - 1]);
        break;
      case Op::tanh:
        stack[top - 1] = std::tanh(stack[top - 1]);
        break;
    }
  }
  const double v = stack[0];
  return std::isfinite(v) ? v : nan;
}

}  // namespace mechgen::numeric
