// The shared emission utilities: CodeBlock (printer + CSE + guards) and render_template.
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <ginac/ginac.h>
#include <gtest/gtest.h>

#include "code_block.hpp"
#include "template_renderer.hpp"

namespace {

using GiNaC::ex;
using GiNaC::symbol;
using mechgen::gen::CodeBlock;
using mechgen::gen::render_template;

// The right-hand side printed for a single output `r`.
std::string print(const ex& e) {
  CodeBlock b;
  b.assign("r", e);
  const std::string code = b.render("");
  EXPECT_EQ(code.substr(0, 4), "r = ") << code;
  EXPECT_EQ(code.substr(code.size() - 2), ";\n") << code;
  return code.substr(4, code.size() - 6);
}

// The message of the std::runtime_error `f` throws ("" if it does not throw).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    lines.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return lines;
}

// ---- printing of each construct ------------------------------------------------------------

TEST(CodeBlockPrint, Numbers) {
  EXPECT_EQ(print(ex(2)), "T(2)");
  EXPECT_EQ(print(ex(0)), "T(0)");
  EXPECT_EQ(print(ex(-3)), "-T(3)");
  EXPECT_EQ(print(GiNaC::numeric(1, 2)), "T(0.5)");
  EXPECT_EQ(print(GiNaC::numeric(3, 2)), "T(1.5)");
  EXPECT_EQ(print(GiNaC::numeric(-5, 4)), "-T(1.25)");
  EXPECT_EQ(print(GiNaC::numeric(1, 3)), "T(1)/T(3)");
  EXPECT_EQ(print(GiNaC::numeric(-2, 3)), "-T(2)/T(3)");
  EXPECT_EQ(print(GiNaC::numeric(0.1)), "T(0.1)");
  EXPECT_EQ(print(GiNaC::numeric(2.5e-7)), "T(2.5e-07)");
  EXPECT_EQ(print(GiNaC::Pi), "T(3.14159265358979323846)");
  // Integers beyond 2^53 become floating literals (the compiler rounds; no integer overflow).
  EXPECT_EQ(print(GiNaC::numeric("123456789012345678901234")), "T(123456789012345678901234.0)");
}

TEST(CodeBlockPrint, SymbolsVerbatim) {
  const symbol l8("p.l8"), th("in.theta8"), q("in.q[2]");
  EXPECT_EQ(print(l8 * GiNaC::cos(th)), "p.l8*cos(in.theta8)");  // parameters first
  EXPECT_EQ(print(q), "in.q[2]");
}

TEST(CodeBlockPrint, Powers) {
  const symbol x("x"), y("y");
  EXPECT_EQ(print(GiNaC::pow(x, 2)), "x*x");
  EXPECT_EQ(print(GiNaC::pow(x, 3)), "(x*x)*x");
  EXPECT_EQ(print(GiNaC::pow(x, -1)), "T(1)/x");
  EXPECT_EQ(print(GiNaC::pow(x, -2)), "T(1)/(x*x)");
  EXPECT_EQ(print(GiNaC::sqrt(x)), "sqrt(x)");
  EXPECT_EQ(print(GiNaC::pow(x, GiNaC::numeric(-1, 2))), "T(1)/sqrt(x)");
  EXPECT_EQ(print(GiNaC::pow(x, GiNaC::numeric(3, 2))), "x*sqrt(x)");
  EXPECT_EQ(print(GiNaC::pow(x, GiNaC::numeric(-5, 2))), "T(1)/((x*x)*sqrt(x))");
  EXPECT_EQ(print(GiNaC::pow(x, GiNaC::numeric(1, 3))), "pow(x, T(1)/T(3))");
  EXPECT_EQ(print(GiNaC::pow(x, GiNaC::numeric(-1, 3))), "T(1)/pow(x, T(1)/T(3))");
  EXPECT_EQ(print(GiNaC::pow(x, 9)), "pow(x, T(9))");
  EXPECT_EQ(print(GiNaC::pow(x, -9)), "T(1)/pow(x, T(9))");
  EXPECT_EQ(print(GiNaC::pow(x, y)), "pow(x, y)");
  EXPECT_EQ(print(GiNaC::pow(x, -y)), "pow(x, -y)");
  EXPECT_EQ(print(GiNaC::sqrt(ex(2))), "sqrt(T(2))");
  // A power of a sum squares the sum's temporary, never recomputes it.
  CodeBlock b;
  b.assign("r", GiNaC::pow(x + y, 2));
  EXPECT_EQ(b.render(""), "const T _tmp0 = x + y;\nr = _tmp0*_tmp0;\n");
  // Higher powers reuse the lower ones.
  CodeBlock c;
  c.assign("r", GiNaC::pow(x, 4));
  c.assign("s", GiNaC::pow(x, 5) * y);
  EXPECT_EQ(c.render(""),
            "const T _tmp0 = x*x;\n"
            "const T _tmp1 = _tmp0*_tmp0;\n"
            "r = _tmp1;\n"
            "s = (_tmp1*x)*y;\n");
  EXPECT_EQ(c.op_count(), 4);
}

