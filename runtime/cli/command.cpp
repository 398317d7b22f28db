// The shared helpers of command.hpp.
#include "cli/command.hpp"

#include <algorithm>
#include <cstdio>
#include <numbers>

#include "model/model.hpp"

namespace mechgen::cli {

std::string g_current_file;

// Left-aligned text columns, each as wide as its widest cell.
std::string table(const std::vector<std::vector<std::string>>& rows, const std::string& indent) {
  std::vector<size_t> width;
  for (const auto& row : rows)
    for (size_t i = 0; i < row.size(); ++i) {
      if (width.size() <= i) width.push_back(0);
      width[i] = std::max(width[i], row[i].size());
    }
  std::string out;
  for (const auto& row : rows) {
    std::string line = indent;
    for (size_t i = 0; i < row.size(); ++i)
      line += row[i] + (i + 1 < row.size() ? std::string(width[i] - row[i].size() + 2, ' ') : "");
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out += line + "\n";
  }
  return out;
}

std::string fixed(double value, int digits) {
  char text[40];
  std::snprintf(text, sizeof text, "%.*g", digits, value);
  return text;
}

std::vector<std::string> comma_list(const Args& args, const std::string& option) {
  std::vector<std::string> names;
  for (const std::string& list : args.all(option))
    for (size_t begin = 0; begin <= list.size();) {
      const size_t end = std::min(list.find(',', begin), list.size());
      if (end == begin) throw UsageError(option + ": an empty name in '" + list + "'");
      names.push_back(list.substr(begin, end - begin));
      begin = end + 1;
    }
  return names;
}

double wrap_angle(double a) {
  return std::remainder(a, 2 * std::numbers::pi);
}

Model load_model(const std::string& path) {
  g_current_file = path;
  return read_model(path);
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string solver_option(const Args& args) {
  const std::string solver = args.get("--solver", "generated");
  if (solver != "generated" && solver != "numeric")
    throw UsageError("--solver: expected generated or numeric, got '" + solver + "'");
  return solver;
}

Shard shard_option(const Args& args) {
  if (!args.has("--shard")) return {};
  try {
    return parse_shard(args.get("--shard"));
  } catch (const std::invalid_argument& error) {
    throw UsageError(std::string("--shard: ") + error.what());
  }
}

SweepOptions sweep_options(const Model& model, const std::vector<double>& parameters,
                           const Args& args) {
  SweepOptions options = default_sweep(model, parameters);
  options.solver = solver_option(args);
  options.samples = args.integer("--samples", options.samples);
  if (options.samples < 1) throw UsageError("--samples must be at least 1");
  options.t0 = args.number("--t0", options.t0);
  options.t1 = args.number("--t1", options.t1);
  return options;
}

}  // namespace mechgen::cli
