// Straight-line C++ code for a templated scalar T, printed from GiNaC expressions with
// common-subexpression elimination and a byte-for-byte deterministic layout.
//
// A CodeBlock is a list of statements in program order:
//   define(name, e)   ->  const T name = <e>;            (a named intermediate)
//   guard(v, op, s)   ->  if (!(<v> op T(0))) s           (a check, e.g. a discriminant)
//   assign(target, e) ->  target = <e>;                   (an output)
// render() prints them in that order. A subexpression used twice or more anywhere in the block
// becomes `const T _tmpN = ...;`, emitted lazily right before the first statement that needs it
// (N counts in emission order). Nothing is ever moved above a statement that precedes its first
// use, so a computation that only follows a guard (e.g. `sqrt(disc_g3)`) is never hoisted above
// that guard.
//
// Printing:
//   * symbols print as their GiNaC name verbatim (`p.l8`, `in.theta8`, `th_l7`); to refer to a
//     define()d intermediate, use a symbol named like it;
//   * numbers: integers `T(2)`; rationals exactly representable as a double `T(0.5)`; other
//     rationals `T(1)/T(3)`; floating-point numbers as their shortest round-trip literal
//     (`T(0.1)`); Pi as `T(3.14159265358979323846)`; a negative number as `-T(2)`;
//   * `x^2` as `x*x`, `x^n` for n <= 8 as products that reuse the lower powers (`(x*x)*x`,
//     `(x*x)*(x*x)`, so a shared `x*x` becomes a temporary), `x^(1/2)` as `sqrt(x)`,
//     `x^(k+1/2)` as `x^k*sqrt(x)` (`x*sqrt(x)`), a negative power as a division by the
//     positive one (`T(1)/x`, `a/(x*x)`, `T(1)/sqrt(x)`), other powers as `pow(x, ...)`;
//   * sums `a + b - c`, products `T(2)*a*b/(c*d)`; nested products are parenthesised;
//   * a denominator shared by two or more printed products is inverted once, where it is first
//     needed (`const T _tmpN = T(1)/x;`), and those products multiply by it (`a*_tmpN`): a
//     division costs several multiplications and the compiler may not do this itself without
//     -ffast-math; the result differs from a/x by about an ulp;
//   * a sum and its negation are one subexpression (GiNaC itself flips the sign of sums inside
//     products, (a - b)*c or -(b - a)*c, depending on its run-dependent term order): the
//     orientation whose first term by printed text is added is kept, the other prints as its
//     negation (`-_tmp0`, or `b - a` when inline);
//   * functions sin cos tan asin acos atan atan2 sinh cosh tanh exp log abs (and sqrt, pow)
//     are called unqualified: the kernel must say `using std::sin;` etc. (see math_functions())
//     so that argument-dependent lookup finds the overloads of other scalar types.
// The operands of every sum and product are ordered by their printed text, never by GiNaC's
// hash order (which changes from run to run), so equal input prints equal output in every process;
// a product prints its numbers first, then the factors that depend on parameters (`p.` symbols)
// only, then the rest, so that the compiler can share and hoist the leading invariant part.
// (Only the printing is canonical: callers should still derive with canonical operations such as
// expand(); normal() or collect() may choose differently shaped results from run to run.)
//
// Errors (unknown functions, derivatives of abstract functions, complex numbers, constants other
// than Pi, invalid names, an intermediate used before its definition, ...) throw
// std::runtime_error naming the culprit; nothing is guessed.
#pragma once

#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <ginac/ginac.h>

namespace mechgen::gen {

class CodeBlock {
 public:
  /// @param temp_prefix prefix of the temporaries' names (`_tmp` gives `_tmp0, _tmp1, ...`);
  ///        change it when several blocks share one C++ scope. Move-only; a moved-from block
  ///        may only be destroyed or assigned to.
  explicit CodeBlock(std::string temp_prefix = "_tmp");
  ~CodeBlock();
  CodeBlock(CodeBlock&&) noexcept;
  CodeBlock& operator=(CodeBlock&&) noexcept;
  CodeBlock(const CodeBlock&) = delete;
  CodeBlock& operator=(const CodeBlock&) = delete;

  /// Prints every non-constant denominator as a reciprocal (`T(1)/x` once, then `a*_tmpN`), not
  /// only shared ones: the division then starts as soon as x is known instead of waiting for a,
  /// which takes it off a long dependency chain such as a Newton-Euler elimination.
  void invert_every_denominator();

  /// `const T name = <e>;` at this point of the program. `name` must be a C++ identifier not
  /// yet defined, not yet used by an earlier statement and not starting with the temp prefix.
  void define(const std::string& name, const GiNaC::ex& e);

  /// `if (!(<value> <comparison> T(0))) <on_fail_statement>`, e.g.
  /// guard(disc_g3, ">=", "return Status::unreachable_g3;"). The negated form also fails on
  /// NaN. comparison is one of < <= > >= == !=; on_fail_statement is one line, verbatim.
  void guard(const GiNaC::ex& value, const std::string& comparison,
             const std::string& on_fail_statement);
  /// As above, comparing against an arbitrary right-hand side.
  void guard(const GiNaC::ex& lhs, const std::string& comparison, const GiNaC::ex& rhs,
             const std::string& on_fail_statement);

  /// `target = <e>;` (target verbatim, e.g. `out.theta3`); each target is assigned once.
  void assign(const std::string& target, const GiNaC::ex& e);

  /// The statements, one per line, each prefixed with `indent` and ended by '\n'.
  std::string render(const std::string& indent) const;
  /// The same with each guard printed by `guard_line(condition, on_fail_statement)` instead of
  /// `if (!(condition)) on_fail_statement`, e.g. as a branch-free select for a vectorised loop.
  using GuardPrinter = std::function<std::string(const std::string& condition,
                                                 const std::string& on_fail_statement)>;
  std::string render(const std::string& indent, const GuardPrinter& guard_line) const;

  /// Arithmetic cost of the rendered code: each binary + - * / and each function call (sqrt,
  /// sin, pow, ...) counts one; unary minus and comparisons count nothing.
  int op_count() const;

  /// Number of `_tmpN` temporaries render() emits.
  int temporary_count() const;

  /// The unqualified math functions render() calls (e.g. {"cos", "sin", "sqrt"}), sorted, so
  /// the caller can emit exactly the `using std::...;` declarations it needs.
  std::set<std::string> math_functions() const;

  /// define()d names that no later statement refers to, in definition order (the compiler
  /// would warn about them as unused variables).
  std::vector<std::string> unused_definitions() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mechgen::gen