TEST(CodeBlockPrint, Sums) {
  const symbol a("a"), b("b"), c("c");
  EXPECT_EQ(print(a - b), "a - b");
  EXPECT_EQ(print(b - a), "b - a");
  EXPECT_EQ(print(-a - b), "-a - b");
  EXPECT_EQ(print(c + b - a), "b + c - a");
  EXPECT_EQ(print(a + 1), "a + T(1)");
  EXPECT_EQ(print(a - 1), "a - T(1)");
  EXPECT_EQ(print(a - 2 * b * c), "a - T(2)*b*c");
  EXPECT_EQ(print(a - b / c), "a - b/c");
  EXPECT_EQ(print(a + GiNaC::numeric(1, 3)), "a + T(1)/T(3)");
}

TEST(CodeBlockPrint, Products) {
  const symbol a("a"), b("b"), c("c"), d("d");
  EXPECT_EQ(print(a * b / c), "a*b/c");
  EXPECT_EQ(print(2 * a * b / (c * d)), "T(2)*a*b/(c*d)");
  EXPECT_EQ(print(-a * b), "-a*b");
  EXPECT_EQ(print(-a), "-a");
  EXPECT_EQ(print(a / 2), "T(0.5)*a");
  EXPECT_EQ(print(a / 3), "a/T(3)");
  EXPECT_EQ(print(2 * a / 3), "T(2)*a/T(3)");
  EXPECT_EQ(print(1 / (3 * a)), "T(1)/(T(3)*a)");
  EXPECT_EQ(print(a * (b + c)), "a*(b + c)");
  EXPECT_EQ(print(a / (b + c)), "a/(b + c)");
  EXPECT_EQ(print(a * b * b / c), "a*(b*b)/c");
  EXPECT_EQ(print(GiNaC::Pi * a), "T(3.14159265358979323846)*a");
}

TEST(CodeBlockPrint, Functions) {
  const symbol x("x"), y("y");
  EXPECT_EQ(print(GiNaC::sin(x) + GiNaC::cos(y)), "cos(y) + sin(x)");
  EXPECT_EQ(print(GiNaC::tan(x)), "tan(x)");
  EXPECT_EQ(print(GiNaC::asin(x) - GiNaC::acos(y)), "asin(x) - acos(y)");
  EXPECT_EQ(print(GiNaC::atan(x)), "atan(x)");
  EXPECT_EQ(print(GiNaC::atan2(y, x - 1)), "atan2(y, x - T(1))");
  EXPECT_EQ(print(GiNaC::exp(x) * GiNaC::log(y)), "exp(x)*log(y)");
  EXPECT_EQ(print(GiNaC::abs(x)), "abs(x)");
  EXPECT_EQ(print(GiNaC::sinh(x)), "sinh(x)");
  EXPECT_EQ(print(GiNaC::sin(-x)), "sin(-x)");
  EXPECT_EQ(print(GiNaC::atan2(-y, x)), "atan2(-y, x)");

  CodeBlock b;
  b.assign("r", GiNaC::sin(x) * GiNaC::sqrt(y) + GiNaC::pow(x, y) + GiNaC::atan2(x, y));
  EXPECT_EQ(b.math_functions(), (std::set<std::string>{"atan2", "pow", "sin", "sqrt"}));
  EXPECT_EQ(b.op_count(), 7);  // 2 adds, 1 mul, 4 calls
}

