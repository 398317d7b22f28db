#include "code_block.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace mechgen::gen {
namespace {

// Expressions are first translated into a DAG of our own nodes. A node's key is its complete
// printed text (children printed inline, never as temporaries), so equal keys mean equal code,
// and sorting operands by key gives an order that does not depend on GiNaC's hash order.
enum class Kind { Leaf, Neg, Add, Mul, Func, Pow };

// Binding strength of a node's printed text.
constexpr int kPrecAdd = 1;
constexpr int kPrecMul = 2;
constexpr int kPrecUnary = 3;
constexpr int kPrecAtom = 4;

// x^n for 2 <= n <= kMaxExpandedPower prints as a product; larger powers call pow.
constexpr int kMaxExpandedPower = 8;

const char* const kPiLiteral = "T(3.14159265358979323846)";

const std::set<std::string>& known_functions() {
  static const std::set<std::string> names = {"sin",  "cos",   "tan",  "asin",       "acos",
                                              "atan", "atan2", "sinh", "cosh",       "tanh",
                                              "exp",  "log",   "abs",  "branch_sign"};
  return names;
}

struct Node {
  Kind kind = Kind::Leaf;
  std::string key;
  int prec = kPrecAtom;
  std::vector<int> kids;   // Neg: {child}; Add: terms; Mul: numerator; Func, Pow: arguments
  int den = -1;            // Mul: denominator node, or -1
  std::string fname;       // Func, Pow: printed function name
  bool is_number = false;  // Leaf: a number or constant (as opposed to a symbol)
};

struct Statement {
  enum class Type { Define, Guard, Assign };
  Type type = Type::Define;
  std::string name;  // Define: variable; Assign: target
  int root = -1;     // Define, Assign: value; Guard: left-hand side
  int rhs = -1;      // Guard: right-hand side
  std::string comparison;
  std::string on_fail;
};

bool is_identifier(const std::string& s) {
  if (s.empty()) return false;
  auto head = [](char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; };
  if (!head(s[0])) return false;
  return std::all_of(s.begin() + 1, s.end(), [&](char c) {
    return head(c) || std::isdigit(static_cast<unsigned char>(c));
  });
}

// Symbol names may also use member access and subscripts: `p.l8`, `in.q[2]`.
bool is_symbol_name(const std::string& s) {
  if (s.empty()) return false;
  auto head = [](char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; };
  if (!head(s[0])) return false;
  return std::all_of(s.begin() + 1, s.end(), [&](char c) {
    return head(c) || std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == '[' ||
           c == ']';
  });
}

std::string to_text(const GiNaC::ex& e) {
  std::ostringstream os;
  os << e;
  return os.str();
}

// Decimal digits of a non-negative integer; beyond 2^53 a floating literal, so that the
// compiler rounds it (an integer literal could overflow).
std::string integer_literal(const GiNaC::numeric& n) {
  std::string digits = to_text(n);
  if (n.int_length() > 53) digits += ".0";
  return "T(" + digits + ")";
}

std::string shortest_double(double d) {
  if (!std::isfinite(d))
    throw std::runtime_error("CodeBlock: non-finite number " + std::to_string(d));
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, d);
  if (ec != std::errc()) throw std::runtime_error("CodeBlock: cannot print number");
  return std::string(buf, end);
}

// A positive rational whose value a double holds exactly (denominator a power of two).
bool is_exact_double(const GiNaC::numeric& r) {
  const GiNaC::numeric q = r.denom();
  const int bits = q.int_length();
  return r.numer().int_length() <= 53 && bits <= 64 &&
         q == GiNaC::pow(GiNaC::numeric(2), GiNaC::numeric(bits - 1));
}

std::string quote(const std::string& s) {
  return "'" + s + "'";
}

}  // namespace

