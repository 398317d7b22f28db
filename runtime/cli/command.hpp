// What every mechgen sub-command shares: the argument parser, usage errors, the command table
// entry and small text helpers. A new sub-command lives in its own cmd_<name>.cpp, which defines
// `Command <name>_command()` (declared at the end of this file) and is listed once in main.cpp's
// commands().
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/model.hpp"
#include "sweep/sweep.hpp"

namespace mechgen::cli {

// ---- errors -------------------------------------------------------------------------------------

// A wrong command line: printed as "mechgen COMMAND: error: MESSAGE (see mechgen COMMAND --help)".
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The file a command is working on, for errors that carry no location of their own.
extern std::string g_current_file;

// ---- suggestions --------------------------------------------------------------------------------

// The candidate nearest to `word` by edit distance (insertions, deletions, substitutions and
// transpositions of neighbours), or "" when none is near enough to be a likely misspelling: at
// most a third of the word's length, and at least one, edits away.
inline std::string nearest_word(const std::string& word,
                                const std::vector<std::string>& candidates) {
  const auto distance = [](const std::string& a, const std::string& b) {
    std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
    for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (size_t i = 1; i <= a.size(); ++i)
      for (size_t j = 1; j <= b.size(); ++j) {
        d[i][j] = std::min(
            {d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
        if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
          d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    return d[a.size()][b.size()];
  };
  std::string best;
  size_t best_distance = std::max<size_t>(1, word.size() / 3) + 1;
  for (const std::string& candidate : candidates)
    if (const size_t dist = distance(word, candidate); dist < best_distance)
      best = candidate, best_distance = dist;
  return best;
}

// "unknown WHAT 'WORD'", with "; did you mean 'NEAREST'?" where one of `candidates` is near.
inline std::string unknown_word(const std::string& what, const std::string& word,
                                const std::vector<std::string>& candidates) {
  const std::string nearest = nearest_word(word, candidates);
  return "unknown " + what + " '" + word + "'" +
         (nearest.empty() ? "" : "; did you mean '" + nearest + "'?");
}

// ---- the argument parser ------------------------------------------------------------------------

struct OptionSpec {
  std::string name;   // "--out"
  std::string alias;  // "-o", or empty
  bool takes_value = false;
  bool repeatable = false;
};

class Args {
 public:
  // Parses the words after the command name. "--name VALUE" and "--name=VALUE" both work; "--"
  // makes the next word positional even when it starts with '-' (`mechgen sweep -- -odd.yaml
  // --out x.csv`: options may follow the model name, as everywhere); "-h" and "--help" ask for
  // help. Throws UsageError for an unknown option, a missing value, or an option given twice that
  // may be given once.
  Args(const std::vector<std::string>& words, std::vector<OptionSpec> specs)
      : specs_(std::move(specs)) {
    bool next_is_positional = false;
    for (size_t i = 0; i < words.size(); ++i) {
      const std::string& word = words[i];
      if (next_is_positional || word.size() < 2 || word[0] != '-') {
        positional_.push_back(word);
        next_is_positional = false;
        continue;
      }
      if (word == "--") {
        next_is_positional = true;
        continue;
      }
      if (word == "--help" || word == "-h") {
        help_ = true;
        continue;
      }
      std::string name = word, value;
      bool inline_value = false;
      if (const auto eq = word.find('='); word.rfind("--", 0) == 0 && eq != std::string::npos) {
        name = word.substr(0, eq);
        value = word.substr(eq + 1);
        inline_value = true;
      }
      const OptionSpec* spec = find(name);
      if (!spec) {
        std::vector<std::string> names{"--help"};
        for (const OptionSpec& known : specs_) names.push_back(known.name);
        throw UsageError(unknown_word("option", name, names));
      }
      if (spec->takes_value && !inline_value) {
        if (i + 1 >= words.size()) throw UsageError("option " + spec->name + " needs a value");
        value = words[++i];
      } else if (!spec->takes_value && inline_value) {
        throw UsageError("option " + spec->name + " takes no value");
      }
      std::vector<std::string>& slot = values_[spec->name];
      if (!slot.empty() && !spec->repeatable)
        throw UsageError("option " + spec->name + " given more than once");
      slot.push_back(value);
    }
  }

  bool help() const { return help_; }
  bool has(const std::string& name) const { return values_.count(name) > 0; }
  std::string get(const std::string& name, const std::string& fallback = "") const {
    const auto it = values_.find(name);
    return it == values_.end() ? fallback : it->second.back();
  }
  std::vector<std::string> all(const std::string& name) const {
    const auto it = values_.find(name);
    return it == values_.end() ? std::vector<std::string>{} : it->second;
  }
  // Every positional argument, in order.
  const std::vector<std::string>& positionals() const { return positional_; }
  // The one positional argument a command takes (its MODEL.yaml or CSV file).
  std::string single_positional(const std::string& what) const {
    if (positional_.empty()) throw UsageError("missing " + what);
    if (positional_.size() > 1) throw UsageError("unexpected argument '" + positional_[1] + "'");
    return positional_.front();
  }
  // A finite number in plain decimal or scientific notation, the whole of `text`; else a
  // UsageError "OPTION: 'TEXT' is not a number".
  static double parse_number(const std::string& text, const std::string& option) {
    size_t used = 0;
    double value = 0;
    try {
      value = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != text.size() || !std::isfinite(value))
      throw UsageError(option + ": '" + text + "' is not a number");
    return value;
  }
  // An option's value as a number (parse_number).
  double number(const std::string& name, double fallback) const {
    return has(name) ? parse_number(get(name), name) : fallback;
  }
  int integer(const std::string& name, int fallback) const {
    const double value = number(name, fallback);
    if (value != std::floor(value) || std::abs(value) > 1e9)
      throw UsageError(name + ": '" + get(name) + "' is not an integer");
    return static_cast<int>(value);
  }

 private:
  const OptionSpec* find(const std::string& name) const {
    for (const OptionSpec& spec : specs_)
      if (spec.name == name || (!spec.alias.empty() && spec.alias == name)) return &spec;
    return nullptr;
  }

  std::vector<OptionSpec> specs_;
  std::map<std::string, std::vector<std::string>> values_;
  std::vector<std::string> positional_;
  bool help_ = false;
};

// ---- small helpers ------------------------------------------------------------------------------

// Left-aligned text columns, each as wide as its widest cell.
std::string table(const std::vector<std::vector<std::string>>& rows, const std::string& indent);
// A number in %g style with the given significant digits.
std::string fixed(double value, int digits = 6);
// An angle wrapped to [-pi, pi].
double wrap_angle(double a);
// Reads a model, remembering its path for errors that carry no location.
Model load_model(const std::string& path);
double seconds_since(std::chrono::steady_clock::time_point start);
// --solver's value: "generated" (the default) or "numeric"; anything else is a UsageError.
std::string solver_option(const Args& args);
// The names of every `option` (each a comma-separated list, as --trace A,B --trace C); an empty
// name is a UsageError.
std::vector<std::string> comma_list(const Args& args, const std::string& option);
// --shard I/N (sweep/shard.hpp), the whole run when absent; a malformed one is a UsageError.
Shard shard_option(const Args& args);
// A fresh sweep of `model` at `parameters`: the model's step, overridden by --solver, --samples,
// --t0 and --t1 where given (each checked).
SweepOptions sweep_options(const Model& model, const std::vector<double>& parameters,
                           const Args& args);

// ---- the command table --------------------------------------------------------------------------

struct Command {
  const char* name;
  const char* summary;
  const char* help;
  std::vector<OptionSpec> options;
  int (*run)(const Args&);
  // `--out` names a folder the command fills and checks itself; otherwise every output option
  // (--out, --over-time, --diagram-out, --plot) is checked as a file before the command runs.
  bool out_is_folder = false;
};

// ---- sub-commands in their own files (cmd_<name>.cpp) -------------------------------------------

Command sweep_command();          // cmd_sweep.cpp
Command grid_command();           // cmd_grid.cpp
Command size_motor_command();     // cmd_size_motor.cpp
Command walk_command();           // cmd_walk.cpp
Command draw_command();           // cmd_draw.cpp
Command loads_command();          // cmd_loads.cpp
Command zmp_command();            // cmd_zmp.cpp
Command merge_command();          // cmd_merge.cpp
Command workspace_command();      // cmd_workspace.cpp
Command follow_command();         // cmd_follow.cpp
Command humanoid_gait_command();  // cmd_humanoid_gait.cpp
Command view_command();           // cmd_view.cpp
Command simulate_command();       // cmd_simulate.cpp
Command import_command();         // cmd_import.cpp
Command export_command();         // cmd_export.cpp

}  // namespace mechgen::cli
