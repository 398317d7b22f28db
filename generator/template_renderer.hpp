// The one template renderer of mechgen: `{{name}}` placeholders, strict both ways.
//
//   * A placeholder is `{{name}}` (spaces inside the braces allowed), name a C++ identifier.
//     Every `{{` must open one: write `{ {` for literal braces in a template.
//   * A placeholder without a value, or a value that no placeholder uses, is an error
//     (std::runtime_error naming the template, and the line of a placeholder).
//   * A value spanning several lines is re-indented: each line after its first is prefixed with
//     as much whitespace as the placeholder's column (empty lines get none), so a block of code
//     rendered without indentation lines up under the placeholder. The value is inserted
//     verbatim otherwise (a trailing newline is kept) and is not scanned for placeholders.
// There are no loops or conditionals: the caller builds repeated text and passes it as a value.
#pragma once

#include <map>
#include <string>

namespace mechgen::gen {

/// Substitutes `values` into `template_text`; `template_name` (e.g. "kernel.hpp.in") only
/// appears in error messages.
std::string render_template(const std::string& template_text,
                            const std::map<std::string, std::string>& values,
                            const std::string& template_name);

/// The text of a template file; std::runtime_error "cannot read template PATH" when unreadable.
std::string read_template(const std::string& path);

}  // namespace mechgen::gen