struct CodeBlock::Impl {
  std::string temp_prefix;
  bool invert_every_denominator = false;
  std::vector<Node> nodes;
  std::map<std::string, int> by_key;
  std::vector<Statement> statements;
  std::set<std::string> defined;     // define()d names
  std::set<std::string> referenced;  // symbol names used by statements so far
  std::set<std::string> assigned;    // assign() targets
  std::vector<std::string> definition_order;
  std::set<std::string> referenced_after_definition;

  // ---- translation of GiNaC expressions --------------------------------------------------

  int intern(Node n) {
    auto it = by_key.find(n.key);
    if (it != by_key.end()) return it->second;
    nodes.push_back(std::move(n));
    const int id = static_cast<int>(nodes.size()) - 1;
    by_key.emplace(nodes.back().key, id);
    return id;
  }

  int leaf(const std::string& text, bool is_number) {
    Node n;
    n.key = text;
    n.is_number = is_number;
    return intern(std::move(n));
  }

  const Node& at(int id) const { return nodes[static_cast<std::size_t>(id)]; }

  std::string wrap(int id, bool parens) const {
    return parens ? "(" + at(id).key + ")" : at(id).key;
  }

  int negate(int id) {
    if (at(id).kind == Kind::Neg) return at(id).kids[0];
    const Node& c = at(id);
    Node n;
    n.kind = Kind::Neg;
    n.prec = kPrecUnary;
    n.kids = {id};
    n.key = "-" + wrap(id, c.prec < kPrecMul);
    return intern(std::move(n));
  }

  // A non-negative real number.
  int positive_number(const GiNaC::numeric& v) {
    if (v.is_integer()) return leaf(integer_literal(v), true);
    if (v.is_rational()) {
      if (is_exact_double(v)) return leaf("T(" + shortest_double(v.to_double()) + ")", true);
      Node n;
      n.key = integer_literal(v.numer()) + "/" + integer_literal(v.denom());
      n.prec = kPrecMul;
      n.is_number = true;
      return intern(std::move(n));
    }
    return leaf("T(" + shortest_double(v.to_double()) + ")", true);
  }

  int number(const GiNaC::numeric& v) {
    if (!v.is_real()) throw std::runtime_error("CodeBlock: complex number " + to_text(v));
    return v.is_negative() ? negate(positive_number(-v)) : positive_number(v);
  }

  // Sort key for product operands: numbers first, then by printed text.
  bool factor_less(int a, int b) const {
    if (at(a).is_number != at(b).is_number) return at(a).is_number;
    return at(a).key < at(b).key;
  }

  // A product of factors, or the single factor itself. The factors of a commutative product
  // are sorted; an expanded power x*...*x*sqrt(x) keeps its order.
  int product(std::vector<int> num, std::vector<int> den_factors, bool sort = true) {
    auto less = [this](int a, int b) { return factor_less(a, b); };
    if (sort) std::sort(num.begin(), num.end(), less);
    std::sort(den_factors.begin(), den_factors.end(), less);
    int den = -1;
    if (den_factors.size() == 1) den = den_factors[0];
    if (den_factors.size() > 1) den = product(std::move(den_factors), {});
    if (den < 0 && num.size() == 1) return num[0];
    Node n;
    n.kind = Kind::Mul;
    n.prec = kPrecMul;
    for (int f : num) {
      if (!n.key.empty()) n.key += "*";
      n.key += wrap(f, at(f).prec != kPrecAtom);
    }
    if (num.empty()) n.key = "T(1)";
    if (den >= 0) n.key += "/" + wrap(den, at(den).prec != kPrecAtom);
    n.kids = std::move(num);
    n.den = den;
    return intern(std::move(n));
  }

  // x^n, n >= 1, as products that reuse the lower powers: x^2 = x*x, x^3 = (x*x)*x,
  // x^4 = (x*x)*(x*x), so x^2 becomes a temporary when x^2 and x^4 both occur.
  int power_product(int base, int n) {
    if (n == 1) return base;
    if (n == 2) return product({base, base}, {}, false);
    if (n % 2 == 0) {
      const int half = power_product(base, n / 2);
      return product({half, half}, {}, false);
    }
    return product({power_product(base, n - 1), base}, {}, false);
  }