// A denominator shared by two products is inverted once, after the guard that precedes its first
// use, and multiplied by; one used once stays a division.
TEST(CodeBlockPrint, SharedDenominatorBecomesOneReciprocal) {
  const symbol a("a"), b("b"), c("c"), d("d");
  CodeBlock block;
  block.guard(d, "!=", "return 1;");
  block.assign("r", a / (c + d));
  block.assign("s", b / (c + d) + a / d);
  EXPECT_EQ(block.render(""),
            "if (!(d != T(0))) return 1;\n"
            "const T _tmp0 = T(1)/(c + d);\n"
            "r = a*_tmp0;\n"
            "s = a/d + b*_tmp0;\n");
  EXPECT_EQ(block.op_count(), 6);  // c + d, its reciprocal, two products, a/d, the sum
}

TEST(CodeBlockPrint, UnsupportedIsAnError) {
  const symbol x("x");
  EXPECT_NE(error_of([&] { print(GiNaC::tgamma(x)); }).find("unknown function 'tgamma'"),
            std::string::npos);
  EXPECT_NE(error_of([&] { print(GiNaC::Euler * x); }).find("unsupported constant 'Euler'"),
            std::string::npos);
  EXPECT_NE(error_of([&] { print(GiNaC::I * x); }).find("complex"), std::string::npos);
  EXPECT_NE(error_of([&] { print(x == 1); }).find("unsupported expression"), std::string::npos);
  EXPECT_NE(error_of([&] { print(symbol("a b")); }).find("'a b'"), std::string::npos);
  EXPECT_NE(error_of([&] { print(symbol("_tmp3")); }).find("prefix"), std::string::npos);
}

// ---- common subexpressions, definitions, guards ---------------------------------------------

TEST(CodeBlockCse, RepeatedSubexpressionEmittedOnce) {
  const symbol l("p.l"), th("in.th"), a("a"), b("b");
  CodeBlock block;
  block.assign("out.x", l * GiNaC::cos(th) + GiNaC::pow(a + b, 2));
  block.assign("out.y", l * GiNaC::sin(th) * GiNaC::cos(th));
  block.assign("out.z", (a + b) * GiNaC::sin(th));
  EXPECT_EQ(block.render("  "),
            "  const T _tmp0 = a + b;\n"
            "  const T _tmp1 = cos(in.th);\n"
            "  out.x = _tmp0*_tmp0 + p.l*_tmp1;\n"
            "  const T _tmp2 = sin(in.th);\n"
            "  out.y = p.l*_tmp1*_tmp2;\n"
            "  out.z = _tmp0*_tmp2;\n");
  EXPECT_EQ(block.temporary_count(), 3);
  // cos, +, sin: 3; out.x: 1 mul + 1 add + 1 mul; out.y: 2 muls; out.z: 1 mul.
  EXPECT_EQ(block.op_count(), 9);
}

TEST(CodeBlockCse, OnlyUsedTemporariesAndNoneInsideATemporary) {
  // sin(x)*y occurs twice, so it is a temporary; sin(x) occurs only inside it: inline.
  const symbol x("x"), y("y"), z("z");
  CodeBlock block;
  block.assign("r0", GiNaC::sin(x) * y + z);
  block.assign("r1", GiNaC::sin(x) * y - z);
  EXPECT_EQ(block.render(""),
            "const T _tmp0 = sin(x)*y;\n"
            "r0 = _tmp0 + z;\n"
            "r1 = _tmp0 - z;\n");
  // A negated use shares the positive subexpression.
  CodeBlock neg;
  neg.assign("r0", x * y * z);
  neg.assign("r1", -x * y * z + 1);
  EXPECT_EQ(neg.render(""),
            "const T _tmp0 = x*y*z;\n"
            "r0 = _tmp0;\n"
            "r1 = T(1) - _tmp0;\n");
}

