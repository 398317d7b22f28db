#include "model/mechanism_graph.hpp"

#include <numeric>

namespace mechgen {

namespace {
struct DisjointSets {
  explicit DisjointSets(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  size_t find(size_t i) { return parent[i] == i ? i : parent[i] = find(parent[i]); }
  void join(size_t a, size_t b) { parent[find(a)] = find(b); }
  std::vector<size_t> parent;
};

SourceLoc model_loc(const Model& model) {
  if (!model.drivers.empty()) return model.drivers.front().loc;
  return model.bodies[static_cast<size_t>(model.ground)].loc;
}
}  // namespace

StructureReport analyze_structure(const Model& model) {
  StructureReport r;
  r.moving_bodies = model.moving_body_count();
  for (const Joint& j : model.joints) r.constraints += j.constraint_count();
  r.drivers = static_cast<int>(model.drivers.size());
  r.mobility = 3 * r.moving_bodies - r.constraints;
  r.loops = static_cast<int>(model.joints.size()) - r.moving_bodies;
  r.ne_unknowns = r.constraints + r.drivers;
  r.ne_equations = 3 * r.moving_bodies;
  return r;
}

void check_structure(const Model& model) {
  const size_t n = model.bodies.size();
  DisjointSets connected(n);
  for (const Joint& j : model.joints)
    connected.join(static_cast<size_t>(j.first), static_cast<size_t>(j.second));
  for (size_t b = 0; b < n; ++b)
    if (connected.find(b) != connected.find(static_cast<size_t>(model.ground)))
      throw ModelError(model.bodies[b].loc,
                       "body '" + model.bodies[b].name + "' is not connected to the ground");

  // Bodies sharing a point name must be pinned together there, else the name is ambiguous.
  for (const auto& [point, locator] : model.named_points()) {
    DisjointSets pinned(n);
    for (const Joint& j : model.joints)
      if (j.type == JointType::revolute && j.point == point)
        pinned.join(static_cast<size_t>(j.first), static_cast<size_t>(j.second));
    for (size_t b = 0; b < n; ++b)
      if (model.bodies[b].find_point(point) &&
          pinned.find(b) != pinned.find(static_cast<size_t>(locator)))
        throw ModelError(model.bodies[b].loc, "point '" + point + "' is on bodies '" +
                                                  model.bodies[static_cast<size_t>(locator)].name +
                                                  "' and '" + model.bodies[b].name +
                                                  "' but no revolute joint pins them there");
  }

  const StructureReport r = analyze_structure(model);
  if (r.mobility != r.drivers)
    throw ModelError(model_loc(model), "mobility is " + std::to_string(r.mobility) + " (3 x " +
                                           std::to_string(r.moving_bodies) + " moving bodies - " +
                                           std::to_string(r.constraints) +
                                           " joint constraints) but " + std::to_string(r.drivers) +
                                           " driver(s) are given");
}

}  // namespace mechgen