  int call(const std::string& fname, std::vector<int> args, Kind kind = Kind::Func) {
    Node n;
    n.kind = kind;
    n.fname = fname;
    n.key = fname + "(";
    for (std::size_t i = 0; i < args.size(); ++i) {
      if (i > 0) n.key += ", ";
      n.key += at(args[i]).key;
    }
    n.key += ")";
    n.kids = std::move(args);
    return intern(std::move(n));
  }

  int convert(const GiNaC::ex& e, std::set<std::string>& symbols) {
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
      const std::string name = GiNaC::ex_to<GiNaC::symbol>(e).get_name();
      if (!is_symbol_name(name))
        throw std::runtime_error("CodeBlock: symbol name " + quote(name) +
                                 " is not a C++ name (identifier, '.', '[', ']')");
      if (name.rfind(temp_prefix, 0) == 0)
        throw std::runtime_error("CodeBlock: symbol name " + quote(name) +
                                 " collides with the temporaries' prefix " + quote(temp_prefix));
      symbols.insert(name);
      return leaf(name, false);
    }
    if (GiNaC::is_a<GiNaC::numeric>(e)) return number(GiNaC::ex_to<GiNaC::numeric>(e));
    if (GiNaC::is_a<GiNaC::constant>(e)) {
      if (e.is_equal(GiNaC::Pi)) return leaf(kPiLiteral, true);
      throw std::runtime_error("CodeBlock: unsupported constant " + quote(to_text(e)));
    }
    if (GiNaC::is_a<GiNaC::add>(e)) return convert_sum(e, symbols);
    if (GiNaC::is_a<GiNaC::mul>(e) || GiNaC::is_a<GiNaC::power>(e)) {
      std::vector<GiNaC::ex> factors;
      if (GiNaC::is_a<GiNaC::mul>(e)) {
        for (std::size_t i = 0; i < e.nops(); ++i) factors.push_back(e.op(i));
      } else {
        factors.push_back(e);
      }
      return convert_product(factors, symbols);
    }
    if (GiNaC::is_a<GiNaC::fderivative>(e))
      throw std::runtime_error("CodeBlock: unsupported derivative of an abstract function " +
                               quote(to_text(e)));
    if (GiNaC::is_a<GiNaC::function>(e)) {
      const std::string name = GiNaC::ex_to<GiNaC::function>(e).get_name();
      if (known_functions().count(name) == 0)
        throw std::runtime_error("CodeBlock: unknown function " + quote(name) + " in " +
                                 quote(to_text(e)));
      std::vector<int> args;
      for (std::size_t i = 0; i < e.nops(); ++i) args.push_back(convert(e.op(i), symbols));
      return call(name, std::move(args));
    }
    throw std::runtime_error("CodeBlock: unsupported expression " + quote(to_text(e)));
  }

  // The terms of a sum as (subtracted, magnitude), in printing order: added terms, then
  // subtracted terms, then the constant, each group by printed text (a positive constant leads
  // if all other terms are subtracted). `flip` negates the sum.
  std::vector<std::pair<bool, int>> signed_terms(const std::vector<int>& terms, bool flip) const {
    std::vector<std::pair<bool, int>> out;
    for (int t : terms) {
      const bool neg = at(t).kind == Kind::Neg;
      out.emplace_back(neg != flip, neg ? at(t).kids[0] : t);
    }
    auto group = [this](const std::pair<bool, int>& t) {
      return at(t.second).is_number ? 2 : (t.first ? 1 : 0);
    };
    std::sort(out.begin(), out.end(), [&](const auto& a, const auto& b) {
      if (group(a) != group(b)) return group(a) < group(b);
      return at(a.second).key < at(b.second).key;
    });
    // T(1) - x rather than -x + T(1).
    if (out.front().first && at(out.back().second).is_number && !out.back().first)
      std::rotate(out.begin(), out.end() - 1, out.end());
    return out;
  }

  // GiNaC normalises the sign of a sum inside a product or power by its own, run-dependent
  // term order ((a - b)*c or -(b - a)*c). So a sum is stored in one orientation, chosen from
  // the printed text alone: its first non-constant term by text is added; the other
  // orientation is the negation of that node.
  int convert_sum(const GiNaC::ex& e, std::set<std::string>& symbols) {
    std::vector<int> terms;
    for (std::size_t i = 0; i < e.nops(); ++i) terms.push_back(convert(e.op(i), symbols));
    int lead = -1;
    for (int t : terms) {
      const int m = at(t).kind == Kind::Neg ? at(t).kids[0] : t;
      if (!at(m).is_number && (lead < 0 || at(m).key < at(lead).key)) lead = m;
    }
    const bool flip = lead >= 0 && std::find(terms.begin(), terms.end(), lead) == terms.end();
    if (flip)
      for (int& t : terms) t = negate(t);
    Node n;
    n.kind = Kind::Add;
    n.prec = kPrecAdd;
    n.key =
        add_text(terms, false, [this](int id) { return std::make_pair(at(id).key, at(id).prec); });
    for (const auto& [neg, m] : signed_terms(terms, false)) n.kids.push_back(neg ? negate(m) : m);
    const int sum = intern(std::move(n));
    return flip ? negate(sum) : sum;
  }

  // The text of a sum (negated if `flip`); `print(id)` gives a term's text and precedence.
  template <class Print>
  std::string add_text(const std::vector<int>& terms, bool flip, Print&& print) const {
    std::string out;
    bool first = true;
    for (const auto& [neg, m] : signed_terms(terms, flip)) {
      const auto [text, prec] = print(m);
      out += first ? (neg ? "-" : "") : (neg ? " - " : " + ");
      out += neg && prec < kPrecMul ? "(" + text + ")" : text;
      first = false;
    }
    return out;
  }

  int convert_product(const std::vector<GiNaC::ex>& factors, std::set<std::string>& symbols) {
    GiNaC::numeric coeff(1);
    bool negative = false;
    std::vector<int> num;
    std::vector<int> den;
    auto push = [&](std::vector<int>& side, int id) {
      if (at(id).kind == Kind::Neg) {
        negative = !negative;
        id = at(id).kids[0];
      }
      side.push_back(id);
    };
    for (const GiNaC::ex& f : factors) {
      if (GiNaC::is_a<GiNaC::numeric>(f)) {
        coeff *= GiNaC::ex_to<GiNaC::numeric>(f);
        continue;
      }
      if (GiNaC::is_a<GiNaC::power>(f) && GiNaC::is_a<GiNaC::numeric>(f.op(1)) &&
          GiNaC::ex_to<GiNaC::numeric>(f.op(1)).is_real()) {
        // A negative exponent divides by the positive power, so x^-2 shares x*x with x^2.
        GiNaC::numeric expo = GiNaC::ex_to<GiNaC::numeric>(f.op(1));
        std::vector<int>& side = expo.is_negative() ? den : num;
        if (expo.is_negative()) expo = -expo;
        int base = convert(f.op(0), symbols);
        if (expo.is_integer() && at(base).kind == Kind::Neg) {  // (-x)^n = (-1)^n x^n
          base = at(base).kids[0];
          if (expo.is_odd()) negative = !negative;
        }
        const GiNaC::numeric twice = expo * 2;
        if (expo.is_rational() && twice.is_integer() && twice.int_length() < 16 &&
            twice.to_int() / 2 <= kMaxExpandedPower) {
          // x^(k + 1/2) = x^k*sqrt(x).
          const int whole = twice.to_int() / 2;
          std::vector<int> parts;
          if (whole > 0) parts.push_back(power_product(base, whole));
          if (!expo.is_integer()) parts.push_back(call("sqrt", {base}));
          push(side, product(std::move(parts), {}, false));
        } else {
          push(side, call("pow", {base, positive_number(expo)}, Kind::Pow));
        }
        continue;
      }
      if (GiNaC::is_a<GiNaC::power>(f)) {
        push(num, call("pow", {convert(f.op(0), symbols), convert(f.op(1), symbols)}, Kind::Pow));
        continue;
      }
      push(num, convert(f, symbols));
    }
    if (!coeff.is_real()) throw std::runtime_error("CodeBlock: complex number " + to_text(coeff));
    if (coeff.is_zero()) return positive_number(coeff);
    if (coeff.is_negative()) {
      negative = !negative;
      coeff = -coeff;
    }
    if (num.empty() && den.empty()) {
      const int value = positive_number(coeff);
      return negative ? negate(value) : value;
    }
    if (coeff != 1) {
      if (coeff.is_rational() && !coeff.is_integer() && !is_exact_double(coeff)) {
        if (coeff.numer() != 1) num.push_back(positive_number(coeff.numer()));
        den.push_back(positive_number(coeff.denom()));
      } else {
        num.push_back(positive_number(coeff));
      }
    }
    const int value = product(std::move(num), std::move(den));
    return negative ? negate(value) : value;
  }

  void note_references(const std::set<std::string>& symbols) {
    for (const std::string& s : symbols) {
      referenced.insert(s);
      if (defined.count(s) != 0) referenced_after_definition.insert(s);
    }
  }

  // ---- planning: counting, lazy emission and printing ------------------------------------

  struct Plan {
    std::vector<std::string> lines;
    int ops = 0;
    int temporaries = 0;
    std::set<std::string> functions;
  };

  struct Planner {
    const Impl& b;
    std::vector<int> count;
    std::vector<char> expanded;
    std::vector<std::string> bound;  // define()d name of a node, if it is a definition's root
    std::vector<std::string> temp;   // temporary's name once emitted
    // Divisions: how many printed products divide by a node, and the name of its reciprocal
    // `_tmpN = T(1)/d` once emitted. A division costs several multiplications (and the compiler
    // may not turn a/d into a*(1/d) without -ffast-math), so a denominator shared by two or more
    // products is inverted once and multiplied by; the result differs from a/d by an ulp or so.
    std::vector<int> den_uses;
    std::vector<std::string> reciprocal;
    Plan plan;
    GuardPrinter guard_line;  // null: `if (!(condition)) on_fail`

    explicit Planner(const Impl& block)
        : b(block),
          count(block.nodes.size(), 0),
          expanded(block.nodes.size(), 0),
          bound(block.nodes.size()),
          temp(block.nodes.size()),
          den_uses(block.nodes.size(), 0),
          reciprocal(block.nodes.size()) {}

    const Node& at(int id) const { return b.at(id); }
    std::size_t ix(int id) const { return static_cast<std::size_t>(id); }

    bool may_be_temporary(int id) const {
      const Kind k = at(id).kind;
      return k == Kind::Add || k == Kind::Mul || k == Kind::Func || k == Kind::Pow;
    }
    bool is_temporary(int id) const { return may_be_temporary(id) && count[ix(id)] >= 2; }

    // A denominator is printed once however many products share it (in their division, or in
    // its reciprocal), so only its first use counts.
    void visit_children(int id) {
      for (int k : at(id).kids) visit(k);
      const int den = at(id).den;
      if (den >= 0 && den_uses[ix(den)]++ == 0) visit(den);
    }
    bool inverted(int den) const {
      return den_uses[ix(den)] >= 2 || (b.invert_every_denominator && !at(den).is_number);
    }

    // Whether a node depends on numbers and parameters (`p.` symbols) only, through define()d
    // names too.
    std::vector<signed char> invariant_memo;
    std::map<std::string, int> definition_root;
    bool invariant(int id) {
      if (invariant_memo.empty()) {
        invariant_memo.assign(b.nodes.size(), -1);
        for (const Statement& s : b.statements)
          if (s.type == Statement::Type::Define) definition_root[s.name] = s.root;
      }
      signed char& memo = invariant_memo[ix(id)];
      if (memo >= 0) return memo != 0;
      const Node& n = at(id);
      bool result = true;
      if (n.kind == Kind::Leaf) {
        const auto def = definition_root.find(n.key);
        result = n.is_number || n.key.rfind("p.", 0) == 0 ||
                 (def != definition_root.end() && invariant(def->second));
      } else {
        for (int k : n.kids) result = result && invariant(k);
        if (n.den >= 0) result = result && invariant(n.den);
      }
      memo = result ? 1 : 0;
      return result;
    }

    // Counts how often each node is printed: a node is expanded (its children counted) only
    // once, since every further use prints the temporary's name. Negations are transparent.
    void visit(int id) {
      const Node& n = at(id);
      if (n.kind == Kind::Leaf || !bound[ix(id)].empty()) return;
      if (n.kind == Kind::Neg) {
        visit(n.kids[0]);
        return;
      }
      ++count[ix(id)];
      if (expanded[ix(id)]) return;
      expanded[ix(id)] = 1;
      visit_children(id);
    }

    void count_all() {
      for (const Statement& s : b.statements) {
        if (s.type == Statement::Type::Define && may_be_temporary(s.root) &&
            !expanded[ix(s.root)] && bound[ix(s.root)].empty()) {
          // The definition names this node: later uses print the name, not a temporary.
          bound[ix(s.root)] = s.name;
          expanded[ix(s.root)] = 1;
          visit_children(s.root);
          continue;
        }
        visit(s.root);
        if (s.rhs >= 0) visit(s.rhs);
      }
    }

    void emit_children(int id) {
      for (int k : at(id).kids) emit(k);
      const int den = at(id).den;
      if (den < 0) return;
      emit(den);
      if (inverted(den) && reciprocal[ix(den)].empty()) {
        const std::string name = b.temp_prefix + std::to_string(plan.temporaries++);
        plan.lines.push_back("const T " + name + " = T(1)/" + print(den, true) + ";");
        if (!at(den).is_number) plan.ops += 1;  // 1/number is folded by the compiler
        reciprocal[ix(den)] = name;
      }
    }

    // Emits, in post-order, the temporaries `id` needs that are not emitted yet.
    void emit(int id) {
      const Node& n = at(id);
      if (n.kind == Kind::Leaf || !bound[ix(id)].empty() || !temp[ix(id)].empty()) return;
      emit_children(id);
      if (is_temporary(id)) {
        const std::string name = b.temp_prefix + std::to_string(plan.temporaries++);
        plan.lines.push_back("const T " + name + " = " + body(id) + ";");
        temp[ix(id)] = name;
      }
    }

    bool named(int id) const { return !bound[ix(id)].empty() || !temp[ix(id)].empty(); }

    // A node's text where it is used (its name if it has one) and that text's precedence.
    std::pair<std::string, int> term(int id) {
      if (!bound[ix(id)].empty()) return {bound[ix(id)], kPrecAtom};
      if (!temp[ix(id)].empty()) return {temp[ix(id)], kPrecAtom};
      return {body(id), at(id).prec};
    }

    std::string print(int id, bool parens_unless_atom) {
      const auto [text, prec] = term(id);
      return parens_unless_atom && prec != kPrecAtom ? "(" + text + ")" : text;
    }

    std::string sum(int id, bool flip) {
      plan.ops += static_cast<int>(at(id).kids.size()) - 1;
      return b.add_text(at(id).kids, flip, [this](int t) { return term(t); });
    }

    // The node's own text, children printed as their names where they have one. Counts the
    // operations printed.
    std::string body(int id) {
      const Node& n = at(id);
      std::string out;
      switch (n.kind) {
        case Kind::Leaf:
          return n.key;
        case Kind::Neg: {
          const int c = n.kids[0];
          if (at(c).kind == Kind::Add && !named(c)) return sum(c, true);  // b - a, not -(a - b)
          const auto [text, prec] = term(c);
          return "-" + (prec < kPrecMul ? "(" + text + ")" : text);
        }
        case Kind::Add:
          return sum(id, false);
        case Kind::Mul: {
          // Factors that depend on parameters only are multiplied first: C++ evaluates a*b*c as
          // (a*b)*c and the compiler may not reorder floating-point products, so only a leading
          // invariant sub-product such as (T(0.4)*_tmp3) is shared between statements (CSE) and
          // hoisted out of evaluate_batch's loop.
          std::vector<std::pair<bool, std::string>> factors;
          for (int f : n.kids) factors.emplace_back(invariant(f), print(f, true));
          plan.ops += std::max(0, static_cast<int>(n.kids.size()) - 1);
          const bool inverted_den = n.den >= 0 && !reciprocal[ix(n.den)].empty();
          if (inverted_den) {
            factors.emplace_back(invariant(n.den), reciprocal[ix(n.den)]);
            if (!n.kids.empty()) plan.ops += 1;
          }
          std::stable_partition(factors.begin(), factors.end(),
                                [](const auto& f) { return f.first; });
          for (const auto& f : factors) out += (out.empty() ? "" : "*") + f.second;
          if (inverted_den) return out;
          if (n.kids.empty()) out = "T(1)";
          if (n.den >= 0) {
            out += "/" + print(n.den, true);
            plan.ops += 1;
          }
          return out;
        }
        case Kind::Func:
        case Kind::Pow:
          out = n.fname + "(";
          for (std::size_t i = 0; i < n.kids.size(); ++i) {
            if (i > 0) out += ", ";
            out += print(n.kids[i], false);
          }
          plan.ops += 1;
          plan.functions.insert(n.fname);
          return out + ")";
      }
      return out;
    }

    void run() {
      count_all();
      for (const Statement& s : b.statements) {
        switch (s.type) {
          case Statement::Type::Define:
            if (bound[ix(s.root)] == s.name) {
              emit_children(s.root);
              plan.lines.push_back("const T " + s.name + " = " + body(s.root) + ";");
            } else {
              emit(s.root);
              plan.lines.push_back("const T " + s.name + " = " + print(s.root, false) + ";");
            }
            break;
          case Statement::Type::Guard:
            emit(s.root);
            emit(s.rhs);
            {
              const std::string condition =
                  print(s.root, false) + " " + s.comparison + " " + print(s.rhs, false);
              plan.lines.push_back(guard_line ? guard_line(condition, s.on_fail)
                                              : "if (!(" + condition + ")) " + s.on_fail);
            }
            break;
          case Statement::Type::Assign:
            emit(s.root);
            plan.lines.push_back(s.name + " = " + print(s.root, false) + ";");
            break;
        }
      }
    }
  };

  Plan make_plan(const GuardPrinter& guard_line = nullptr) const {
    Planner p(*this);
    p.guard_line = guard_line;
    p.run();
    return std::move(p.plan);
  }
};