TEST(CodeBlockCse, BothSignsOfASumShareOneTemporary) {
  // GiNaC stores (b - a)*d as -(a - b)*d or (b - a)*d depending on its hash order; the block
  // picks one orientation from the printed text.
  const symbol a("a"), b("b"), c("c"), d("d");
  CodeBlock block;
  block.assign("r0", (a - b) * c);
  block.assign("r1", (b - a) * d);
  block.assign("r2", GiNaC::sqrt(b - a));
  block.assign("r3", GiNaC::pow(b - a, 3));
  EXPECT_EQ(block.render(""),
            "const T _tmp0 = a - b;\n"
            "r0 = _tmp0*c;\n"
            "r1 = -_tmp0*d;\n"
            "r2 = sqrt(-_tmp0);\n"
            "r3 = -(_tmp0*_tmp0)*_tmp0;\n");
  // Inline (not shared), the negated orientation prints as the sum it is.
  EXPECT_EQ(print(GiNaC::sqrt(b - a)), "sqrt(b - a)");
  EXPECT_EQ(print(GiNaC::atan2(b - a, c)), "atan2(b - a, c)");
}

TEST(CodeBlockCse, DefinitionNamesItsValue) {
  const symbol th("th"), s("s_th"), l("l");
  CodeBlock block;
  block.define("s_th", GiNaC::sin(th));
  // A later occurrence of the same expression prints the defined name.
  block.assign("out.a", l * GiNaC::sin(th));
  block.assign("out.b", s * s);
  EXPECT_EQ(block.render(""),
            "const T s_th = sin(th);\n"
            "out.a = l*s_th;\n"
            "out.b = s_th*s_th;\n");
  EXPECT_TRUE(block.unused_definitions().empty());
  EXPECT_EQ(block.math_functions(), (std::set<std::string>{"sin"}));

  CodeBlock unused;
  unused.define("a", l + 1);
  unused.define("b", l - 1);
  unused.assign("r", symbol("b") * 2);
  EXPECT_EQ(unused.unused_definitions(), (std::vector<std::string>{"a"}));
}

TEST(CodeBlockGuard, NothingIsHoistedAboveAGuard) {
  const symbol l1("p.l1"), l2("p.l2"), th("in.th"), disc("disc_g3");
  const ex c = GiNaC::cos(th);
  CodeBlock block;
  block.define("disc_g3", l2 * l2 - l1 * l1 * c * c);
  block.guard(disc, ">=", "return Status::unreachable_g3;");
  // sqrt(disc_g3) and l1*cos(th) are used twice, but only after the guard; cos(th) before it.
  block.assign("out.x", l1 * c + GiNaC::sqrt(disc));
  block.assign("out.y", (l1 * c - 1) * GiNaC::sqrt(disc));
  EXPECT_EQ(block.render(""),
            "const T _tmp0 = cos(in.th);\n"
            "const T disc_g3 = p.l2*p.l2 - (p.l1*p.l1)*(_tmp0*_tmp0);\n"
            "if (!(disc_g3 >= T(0))) return Status::unreachable_g3;\n"
            "const T _tmp1 = p.l1*_tmp0;\n"
            "const T _tmp2 = sqrt(disc_g3);\n"
            "out.x = _tmp1 + _tmp2;\n"
            "out.y = (_tmp1 - T(1))*_tmp2;\n");
}

TEST(CodeBlockGuard, TemporaryOfTheGuardedValueComesFirst) {
  const symbol a("a"), b("b");
  CodeBlock block;
  block.guard(a * a - b, ">", "return false;");
  block.guard(a * a - b, "<", 2 * b, "return false;");
  block.assign("r", GiNaC::sqrt(a * a - b));
  const std::vector<std::string> lines = lines_of(block.render("    "));
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], "    const T _tmp0 = a*a - b;");
  EXPECT_EQ(lines[1], "    if (!(_tmp0 > T(0))) return false;");
  EXPECT_EQ(lines[2], "    if (!(_tmp0 < T(2)*b)) return false;");
  EXPECT_EQ(lines[3], "    r = sqrt(_tmp0);");
}

