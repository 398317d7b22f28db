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
    case GroupKind::slot_on_body:
      return "slot on the body around a pin (circle-line)";
    case GroupKind::prp:
      return "PRP dyad (line-line)";
    case GroupKind::rpr:
      return "RPR driven-length cylinder (triangle)";
    case GroupKind::passive_rpr:
      return "RPR dyad with a passive slider (circle-line)";
    case GroupKind::iterative:
      return "no closed form (Newton-Raphson)";
  }
  return "?";
}

bool has_branch(GroupKind kind) {
  return kind != GroupKind::driven_revolute && kind != GroupKind::driven_prismatic &&
         kind != GroupKind::prp && kind != GroupKind::iterative;
}

bool is_iterative(GroupKind kind) {
  return kind == GroupKind::iterative;
}

namespace {

class Planner {
 public:
  Planner(const Model& model, int reference, bool allow_iterative)
      : model_(model),
        allow_iterative_(allow_iterative),
        located_(model.bodies.size(), false),
        used_(model.joints.size(), false) {
    located_[static_cast<size_t>(reference)] = true;
  }

  // Greedily adds the first group found (bodies and joints in file order) until none applies;
  // a closed form always wins over the iterative fallback.
  void run(SolvePlan& plan) {
    while (next_group(plan) || more_closed_forms(plan) ||
           (allow_iterative_ && iterative_group(plan))) {
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

  const Joint& joint(int j) const { return model_.joints[static_cast<size_t>(j)]; }

  // The closed forms added after the first ones (searched later, so that the plans of models
  // that need only the first kinds stay as they were).
  bool more_closed_forms(SolvePlan& plan) {
    const int n = static_cast<int>(model_.bodies.size());
    // A body pinned to a located point whose own slot runs around a located pin.
    for (int b = 0; b < n; ++b) {
      if (known(b)) continue;
      const std::vector<int> pins = links_to_known(b, JointType::revolute);
      if (pins.empty()) continue;
      for (int j : links_to_known(b, JointType::pin_in_slot))
        if (driver_of(j) < 0 && joint(j).first == b)
          return add(plan, GroupKind::slot_on_body, {b}, {pins.front(), j}), true;
    }
    // Two bodies pinned together, each sliding (undriven) on a located body's line.
    auto free_slides = [&](int b) {
      std::vector<int> result;
      for (int j : links_to_known(b, JointType::prismatic))
        if (joint(j).second == b && driver_of(j) < 0) result.push_back(j);
      return result;
    };
    for (int b1 = 0; b1 < n; ++b1) {
      if (known(b1) || free_slides(b1).empty()) continue;
      for (int b2 = b1 + 1; b2 < n; ++b2) {
        if (known(b2) || free_slides(b2).empty()) continue;
        const std::vector<int> middle = links_between(b1, b2, JointType::revolute);
        if (!middle.empty())
          return add(plan, GroupKind::prp, {b1, b2},
                     {free_slides(b1).front(), middle.front(), free_slides(b2).front()}),
                 true;
      }
    }
    // A driven-length cylinder (c1, c2) from a located pin (on c1) to a link pinned to a located
    // body: the pin distance is known from the length, the link closes a triangle.
    for (size_t d = 0; d < model_.drivers.size(); ++d) {
      const int jp = model_.drivers[d].joint;
      if (joint(jp).type != JointType::prismatic) continue;
      const int ends[2] = {joint(jp).first, joint(jp).second};
      if (known(ends[0]) || known(ends[1])) continue;
      for (int side = 0; side < 2; ++side) {
        const int c1 = ends[side], c2 = ends[1 - side];
        const std::vector<int> base = links_to_known(c1, JointType::revolute);
        if (base.empty()) continue;
        for (int link = 0; link < n; ++link) {
          if (known(link) || link == c1 || link == c2) continue;
          const std::vector<int> tip = links_between(c2, link, JointType::revolute);
          const std::vector<int> hinge = links_to_known(link, JointType::revolute);
          if (tip.empty() || hinge.empty()) continue;
          return add(plan, GroupKind::rpr, {link, c1, c2},
                     {hinge.front(), base.front(), jp, tip.front()}, static_cast<int>(d)),
                 true;
        }
      }
    }
    // Two bodies sliding along each other (an undriven prismatic), each pinned to a located
    // body: the link (the joint's first body, which carries the line) and the block of an
    // inverted slider-crank, or the barrel and the rod of a passive strut.
    for (size_t j = 0; j < model_.joints.size(); ++j) {
      const int jp = static_cast<int>(j);
      if (used_[j] || joint(jp).type != JointType::prismatic || driver_of(jp) >= 0) continue;
      const int link = joint(jp).first, block = joint(jp).second;
      if (known(link) || known(block)) continue;
      const std::vector<int> hinge = links_to_known(link, JointType::revolute);
      const std::vector<int> pin = links_to_known(block, JointType::revolute);
      if (hinge.empty() || pin.empty()) continue;
      return add(plan, GroupKind::passive_rpr, {link, block}, {hinge.front(), jp, pin.front()}),
             true;
    }
    return false;
  }

  // The fallback: the smallest set of unlocated bodies (up to five) whose undriven joints to each
  // other and to located bodies remove exactly their freedom, reachable from the located bodies
  // through revolute joints (whose angles become the unknowns of a Newton solve).
  bool iterative_group(SolvePlan& plan) {
    std::vector<int> free;
    for (size_t b = 0; b < model_.bodies.size(); ++b)
      if (!located_[b]) free.push_back(static_cast<int>(b));
    const int most = std::min<int>(5, static_cast<int>(free.size()));
    for (int size = 2; size <= most; ++size) {
      std::vector<int> pick(static_cast<size_t>(size));
      for (int i = 0; i < size; ++i) pick[static_cast<size_t>(i)] = i;
      while (true) {
        std::vector<int> bodies;
        for (int i : pick) bodies.push_back(free[static_cast<size_t>(i)]);
        if (try_iterative(plan, bodies)) return true;
        int i = size - 1;  // next combination in lexicographic order
        while (i >= 0 && pick[static_cast<size_t>(i)] == static_cast<int>(free.size()) - size + i)
          --i;
        if (i < 0) break;
        ++pick[static_cast<size_t>(i)];
        for (int k = i + 1; k < size; ++k)
          pick[static_cast<size_t>(k)] = pick[static_cast<size_t>(k - 1)] + 1;
      }
    }
    return false;
  }

  bool try_iterative(SolvePlan& plan, const std::vector<int>& set) {
    auto inside = [&](int b) { return std::find(set.begin(), set.end(), b) != set.end(); };
    std::vector<int> joints;
    int constraints = 0;
    for (size_t j = 0; j < model_.joints.size(); ++j) {
      const Joint& jt = model_.joints[j];
      if (used_[j]) continue;
      const bool a = inside(jt.first), b = inside(jt.second);
      if (!(a || b) || !(a || known(jt.first)) || !(b || known(jt.second))) continue;
      if (driver_of(static_cast<int>(j)) >= 0) return false;  // drivers only in closed forms
      joints.push_back(static_cast<int>(j));
      constraints += jt.type == JointType::pin_in_slot ? 1 : 2;
    }
    if (constraints != 3 * static_cast<int>(set.size())) return false;
    // Spanning tree through revolute joints, grown from the located bodies.
    std::vector<int> order, tree;
    std::vector<bool> reached(model_.bodies.size(), false);
    for (size_t b = 0; b < reached.size(); ++b) reached[b] = located_[b];
    for (bool grew = true; grew;) {
      grew = false;
      for (int j : joints) {
        if (joint(j).type != JointType::revolute) continue;
        const int f = joint(j).first, s = joint(j).second;
        const int to = reached[static_cast<size_t>(f)] && !reached[static_cast<size_t>(s)]   ? s
                       : reached[static_cast<size_t>(s)] && !reached[static_cast<size_t>(f)] ? f
                                                                                             : -1;
        if (to < 0) continue;
        reached[static_cast<size_t>(to)] = grew = true;
        order.push_back(to);
        tree.push_back(j);
      }
    }
    if (order.size() != set.size()) return false;
    for (int j : joints)
      if (std::find(tree.begin(), tree.end(), j) == tree.end()) tree.push_back(j);
    add(plan, GroupKind::iterative, order, tree);
    return true;
  }

  const Model& model_;
  bool allow_iterative_;
  std::vector<bool> located_;
  std::vector<bool> used_;
};

}  // namespace

// A closed form from any reference beats an iterative group; the fallback plans from the ground.
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
    Planner(model, plan.reference, false).run(plan);
    if (plan.complete()) return plan;
    if (i == 0) first_try = plan;
  }
  SolvePlan fallback;
  fallback.reference = model.ground;
  Planner(model, fallback.reference, true).run(fallback);
  return fallback.complete() ? fallback : first_try;
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