CodeBlock::CodeBlock(std::string temp_prefix) : impl_(std::make_unique<Impl>()) {
  if (!is_identifier(temp_prefix))
    throw std::runtime_error("CodeBlock: temporary prefix " + quote(temp_prefix) +
                             " is not an identifier");
  impl_->temp_prefix = std::move(temp_prefix);
}

CodeBlock::~CodeBlock() = default;

void CodeBlock::invert_every_denominator() {
  impl_->invert_every_denominator = true;
}
CodeBlock::CodeBlock(CodeBlock&&) noexcept = default;
CodeBlock& CodeBlock::operator=(CodeBlock&&) noexcept = default;

void CodeBlock::define(const std::string& name, const GiNaC::ex& e) {
  Impl& b = *impl_;
  if (!is_identifier(name))
    throw std::runtime_error("CodeBlock: define: " + quote(name) + " is not an identifier");
  if (name.rfind(b.temp_prefix, 0) == 0)
    throw std::runtime_error("CodeBlock: define: " + quote(name) +
                             " collides with the temporaries' prefix " + quote(b.temp_prefix));
  if (b.defined.count(name) != 0)
    throw std::runtime_error("CodeBlock: define: " + quote(name) + " is defined twice");
  if (b.referenced.count(name) != 0)
    throw std::runtime_error("CodeBlock: define: " + quote(name) +
                             " is used by an earlier statement (before its definition)");
  std::set<std::string> symbols;
  Statement s;
  s.type = Statement::Type::Define;
  s.name = name;
  s.root = b.convert(e, symbols);
  if (symbols.count(name) != 0)
    throw std::runtime_error("CodeBlock: define: " + quote(name) + " refers to itself");
  b.note_references(symbols);
  b.defined.insert(name);
  b.definition_order.push_back(name);
  b.statements.push_back(std::move(s));
}