TEST(CodeBlockErrors, MisuseIsReported) {
  const symbol x("x"), y("y");
  CodeBlock b;
  b.define("y2", y * y);
  EXPECT_NE(error_of([&] { b.define("y2", y); }).find("defined twice"), std::string::npos);
  EXPECT_NE(error_of([&] { b.define("z", symbol("z") + 1); }).find("refers to itself"),
            std::string::npos);
  b.assign("out", x + symbol("later"));
  EXPECT_NE(error_of([&] { b.define("later", y); }).find("before its definition"),
            std::string::npos);
  EXPECT_NE(error_of([&] { b.assign("out", x); }).find("assigned twice"), std::string::npos);
  EXPECT_NE(error_of([&] { b.define("p.x", x); }).find("not an identifier"), std::string::npos);
  EXPECT_NE(error_of([&] { b.define("_tmp1", x); }).find("prefix"), std::string::npos);
  EXPECT_NE(error_of([&] { b.guard(x, "=>", "return;"); }).find("comparison '=>'"),
            std::string::npos);
  EXPECT_NE(error_of([&] { b.guard(x, ">=", "return;\nfoo();"); }).find("one non-empty line"),
            std::string::npos);
  EXPECT_NE(error_of([] { CodeBlock bad("1x"); }).find("prefix"), std::string::npos);
}

TEST(CodeBlockErrors, UnknownFunctionInsideAnExpressionIsNamed) {
  const symbol x("x");
  CodeBlock b;
  const std::string message = error_of([&] { b.assign("r", 1 + GiNaC::sin(GiNaC::zeta(x))); });
  EXPECT_NE(message.find("unknown function 'zeta'"), std::string::npos) << message;
}

TEST(CodeBlockCse, TemporaryPrefixAndIndent) {
  const symbol x("x");
  CodeBlock b("_acc");
  b.assign("a", GiNaC::cos(x) * GiNaC::cos(x) + 1);
  b.assign("c", GiNaC::cos(x));
  EXPECT_EQ(b.render("\t"), "\tconst T _acc0 = cos(x);\n\ta = _acc0*_acc0 + T(1);\n\tc = _acc0;\n");
  EXPECT_EQ(CodeBlock().render("  "), "");
  EXPECT_EQ(CodeBlock().op_count(), 0);
}

// ---- the emitted code is valid C++ that computes the expressions --------------------------

// The block below, rendered, is pasted into sample_kernel(); the test pins the text (so a change
// of the printer shows up here) and compares the kernel's values with GiNaC's evalf.
struct SampleIn {
  double a, b;
};
struct SampleParams {
  double c;
};
struct SampleOut {
  double r0, r1, r2, r3;
};

struct SampleSymbols {
  symbol a{"in.a"}, b{"in.b"}, c{"p.c"}, d{"d_g1"};
  std::vector<ex> outputs() const {
    return {(b - a) * c + GiNaC::pow(a - b, 3) / c,
            GiNaC::sqrt(d) * GiNaC::atan2(b - a, c) - GiNaC::Pi / 3,
            GiNaC::pow(a * a + 1, GiNaC::numeric(3, 2)) / (2 * b) + GiNaC::pow(c, -2),
            GiNaC::exp(-a) * GiNaC::log(c) + GiNaC::abs(b) * GiNaC::pow(GiNaC::cos(a), 2) -
                GiNaC::pow(GiNaC::sin(a), 4)};
  }
  ex discriminant() const { return a * a - b / 7; }
};

template <class T>
bool sample_kernel(const SampleIn& in, const SampleParams& p, SampleOut& out) {
  using std::abs, std::atan2, std::cos, std::exp, std::log, std::sin, std::sqrt;
  // clang-format off
  const T _tmp0 = in.a*in.a;
  const T d_g1 = _tmp0 - in.b/T(7);
  if (!(d_g1 >= T(0))) return false;
  const T _tmp1 = in.a - in.b;
  out.r0 = ((_tmp1*_tmp1)*_tmp1)/p.c - p.c*_tmp1;
  out.r1 = atan2(-_tmp1, p.c)*sqrt(d_g1) - T(3.14159265358979323846)/T(3);
  const T _tmp2 = _tmp0 + T(1);
  out.r2 = T(0.5)*(_tmp2*sqrt(_tmp2))/in.b + T(1)/(p.c*p.c);
  const T _tmp3 = sin(in.a);
  const T _tmp4 = _tmp3*_tmp3;
  const T _tmp5 = cos(in.a);
  out.r3 = abs(in.b)*(_tmp5*_tmp5) + log(p.c)*exp(-in.a) - _tmp4*_tmp4;
  // clang-format on
  return true;
}

