// The worst difference between two sweeps of the same columns, each column to its own scale
// (shared by the compiled-in and the on-demand spatial kernel tests).
#pragma once

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace mechgen::test {

inline bool is_reaction(const std::string& column) {
  for (const char* suffix : {".fx", ".fy", ".fz", ".mx", ".my", ".mz"}) {
    const std::string s(suffix);
    if (column.size() > s.size() && column.compare(column.size() - s.size(), s.size(), s) == 0)
      return true;
  }
  return false;
}

// Every column of `generated` against `numeric` to its scale: the column's largest magnitude, at
// least 1 % of the largest of its kind (the suffix without digits: a spherical joint's q1, q2, q3
// are one kind) and 1e-6 (SI: 1e-15 absolute: a kind that stays near round-off level over the
// whole step, such as the standing bioloid's vertical velocities, has no scale of its own; `floor`
// replaces that 1e-6); a
// reaction's at least 1e-3 of the largest reaction force or moment (a component that is zero, a
// revolute's moments in chebyshev_spatial, the numeric solver's at 1e-16, has none either).
// Returns the worst relative difference, its column in `where`.
inline double worst_column_difference(const std::vector<std::string>& columns,
                                      const std::vector<std::vector<double>>& numeric,
                                      const std::vector<std::vector<double>>& generated,
                                      std::string& where, double floor = 1e-6) {
  auto kind = [](const std::string& c) {
    std::string k;
    for (const char ch : c.substr(c.rfind('.') + 1))
      if (ch < '0' || ch > '9') k += ch;
    return k;
  };
  std::map<std::string, double> kind_scale;
  double force_scale = 0, moment_scale = 0;
  for (const auto& row : numeric)
    for (size_t c = 0; c < columns.size(); ++c) {
      const std::string& n = columns[c];
      kind_scale[kind(n)] = std::max(kind_scale[kind(n)], std::abs(row[c]));
      double& reaction_scale = n[n.size() - 2] == 'f' ? force_scale : moment_scale;
      if (is_reaction(n)) reaction_scale = std::max(reaction_scale, std::abs(row[c]));
    }
  double worst = 0;
  for (size_t c = 0; c < columns.size(); ++c) {
    double scale = std::max(floor, 0.01 * kind_scale[kind(columns[c])]);
    if (is_reaction(columns[c]))
      scale = std::max(scale, 1e-3 * std::max(force_scale, moment_scale));
    for (const auto& row : numeric) scale = std::max(scale, std::abs(row[c]));
    for (size_t r = 0; r < numeric.size(); ++r) {
      const double e = std::abs(generated[r][c] - numeric[r][c]) / scale;
      if (!(e <= worst)) worst = e, where = columns[c];
    }
  }
  return worst;
}

}  // namespace mechgen::test