void CodeBlock::guard(const GiNaC::ex& value, const std::string& comparison,
                      const std::string& on_fail_statement) {
  guard(value, comparison, GiNaC::ex(0), on_fail_statement);
}

void CodeBlock::guard(const GiNaC::ex& lhs, const std::string& comparison, const GiNaC::ex& rhs,
                      const std::string& on_fail_statement) {
  Impl& b = *impl_;
  static const std::set<std::string> comparisons = {"<", "<=", ">", ">=", "==", "!="};
  if (comparisons.count(comparison) == 0)
    throw std::runtime_error("CodeBlock: guard: unknown comparison " + quote(comparison));
  if (on_fail_statement.empty() || on_fail_statement.find('\n') != std::string::npos)
    throw std::runtime_error("CodeBlock: guard: the failure statement " + quote(on_fail_statement) +
                             " must be one non-empty line");
  std::set<std::string> symbols;
  Statement s;
  s.type = Statement::Type::Guard;
  s.root = b.convert(lhs, symbols);
  s.rhs = b.convert(rhs, symbols);
  s.comparison = comparison;
  s.on_fail = on_fail_statement;
  b.note_references(symbols);
  b.statements.push_back(std::move(s));
}

void CodeBlock::assign(const std::string& target, const GiNaC::ex& e) {
  Impl& b = *impl_;
  if (target.empty() || target.find_first_of(";\n") != std::string::npos)
    throw std::runtime_error("CodeBlock: assign: invalid target " + quote(target));
  if (b.assigned.count(target) != 0)
    throw std::runtime_error("CodeBlock: assign: " + quote(target) + " is assigned twice");
  std::set<std::string> symbols;
  Statement s;
  s.type = Statement::Type::Assign;
  s.name = target;
  s.root = b.convert(e, symbols);
  b.note_references(symbols);
  b.assigned.insert(target);
  b.statements.push_back(std::move(s));
}

std::string CodeBlock::render(const std::string& indent) const {
  return render(indent, nullptr);
}

std::string CodeBlock::render(const std::string& indent, const GuardPrinter& guard_line) const {
  std::string out;
  for (const std::string& line : impl_->make_plan(guard_line).lines) out += indent + line + "\n";
  return out;
}

int CodeBlock::op_count() const {
  return impl_->make_plan().ops;
}

int CodeBlock::temporary_count() const {
  return impl_->make_plan().temporaries;
}

std::set<std::string> CodeBlock::math_functions() const {
  return impl_->make_plan().functions;
}

std::vector<std::string> CodeBlock::unused_definitions() const {
  std::vector<std::string> unused;
  for (const std::string& name : impl_->definition_order)
    if (impl_->referenced_after_definition.count(name) == 0) unused.push_back(name);
  return unused;
}

}  // namespace mechgen::gen