TEST(CodeBlockNumeric, EmittedCodeComputesTheExpressions) {
  const SampleSymbols s;
  CodeBlock block;
  block.define("d_g1", s.discriminant());
  block.guard(s.d, ">=", "return false;");
  const std::vector<ex> outputs = s.outputs();
  const std::vector<std::string> targets = {"out.r0", "out.r1", "out.r2", "out.r3"};
  for (std::size_t i = 0; i < outputs.size(); ++i) block.assign(targets[i], outputs[i]);
  const std::string expected =
      "  const T _tmp0 = in.a*in.a;\n"
      "  const T d_g1 = _tmp0 - in.b/T(7);\n"
      "  if (!(d_g1 >= T(0))) return false;\n"
      "  const T _tmp1 = in.a - in.b;\n"
      "  out.r0 = ((_tmp1*_tmp1)*_tmp1)/p.c - p.c*_tmp1;\n"
      "  out.r1 = atan2(-_tmp1, p.c)*sqrt(d_g1) - T(3.14159265358979323846)/T(3);\n"
      "  const T _tmp2 = _tmp0 + T(1);\n"
      "  out.r2 = T(0.5)*(_tmp2*sqrt(_tmp2))/in.b + T(1)/(p.c*p.c);\n"
      "  const T _tmp3 = sin(in.a);\n"
      "  const T _tmp4 = _tmp3*_tmp3;\n"
      "  const T _tmp5 = cos(in.a);\n"
      "  out.r3 = abs(in.b)*(_tmp5*_tmp5) + log(p.c)*exp(-in.a) - _tmp4*_tmp4;\n";
  ASSERT_EQ(block.render("  "), expected) << "update sample_kernel with the new text";
  EXPECT_EQ(block.math_functions(),
            (std::set<std::string>{"abs", "atan2", "cos", "exp", "log", "sin", "sqrt"}));

  const double a = 0.7, b = 0.3, c = 1.9;
  SampleOut out{};
  ASSERT_TRUE(sample_kernel<double>({a, b}, {c}, out));
  const GiNaC::lst at = {s.a == a, s.b == b, s.c == c,
                         s.d == s.discriminant().subs(GiNaC::lst{s.a == a, s.b == b})};
  const double got[] = {out.r0, out.r1, out.r2, out.r3};
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const double want = GiNaC::ex_to<GiNaC::numeric>(outputs[i].subs(at).evalf()).to_double();
    EXPECT_NEAR(got[i], want, 1e-14 * (1 + std::abs(want))) << targets[i];
  }
  // The guard: a negative discriminant, or NaN, stops before any output is written.
  SampleOut untouched{-1, -1, -1, -1};
  EXPECT_FALSE(sample_kernel<double>({0.1, 0.3}, {c}, untouched));
  EXPECT_FALSE(sample_kernel<double>({std::nan(""), 0.3}, {c}, untouched));
  EXPECT_EQ(untouched.r0, -1);
  // The same text compiles for another scalar type.
  SampleOut wide{};
  ASSERT_TRUE(sample_kernel<long double>({a, b}, {c}, wide));
  EXPECT_NEAR(wide.r3, out.r3, 1e-14);
}

// ---- determinism ---------------------------------------------------------------------------

