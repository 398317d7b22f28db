#include "output_checks.hpp"

#include <algorithm>
#include <stdexcept>

namespace mechgen::gen {

namespace {

bool starts_with(const std::string& text, const std::string& prefix) {
  return text.rfind(prefix, 0) == 0;
}

// The pairwise sum of terms[begin, end) as one expression (parenthesised when more than one).
std::string pairwise(const std::vector<std::string>& terms, size_t begin, size_t end) {
  if (end - begin == 1) return terms[begin];
  const size_t middle = begin + (end - begin) / 2;
  return "(" + pairwise(terms, begin, middle) + " + " + pairwise(terms, middle, end) + ")";
}

std::string strip_parentheses(const std::string& text) {
  return text.size() > 1 && text.front() == '(' ? text.substr(1, text.size() - 2) : text;
}

// `const T name = <sum of terms>;` lines: terms in lines of at most kPerLine, each line a partial
// sum `name_K` (K counting on through the levels), the partial sums summed the same way until one
// is left.
constexpr size_t kPerLine = 8;
std::string sum_lines(const std::vector<std::string>& terms, const std::string& name,
                      const std::string& indent, int& next_partial) {
  if (terms.size() <= kPerLine)
    return indent + "const T " + name + " = " +
           strip_parentheses(pairwise(terms, 0, terms.size())) + ";\n";
  std::string text;
  std::vector<std::string> partial;
  for (size_t begin = 0; begin < terms.size(); begin += kPerLine) {
    const std::string part = name + "_" + std::to_string(next_partial++);
    const size_t end = std::min(terms.size(), begin + kPerLine);
    text +=
        indent + "const T " + part + " = " + strip_parentheses(pairwise(terms, begin, end)) + ";\n";
    partial.push_back(part);
  }
  return text + sum_lines(partial, name, indent, next_partial);
}

}  // namespace

OutputStage stage_of(const std::string& source) {
  const auto field_of = [&source]() { return source.substr(source.rfind('.') + 1); };
  if (starts_with(source, "s.points.")) {
    const std::string field = field_of();
    return field == "x" || field == "y" ? OutputStage::positions : OutputStage::rates;
  }
  if (starts_with(source, "s.joints.")) return OutputStage::forces;
  if (starts_with(source, "s.drivers.")) {
    const std::string field = field_of();
    if (field == "q") return OutputStage::positions;
    return field == "effort" ? OutputStage::forces : OutputStage::rates;
  }
  if (starts_with(source, "s.bodies.")) {
    const std::string field = field_of();
    const bool position =
        field == "x" || field == "y" || field == "cos_th" || field == "sin_th" || field == "th()";
    return position ? OutputStage::positions : OutputStage::rates;
  }
  return OutputStage::none;
}

OutputStage spatial_stage_of(const std::string& target) {
  if (starts_with(target, "s.body_jacobians.") || starts_with(target, "s.point_jacobians."))
    return OutputStage::positions;
  if (!starts_with(target, "s.")) return OutputStage::none;
  const std::string field = target.substr(target.rfind('.') + 1);
  if (field == "x" || field == "y" || field == "z" || starts_with(field, "R[") ||
      (starts_with(field, "q") && field.find('d') == std::string::npos))
    return OutputStage::positions;
  if (field == "effort" || field == "fx" || field == "fy" || field == "fz" || field == "mx" ||
      field == "my" || field == "mz")
    return OutputStage::forces;
  return OutputStage::rates;
}

std::string output_checks(
    const std::vector<CheckedOutput>& outputs, const std::string& indent,
    const std::function<std::string(OutputStage, const std::string& condition)>& check_line) {
  std::string text;
  for (int k = static_cast<int>(OutputStage::positions); k < kStageCount; ++k) {
    const OutputStage stage = static_cast<OutputStage>(k);
    std::vector<std::string> terms;
    for (const CheckedOutput& o : outputs)
      if (o.stage == stage) terms.push_back(o.expression);
    if (terms.empty()) continue;
    const std::string sum = std::string("_sum_") + kStageNames[k];
    int next_partial = 0;
    text += sum_lines(terms, sum, indent, next_partial);
    text += indent + check_line(stage, sum + " - " + sum + " == T(0)") + "\n";
  }
  return text;
}

}  // namespace mechgen::gen
