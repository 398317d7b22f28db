// A circuit as a loop of joints (spatial_circuit_loop.hpp).
#include "spatial_circuit_loop.hpp"

#include <algorithm>

namespace mechgen::gen {

std::vector<CircuitStep> circuit_loop(const SpatialModel& m, const SpatialGraph& g, int circuit) {
  const int chord = g.chords[static_cast<size_t>(circuit)];
  const SpatialJoint& cj = m.joints[static_cast<size_t>(chord)];
  const auto ancestors = [&g](int b) {
    std::vector<int> out{b};
    while (g.parent[static_cast<size_t>(b)] >= 0)
      out.push_back(b = g.parent[static_cast<size_t>(b)]);
    return out;
  };
  const std::vector<int> a = ancestors(cj.first), b = ancestors(cj.second);
  size_t ia = 0, ib = 0;
  while (std::find(b.begin(), b.end(), a[ia]) == b.end()) ++ia;
  while (b[ib] != a[ia]) ++ib;
  std::vector<CircuitStep> steps;
  for (size_t k = ia; k-- > 0;) {
    const int j = g.parent_joint[static_cast<size_t>(a[k])];
    steps.push_back({j, m.joints[static_cast<size_t>(j)].first == a[k + 1] ? 1 : -1});
  }
  steps.push_back({chord, 1});
  for (size_t k = 0; k < ib; ++k) {
    const int j = g.parent_joint[static_cast<size_t>(b[k])];
    steps.push_back({j, m.joints[static_cast<size_t>(j)].first == b[k] ? 1 : -1});
  }
  return steps;
}

}  // namespace mechgen::gen