// A small four-bar position block, with the symbols created in the order given by `order`
// (GiNaC's canonical operand order follows the symbols' serial numbers, i.e. creation order).
std::string four_bar_block(const std::vector<int>& order) {
  const std::vector<std::string> names = {"p.l1",  "p.l2",    "p.l3", "p.l4",
                                          "in.th", "disc_g1", "u_g1", "p.m"};
  std::map<std::string, symbol> s;
  for (int i : order) s.emplace(names[static_cast<std::size_t>(i)], symbol(names[i]));
  const ex l1 = s.at("p.l1"), l2 = s.at("p.l2"), l3 = s.at("p.l3"), l4 = s.at("p.l4");
  const ex th = s.at("in.th"), disc = s.at("disc_g1"), u = s.at("u_g1"), m = s.at("p.m");
  const ex ax = l1 * GiNaC::cos(th) - l4, ay = l1 * GiNaC::sin(th);
  const ex d2 = ax * ax + ay * ay;
  CodeBlock b;
  b.define("disc_g1", GiNaC::expand(4 * d2 * l2 * l2 - GiNaC::pow(d2 + l2 * l2 - l3 * l3, 2)));
  b.guard(disc, ">=", "return Status::unreachable_g1;");
  b.define("u_g1", (d2 + l2 * l2 - l3 * l3) / (2 * d2));
  b.assign("out.bx", ax * u - ay * GiNaC::sqrt(disc) / (2 * d2) + l4);
  b.assign("out.by", ay * u + ax * GiNaC::sqrt(disc) / (2 * d2));
  b.assign("out.e", GiNaC::expand(m * (ax * ax + ay * ay) * GiNaC::pow(u, 3) / 3 - GiNaC::Pi * m));
  b.assign("out.f", GiNaC::atan2(ay * u, ax * u - GiNaC::numeric(1, 2) * l4));
  return b.render("  ") + "// Total ops: " + std::to_string(b.op_count()) + "\n";
}

TEST(CodeBlockDeterminism, SameOutputWhateverTheSymbolCreationOrder) {
  const std::string first = four_bar_block({0, 1, 2, 3, 4, 5, 6, 7});
  EXPECT_EQ(four_bar_block({7, 6, 5, 4, 3, 2, 1, 0}), first);
  EXPECT_EQ(four_bar_block({4, 2, 7, 0, 5, 3, 6, 1}), first);
  EXPECT_EQ(four_bar_block({0, 1, 2, 3, 4, 5, 6, 7}), first);
  // The sums and powers that GiNaC normalises differently by order all occur in it.
  EXPECT_NE(first.find("const T u_g1 = "), std::string::npos);
  // 1/d2 is staged once for its three products (one op more than three divisions).
  EXPECT_NE(first.find("// Total ops: 135"), std::string::npos) << first;
}

// ---- templates -----------------------------------------------------------------------------

TEST(Template, SubstitutesAndReindents) {
  const std::string text =
      "// {{ banner }}\n"
      "void f(T x) {\n"
      "  {{body}}\n"
      "  return {{value}};  // {{value}}\n"
      "}\n";
  const std::string out = render_template(
      text,
      {{"banner", "do not edit"}, {"body", "const T a = x;\n\nconst T b = a*a;"}, {"value", "b"}},
      "f.hpp.in");
  EXPECT_EQ(out,
            "// do not edit\n"
            "void f(T x) {\n"
            "  const T a = x;\n"
            "\n"
            "  const T b = a*a;\n"
            "  return b;  // b\n"
            "}\n");
  // Values are not rescanned; single braces and '}}' are plain text.
  EXPECT_EQ(render_template("a{{x}}b { {1, 2} }}", {{"x", "{{y}}"}}, "t"), "a{{y}}b { {1, 2} }}");
  // Tabs before the placeholder are kept; the rest of the prefix becomes spaces.
  EXPECT_EQ(render_template("\tx = {{v}};", {{"v", "f(a,\nb)"}}, "t"), "\tx = f(a,\n\t    b);");
}

TEST(Template, ErrorsNameTheTemplateAndLine) {
  const std::string text = "line one\nline two {{known}}\nline {{unknwon}} three\n";
  EXPECT_EQ(error_of([&] {
              render_template(text, {{"known", "k"}}, "kernel.hpp.in");
            }),
            "template 'kernel.hpp.in', line 3: unknown placeholder '{{unknwon}}' (no value given)");
  EXPECT_EQ(error_of([&] {
              render_template(text, {{"known", "k"}, {"unknwon", "u"}, {"extra", "e"}}, "k.in");
            }),
            "template 'k.in': value 'extra' is never used (no {{extra}} in the template)");
  EXPECT_NE(error_of([] { render_template("a\n{{x y}}", {}, "t"); }).find("line 2: malformed"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              render_template("{{x\n}}", {{"x", ""}}, "t");
            }).find("line 1"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              render_template("{{{x}}}", {{"x", ""}}, "t");
            }).find("malformed"),
            std::string::npos);
}

}  // namespace
