#include "forward_dynamics_emit.hpp"

#include <map>

#include "template_renderer.hpp"

namespace mechgen::gen {

namespace {

std::string join(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += (text.empty() ? "" : "\n") + line;
  return text;
}

// M[a][b] as its row-major index in a constant expression's text.
std::string at(size_t a, size_t b, size_t n) {
  return std::to_string(a * n + b);
}

// mass_bias()'s body: one evaluation per unit acceleration (column b keeps rows a <= b), one at
// q'' = 0 (h), then the columns minus h, each pair mirrored once.
std::string mass_bias_body(const std::vector<std::string>& q) {
  const size_t n = q.size();
  std::vector<std::string> body;
  for (const std::string& c : q) body.push_back("at." + c + "_dd = T(0);");
  for (size_t b = 0; b <= n; ++b) {
    if (b > 0) body.push_back("at." + q[b - 1] + "_dd = T(0);");
    if (b < n) {
      body.push_back("// Efforts at a unit acceleration of " + q[b] + ".");
      body.push_back("at." + q[b] + "_dd = T(1);");
    } else {
      body.push_back("// h: the efforts at zero driver acceleration.");
    }
    body.push_back("status = evaluate(p, at, s);");
    body.push_back("if (status != Status::ok) return status;");
    for (size_t a = 0; a < n && a <= b; ++a)
      body.push_back((b < n ? "M[" + at(a, b, n) + "]" : "h[" + std::to_string(a) + "]") +
                     " = s.drivers." + q[a] + ".effort;");
  }
  body.push_back("// Columns minus h; M[b][a] = M[a][b].");
  for (size_t b = 0; b < n; ++b)
    for (size_t a = 0; a <= b; ++a) {
      body.push_back("M[" + at(a, b, n) + "] -= h[" + std::to_string(a) + "];");
      if (a < b) body.push_back("M[" + at(b, a, n) + "] = M[" + at(a, b, n) + "];");
    }
  return join(body);
}

// Above this many coordinates mass_solve() is a loop, not straight lines (bioloid's 30: 130 kB
// of code for one solve per forward-dynamics step, where the mass matrix's n + 1 evaluations
// dominate); both do the same operations in the same order.
constexpr size_t kUnrolledLdltAtMost = 12;

// mass_solve()'s body for a large M: ldlt_body's operations, in loops over arrays.
std::string ldlt_loop_body(size_t n) {
  const std::string N = std::to_string(n);
  return join({
      "using std::abs;",
      "using std::isfinite;",
      "constexpr int n = " + N + ";",
      "// The largest diagonal entry sets the scale of the pivots' tolerance.",
      "T scale = abs(M[0]);",
      "for (int j = 1; j < n; ++j) scale = abs(M[j * n + j]) > scale ? abs(M[j * n + j]) : scale;",
      "const T relative = T(64) * std::numeric_limits<T>::epsilon();",
      "const T tolerance = (relative > T(1e-12) ? relative : T(1e-12)) * scale;",
      "// d: pivots; l: L below the diagonal; e = l d.",
      "T d[n], l[n * n], e[n * n];",
      "for (int j = 0; j < n; ++j) {",
      "  T pivot = M[j * n + j];",
      "  for (int k = 0; k < j; ++k) pivot = pivot - e[j * n + k] * l[j * n + k];",
      "  if (!(pivot > tolerance)) return Status::singular;",
      "  d[j] = pivot;",
      "  for (int i = j + 1; i < n; ++i) {",
      "    T below = M[i * n + j];",
      "    for (int k = 0; k < j; ++k) below = below - e[i * n + k] * l[j * n + k];",
      "    e[i * n + j] = below;",
      "    l[i * n + j] = below / pivot;",
      "  }",
      "}",
      "// L z = effort - h, then D y = z and L^T x = y.",
      "T z[n], x[n];",
      "for (int i = 0; i < n; ++i) {",
      "  z[i] = effort[i] - h[i];",
      "  for (int k = 0; k < i; ++k) z[i] = z[i] - l[i * n + k] * z[k];",
      "}",
      "bool finite = true;",
      "for (int r = n - 1; r >= 0; --r) {",
      "  x[r] = z[r] / d[r];",
      "  for (int k = r + 1; k < n; ++k) x[r] = x[r] - l[k * n + r] * x[k];",
      "  finite = finite && isfinite(x[r]);",
      "}",
      "if (!finite) return Status::non_finite;",
      "for (int i = 0; i < n; ++i) qdd[i] = x[i];",
  });
}

// mass_solve()'s body: LDL^T of M in fixed order (d_j pivots, l_i_j below the diagonal, e_i_j =
// l_i_j d_j), a pivot not above the tolerance is singular; then L z = r, D y = z, L^T x = y.
std::string ldlt_body(size_t n) {
  if (n > kUnrolledLdltAtMost) return ldlt_loop_body(n);
  auto l = [](size_t i, size_t j) { return "l_" + std::to_string(i) + "_" + std::to_string(j); };
  auto e = [](size_t i, size_t j) { return "e_" + std::to_string(i) + "_" + std::to_string(j); };
  auto d = [](size_t j) { return "d_" + std::to_string(j); };
  std::vector<std::string> body;
  body.push_back("using std::abs;");
  body.push_back("using std::isfinite;");
  body.push_back("// The largest diagonal entry sets the scale of the pivots' tolerance.");
  body.push_back("T scale = abs(M[0]);");
  for (size_t j = 1; j < n; ++j)
    body.push_back("scale = abs(M[" + at(j, j, n) + "]) > scale ? abs(M[" + at(j, j, n) +
                   "]) : scale;");
  body.push_back("const T relative = T(64) * std::numeric_limits<T>::epsilon();");
  body.push_back("const T tolerance = (relative > T(1e-12) ? relative : T(1e-12)) * scale;");
  for (size_t j = 0; j < n; ++j) {
    std::string pivot = "M[" + at(j, j, n) + "]";
    for (size_t k = 0; k < j; ++k) pivot += " - " + e(j, k) + " * " + l(j, k);
    body.push_back("const T " + d(j) + " = " + pivot + ";");
    body.push_back("if (!(" + d(j) + " > tolerance)) return Status::singular;");
    for (size_t i = j + 1; i < n; ++i) {
      std::string below = "M[" + at(i, j, n) + "]";
      for (size_t k = 0; k < j; ++k) below += " - " + e(i, k) + " * " + l(j, k);
      body.push_back("const T " + e(i, j) + " = " + below + ";");
      body.push_back("const T " + l(i, j) + " = " + e(i, j) + " / " + d(j) + ";");
    }
  }
  body.push_back("// L z = effort - h, then D y = z and L^T x = y.");
  for (size_t i = 0; i < n; ++i) {
    std::string z = "effort[" + std::to_string(i) + "] - h[" + std::to_string(i) + "]";
    for (size_t k = 0; k < i; ++k) z += " - " + l(i, k) + " * z_" + std::to_string(k);
    body.push_back("const T z_" + std::to_string(i) + " = " + z + ";");
  }
  for (size_t r = n; r-- > 0;) {
    std::string x = "z_" + std::to_string(r) + " / " + d(r);
    for (size_t k = r + 1; k < n; ++k) x += " - " + l(k, r) + " * x_" + std::to_string(k);
    body.push_back("const T x_" + std::to_string(r) + " = " + x + ";");
  }
  std::string finite;
  for (size_t i = 0; i < n; ++i)
    finite += std::string(i ? " && " : "") + "isfinite(x_" + std::to_string(i) + ")";
  body.push_back("if (!(" + finite + ")) return Status::non_finite;");
  for (size_t i = 0; i < n; ++i)
    body.push_back("qdd[" + std::to_string(i) + "] = x_" + std::to_string(i) + ";");
  return join(body);
}

}  // namespace

ForwardDynamicsText emit_forward_dynamics(const std::string& templates_dir,
                                          const std::vector<std::string>& coordinates,
                                          const std::string& driven_inputs,
                                          const std::string& entry_state) {
  std::string names, bias_zero, bias_out;
  for (size_t a = 0; a < coordinates.size(); ++a) {
    const std::string& c = coordinates[a];
    names += std::string(a ? ", " : "") + "\"" + c + "\"";
    bias_zero += std::string(a ? "\n" : "") + "at." + c + "_dd = T(0);";
    bias_out +=
        std::string(a ? "\n" : "") + "h[" + std::to_string(a) + "] = s.drivers." + c + ".effort;";
  }
  const std::map<std::string, std::string> header{
      {"coordinate_count", std::to_string(coordinates.size())},
      {"coordinate_names", names},
      {"mass_bias_body", mass_bias_body(coordinates)},
      {"bias_zero", bias_zero},
      {"bias_out", bias_out},
      {"ldlt_body", ldlt_body(coordinates.size())}};
  const std::map<std::string, std::string> entry{{"driven_inputs", driven_inputs},
                                                 {"entry_state", entry_state}};
  // Without the files' last newline: the including templates place the blocks.
  auto block = [](std::string text) {
    if (!text.empty() && text.back() == '\n') text.pop_back();
    return text;
  };
  return {block(render_template(read_template(templates_dir + "/forward_dynamics.hpp.in"), header,
                                "forward_dynamics.hpp.in")),
          block(render_template(read_template(templates_dir + "/forward_dynamics_entry.cpp.in"),
                                entry, "forward_dynamics_entry.cpp.in"))};
}

}  // namespace mechgen::gen
