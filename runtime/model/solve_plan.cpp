#include "model/solve_plan.hpp"

#include <algorithm>

namespace mechgen {

const char* to_string(GroupKind kind) {
  switch (kind) {
    case GroupKind::driven_revolute:
      return "driven revolute";
    case GroupKind::driven_prismatic:
      return "driven prismatic";
    case GroupKind::rrr:
      return "RRR dyad (circle-circle)";
    case GroupKind::rrp:
      return "RRP dyad (circle-line)";
    case GroupKind::r_slot:
      return "pin in slot (circle-line)";
  }
  return "?";
}

bool has_branch(GroupKind kind) {
  return kind != GroupKind::driven_revolute && kind != GroupKind::driven_prismatic;
}

namespace {

class Planner {
 public:
  Planner(const Model& model, int reference)
      : model_(model), located_(model.bodies.size(), false), used_(model.joints.size(), false) {
    located_[static_cast<size_t>(reference)] = true;
  }

  // Greedily adds the first group found (bodies and joints in file order) until none applies.
  void run(SolvePlan& plan) {
    while (next_group(plan)) {
    }
    for (size_t b = 0; b < located_.size(); ++b)
      if (!located_[b]) plan.unsolved.push_back(static_cast<int>(b));
  }

 private:
  bool known(int body) const { return located_[static_cast<size_t>(body)]; }
  int driver_of(int joint) const {
    for (size_t d = 0; d < model_.drivers.size(); ++d)
      if (model_.drivers[d].joint == joint) return static_cast<int>(d);
    return -1;
  }
  // Unused joints between `body` and a located body, of the given type.
  std::vector<int> links_to_known(int body, JointType type) const {
    std::vector<int> result;
    for (size_t j = 0; j < model_.joints.size(); ++j) {
      const Joint& joint = model_.joints[j];
      if (used_[j] || joint.type != type) continue;
      if ((joint.first == body && known(joint.second)) ||
          (joint.second == body && known(joint.first)))
        result.push_back(static_cast<int>(j));
    }
    return result;
  }
  std::vector<int> links_between(int a, int b, JointType type) const {
    std::vector<int> result;
    for (size_t j = 0; j < model_.joints.size(); ++j) {
      const Joint& joint = model_.joints[j];
      if (used_[j] || joint.type != type) continue;
      if ((joint.first == a && joint.second == b) || (joint.first == b && joint.second == a))
        result.push_back(static_cast<int>(j));
    }
    return result;
  }

  void add(SolvePlan& plan, GroupKind kind, std::vector<int> bodies, std::vector<int> joints,
           int driver = -1) {
    SolveGroup group{kind, bodies, joints, driver, "g" + std::to_string(plan.groups.size() + 1)};
    for (int b : bodies) {
      located_[static_cast<size_t>(b)] = true;
      group.name += "_" + model_.bodies[static_cast<size_t>(b)].name;
    }
    for (int j : joints) used_[static_cast<size_t>(j)] = true;
    plan.groups.push_back(group);
  }

  bool next_group(SolvePlan& plan) {
    const int n = static_cast<int>(model_.bodies.size());
    // One body: driven joints first, then a pin and a slot.
    for (int b = 0; b < n; ++b) {
      if (known(b)) continue;
      for (int j : links_to_known(b, JointType::revolute)) {
        const int d = driver_of(j);
        if (d >= 0) return add(plan, GroupKind::driven_revolute, {b}, {j}, d), true;
      }
      for (int j : links_to_known(b, JointType::prismatic)) {
        const int d = driver_of(j);
        if (d >= 0 && model_.joints[static_cast<size_t>(j)].second == b)
          return add(plan, GroupKind::driven_prismatic, {b}, {j}, d), true;
      }
    }
    for (int b = 0; b < n; ++b) {
      if (known(b)) continue;
      const std::vector<int> pins = links_to_known(b, JointType::revolute);
      const std::vector<int> slots = links_to_known(b, JointType::pin_in_slot);
      if (pins.empty() || slots.empty() || driver_of(slots.front()) >= 0) continue;
      // Only a pin of b in a located slot has a closed form here; a slot carried by b around a
      // located pin is left unsolved (reported by `check`).
      if (model_.joints[static_cast<size_t>(slots.front())].second != b) continue;
      return add(plan, GroupKind::r_slot, {b}, {pins.front(), slots.front()}), true;
    }
    // Two bodies pinned together, each tied to a located body.
    for (int b1 = 0; b1 < n; ++b1) {
      if (known(b1)) continue;
      const std::vector<int> pins1 = links_to_known(b1, JointType::revolute);
      if (pins1.empty()) continue;
      for (int b2 = 0; b2 < n; ++b2) {
        if (b2 == b1 || known(b2)) continue;
        const std::vector<int> middle = links_between(b1, b2, JointType::revolute);
        if (middle.empty()) continue;
        const std::vector<int> pins2 = links_to_known(b2, JointType::revolute);
        if (!pins2.empty() && b1 < b2)
          return add(plan, GroupKind::rrr, {b1, b2},
                     {pins1.front(), middle.front(), pins2.front()}),
                 true;
        for (int j : links_to_known(b2, JointType::prismatic))
          if (model_.joints[static_cast<size_t>(j)].second == b2 && driver_of(j) < 0)
            return add(plan, GroupKind::rrp, {b1, b2}, {pins1.front(), middle.front(), j}), true;
      }
    }
    return false;
  }

  const Model& model_;
  std::vector<bool> located_;
  std::vector<bool> used_;
};

}  // namespace

SolvePlan make_solve_plan(const Model& model) {
  std::vector<int> candidates{model.ground};
  for (const Driver& d : model.drivers)
    candidates.push_back(model.joints[static_cast<size_t>(d.joint)].first);
  for (size_t b = 0; b < model.bodies.size(); ++b) candidates.push_back(static_cast<int>(b));
  SolvePlan first_try;
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (std::find(candidates.begin(), candidates.begin() + static_cast<long>(i), candidates[i]) !=
        candidates.begin() + static_cast<long>(i))
      continue;
    SolvePlan plan;
    plan.reference = candidates[i];
    Planner(model, plan.reference).run(plan);
    if (plan.complete()) return plan;
    if (i == 0) first_try = plan;
  }
  return first_try;
}

std::string describe(const Model& model, const SolveGroup& group) {
  std::string text = group.name + ": " + to_string(group.kind) + ", bodies";
  for (int b : group.bodies) text += " " + model.bodies[static_cast<size_t>(b)].name;
  text += ", joints";
  for (int j : group.joints) text += " " + model.joints[static_cast<size_t>(j)].name;
  if (group.driver >= 0)
    text += ", driver " + model.drivers[static_cast<size_t>(group.driver)].name;
  return text;
}

}  // namespace mechgen
