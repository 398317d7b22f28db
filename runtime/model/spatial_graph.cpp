// Spanning tree, circuits and primary / secondary split of a spatial model's joint graph.
#include "model/spatial_graph.hpp"

#include <deque>
#include <limits>
#include <utility>

namespace mechgen {

SpatialGraph build_spatial_graph(const SpatialModel& model) {
  SpatialGraph g;
  const size_t nb = model.bodies.size(), nj = model.joints.size();
  for (size_t j = 0; j < nj; ++j) {
    g.joint_column.push_back(g.cols());
    const SpatialJoint& joint = model.joints[j];
    for (size_t k = 0; k < joint.columns.size(); ++k) {
      SpatialColumn c;
      c.joint = static_cast<int>(j);
      c.index = static_cast<int>(k);
      c.pose_driver = joint.pose_driver;
      g.columns.push_back(c);
    }
  }
  for (size_t d = 0; d < model.drivers.size(); ++d) {
    const SpatialDriver& driver = model.drivers[d];
    SpatialColumn& c = g.columns[static_cast<size_t>(
        g.joint_column[static_cast<size_t>(driver.joint)] + driver.column)];
    c.driver = static_cast<int>(d);
    c.primary = true;
  }
  for (const PoseDriver& pd : model.pose_drivers)
    for (size_t k = 0; k < pd.coordinates.size(); ++k) {
      SpatialColumn& c = g.columns[static_cast<size_t>(
          g.joint_column[static_cast<size_t>(pd.coordinates[k].joint)])];
      c.pose_coordinate = static_cast<int>(k);
      c.primary = pd.coordinates[k].value.has_value();
    }
  for (int c = 0; c < g.cols(); ++c)
    (g.columns[static_cast<size_t>(c)].primary ? g.primary : g.secondary).push_back(c);

  // Spanning tree: breadth first from the ground, joints in model order. A body whose pose is
  // fully prescribed (reached from the ground through joints whose coordinates are all primary:
  // driven joints, a pose driver's prescribed virtual chain, fixed joints) must be reached through
  // them, so that its tree pose is known without solving anything (issue 27: a Stewart platform's
  // top, pose-driven, was reached through a leg). Where the breadth-first tree does not do so, the
  // tree is rebuilt by a 0-1 breadth-first search that takes prescribed joints first.
  std::vector<bool> prescribed(nj, true);
  for (size_t j = 0; j < nj; ++j)
    for (size_t k = 0; k < model.joints[j].columns.size(); ++k)
      prescribed[j] =
          prescribed[j] && g.columns[static_cast<size_t>(g.joint_column[j]) + k].primary;
  g.parent.assign(nb, -1);
  g.parent_joint.assign(nb, -1);
  std::vector<bool> reached(nb, false), in_tree(nj, false);
  auto tree = [&](bool prefer_prescribed) {
    g.parent.assign(nb, -1);
    g.parent_joint.assign(nb, -1);
    g.order.clear();
    reached.assign(nb, false);
    in_tree.assign(nj, false);
    std::vector<int> dist(nb, std::numeric_limits<int>::max());
    std::vector<bool> done(nb, false);
    std::deque<int> queue{model.ground};
    dist[static_cast<size_t>(model.ground)] = 0;
    reached[static_cast<size_t>(model.ground)] = true;
    while (!queue.empty()) {
      const int b = queue.front();
      queue.pop_front();
      if (done[static_cast<size_t>(b)]) continue;
      done[static_cast<size_t>(b)] = true;
      g.order.push_back(b);
      for (size_t j = 0; j < nj; ++j) {
        const SpatialJoint& joint = model.joints[j];
        if (joint.first != b && joint.second != b) continue;
        const int other = joint.first == b ? joint.second : joint.first;
        const int w = prefer_prescribed && prescribed[j] ? 0 : 1;
        if (done[static_cast<size_t>(other)] ||
            dist[static_cast<size_t>(b)] + w >= dist[static_cast<size_t>(other)])
          continue;
        dist[static_cast<size_t>(other)] = dist[static_cast<size_t>(b)] + w;
        reached[static_cast<size_t>(other)] = true;
        g.parent[static_cast<size_t>(other)] = b;
        g.parent_joint[static_cast<size_t>(other)] = static_cast<int>(j);
        if (w == 0)
          queue.push_front(other);
        else
          queue.push_back(other);
      }
    }
    for (size_t b = 0; b < nb; ++b)
      if (g.parent_joint[b] >= 0) in_tree[static_cast<size_t>(g.parent_joint[b])] = true;
  };
  // Bodies whose pose is prescribed, and whether the tree reaches each through prescribed joints.
  auto prescribed_bodies_known = [&] {
    std::vector<bool> known(nb, false);
    known[static_cast<size_t>(model.ground)] = true;
    for (bool grew = true; grew;) {
      grew = false;
      for (size_t j = 0; j < nj; ++j) {
        const SpatialJoint& joint = model.joints[j];
        if (!prescribed[j]) continue;
        for (const auto& [from, to] :
             {std::pair{joint.first, joint.second}, std::pair{joint.second, joint.first}})
          if (known[static_cast<size_t>(from)] && !known[static_cast<size_t>(to)])
            known[static_cast<size_t>(to)] = grew = true;
      }
    }
    for (const int b : g.order)
      if (b != model.ground && known[static_cast<size_t>(b)]) {
        const int p = g.parent[static_cast<size_t>(b)], j = g.parent_joint[static_cast<size_t>(b)];
        if (!known[static_cast<size_t>(p)] || !prescribed[static_cast<size_t>(j)]) return false;
      }
    return true;
  };
  tree(false);
  if (!prescribed_bodies_known()) tree(true);
  for (size_t b = 0; b < nb; ++b)
    if (!reached[b])
      throw ModelError(model.bodies[b].loc, "body '" + model.bodies[b].name +
                                                "' is not connected to the ground: add a joint "
                                                "(or a pose driver) that links it");

  g.path_sign.assign(nb, std::vector<int>(g.columns.size(), 0));
  for (const int b : g.order) {
    if (b == model.ground) continue;
    const int p = g.parent[static_cast<size_t>(b)], j = g.parent_joint[static_cast<size_t>(b)];
    std::vector<int>& sign = g.path_sign[static_cast<size_t>(b)];
    sign = g.path_sign[static_cast<size_t>(p)];
    const SpatialJoint& joint = model.joints[static_cast<size_t>(j)];
    for (size_t k = 0; k < joint.columns.size(); ++k)
      sign[static_cast<size_t>(g.joint_column[static_cast<size_t>(j)]) + k] +=
          joint.first == p ? 1 : -1;
  }
  for (size_t j = 0; j < nj; ++j) {
    if (in_tree[j]) continue;
    const SpatialJoint& joint = model.joints[j];
    std::vector<int> sign(g.columns.size(), 0);
    bool moving = false;
    for (size_t c = 0; c < sign.size(); ++c) {
      sign[c] = g.path_sign[static_cast<size_t>(joint.first)][c] -
                g.path_sign[static_cast<size_t>(joint.second)][c];
      if (g.columns[c].joint == static_cast<int>(j)) sign[c] += 1;
      moving = moving || sign[c] != 0;
    }
    if (!moving)
      throw ModelError(joint.loc, "joint '" + joint.name +
                                      "' closes a circuit with no joint coordinate (every joint "
                                      "on it is fixed): the loop is rigid; remove a fixed joint "
                                      "or merge the bodies");
    g.chords.push_back(static_cast<int>(j));
    g.circuit_sign.push_back(sign);
  }
  return g;
}

std::string column_name(const SpatialModel& model, const SpatialGraph& graph, int column) {
  const SpatialColumn& c = graph.columns[static_cast<size_t>(column)];
  const SpatialJoint& j = model.joints[static_cast<size_t>(c.joint)];
  if (j.columns.size() == 1) return j.name;
  return j.name + ".q" + std::to_string(c.index + 1);
}

}  // namespace mechgen
