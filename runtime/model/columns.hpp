// The named quantities every solver produces, in one fixed order: the CSV contract of
// ../shared/DESIGN.md. The numeric reference solver and the generated kernels both fill a row of
// exactly these columns, so equivalence is a column-by-column comparison.
#pragma once

#include <string>
#include <vector>

#include "model/model.hpp"

namespace mechgen {

// t; per driver q, qd, qdd, effort; per moving body x, y, th, vx, vy, w, ax, ay, al (centre of
// mass, body angle); per named point x, y; per joint fx, fy (force of first on second body) and
// m for prismatic joints; then per named point vx, vy, ax, ay (appended after the joints, so the
// earlier columns keep their positions).
std::vector<std::string> column_names(const Model& model);

// Offsets of each group of columns inside a row, for writers that fill rows by structure.
struct ColumnLayout {
  int time = 0;
  std::vector<int> driver;       // 4 columns each
  std::vector<int> body;         // per body index; 9 columns each; -1 for the ground
  std::vector<int> point;        // per Model::named_points() entry; 2 columns each
  std::vector<int> joint;        // per joint; 2 or 3 columns
  std::vector<int> point_rates;  // per named point; vx, vy, ax, ay
  int count = 0;
};
ColumnLayout column_layout(const Model& model);

}  // namespace mechgen
