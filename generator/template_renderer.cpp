#include "template_renderer.hpp"

#include <cctype>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

namespace mechgen::gen {
namespace {

bool is_identifier(const std::string& s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
  for (char c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  return true;
}

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(' ');
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(' ') - first + 1);
}

}  // namespace

std::string render_template(const std::string& template_text,
                            const std::map<std::string, std::string>& values,
                            const std::string& template_name) {
  std::string out;
  std::set<std::string> used;
  int line = 1;
  std::size_t pos = 0;
  auto fail = [&](const std::string& what) {
    throw std::runtime_error("template '" + template_name + "', line " + std::to_string(line) +
                             ": " + what);
  };
  while (true) {
    const std::size_t open = template_text.find("{{", pos);
    const std::size_t stop = open == std::string::npos ? template_text.size() : open;
    for (std::size_t i = pos; i < stop; ++i) line += template_text[i] == '\n' ? 1 : 0;
    out.append(template_text, pos, stop - pos);
    if (open == std::string::npos) break;

    const std::size_t close = template_text.find("}}", open + 2);
    const std::size_t line_end = template_text.find('\n', open);
    if (close == std::string::npos || (line_end != std::string::npos && close > line_end))
      fail("'{{' without '}}' on the same line (write '{ {' for literal braces)");
    const std::string name = trim(template_text.substr(open + 2, close - open - 2));
    if (!is_identifier(name))
      fail("malformed placeholder '" + template_text.substr(open, close + 2 - open) + "'");
    const auto value = values.find(name);
    if (value == values.end()) fail("unknown placeholder '{{" + name + "}}' (no value given)");
    used.insert(name);

    // Indent continuation lines to the placeholder's column in the output, keeping tabs.
    std::string indent = out.substr(out.rfind('\n') == std::string::npos ? 0 : out.rfind('\n') + 1);
    for (char& c : indent)
      if (c != '\t') c = ' ';
    const std::string& text = value->second;
    for (std::size_t i = 0; i < text.size(); ++i) {
      out += text[i];
      if (text[i] == '\n' && i + 1 < text.size() && text[i + 1] != '\n') out += indent;
    }
    pos = close + 2;
  }

  for (const auto& [name, unused] : values) {
    (void)unused;
    if (used.count(name) == 0)
      throw std::runtime_error("template '" + template_name + "': value '" + name +
                               "' is never used (no {{" + name + "}} in the template)");
  }
  return out;
}

std::string read_template(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read template " + path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace mechgen::gen
