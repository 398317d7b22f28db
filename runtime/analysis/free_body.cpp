#include "analysis/free_body.hpp"

#include <cmath>
#include <stdexcept>

namespace mechgen::analysis {

namespace {

Eigen::Vector2d perp(const Eigen::Vector2d& v) {
  return {-v.y(), v.x()};
}

Eigen::Vector2d rotate(double th, const Eigen::Vector2d& v) {
  const double c = std::cos(th), s = std::sin(th);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

}  // namespace

FreeBodies::FreeBodies(const Model& model, const std::vector<double>& parameters,
                       const std::vector<std::string>& columns)
    : model_(model), subs_(model.substitutions(parameters)) {
  for (size_t i = 0; i < columns.size(); ++i) index_.emplace(columns[i], static_cast<int>(i));
  gravity_ = {model.evaluate(model.gravity.x, subs_), model.evaluate(model.gravity.y, subs_)};
  time_ = column("t");
  const size_t n = model.bodies.size();
  body_cols_.resize(n);
  mass_.assign(n, 0);
  inertia_.assign(n, 0);
  com_local_.assign(n, Eigen::Vector2d::Zero());
  for (size_t b = 0; b < n; ++b) {
    const Body& body = model.bodies[b];
    const MassProperties& m = body.mass;
    if (m.source != MassProperties::Source::none) {
      mass_[b] = model.evaluate(m.mass, subs_);
      inertia_[b] = model.evaluate(m.inertia, subs_);
      com_local_[b] = {model.evaluate(m.com.x, subs_), model.evaluate(m.com.y, subs_)};
    }
    if (body.ground) continue;
    const std::string& p = body.name;
    body_cols_[b] = {column(p + ".x"),  column(p + ".y"),  column(p + ".th"),
                     column(p + ".vx"), column(p + ".vy"), column(p + ".w"),
                     column(p + ".ax"), column(p + ".ay"), column(p + ".al")};
  }
  for (const Joint& j : model.joints) {
    column(j.name + ".fx");
    column(j.name + ".fy");
    if (j.type == JointType::prismatic) column(j.name + ".m");
  }
  for (const Driver& d : model.drivers) column(d.name + ".effort");
  for (const auto& [name, body] : model.named_points()) {
    column(name + ".x");
    column(name + ".y");
  }
  const auto compiled = [&](const Expr& e) {
    // A map of symbols: exact lookups, linear in the parameter count (see Model::evaluate).
    return numeric::TimeExpression(
        e.ex.subs(subs_,
                  GiNaC::subs_options::no_pattern | GiNaC::subs_options::pattern_is_not_product),
        model.t);
  };
  for (const ForceElement& f : model.forces) {
    AppliedLoad a;
    if (f.type == ForceType::spring_damper)
      a.k = compiled(f.stiffness), a.c = compiled(f.damping),
      a.free_length = compiled(f.free_length);
    if (f.type == ForceType::force) a.fx = compiled(f.force.x), a.fy = compiled(f.force.y);
    if (f.type == ForceType::torque) a.torque = compiled(f.torque);
    applied_.push_back(std::move(a));
  }
}

int FreeBodies::column(const std::string& name) const {
  if (const auto it = index_.find(name); it != index_.end()) return it->second;
  throw std::invalid_argument("no column '" + name + "' (is this a sweep of model '" + model_.name +
                              "'?)");
}

Eigen::Vector2d FreeBodies::point(const std::string& name, const std::vector<double>& row) const {
  return {row[static_cast<size_t>(column(name + ".x"))],
          row[static_cast<size_t>(column(name + ".y"))]};
}

std::vector<FreeBody> FreeBodies::at(const std::vector<double>& row) const {
  const auto value = [&](int c) { return row[static_cast<size_t>(c)]; };
  const auto named = [&](const std::string& name) { return value(column(name)); };
  const size_t n = model_.bodies.size();
  std::vector<FreeBody> bodies(n);
  // The ground frame is the world: its pose is the identity and it does not move.
  for (size_t b = 0; b < n; ++b) {
    FreeBody& f = bodies[b];
    f.body = static_cast<int>(b);
    f.mass = mass_[b];
    f.inertia = inertia_[b];
    if (model_.bodies[b].ground) {
      f.com = com_local_[b];
      continue;
    }
    const BodyColumns& c = body_cols_[b];
    f.com = {value(c.x), value(c.y)};
    f.acc = {value(c.ax), value(c.ay)};
    f.th = value(c.th);
    f.w = value(c.w);
    f.al = value(c.al);
  }
  const auto angle = [&](int b) {
    return model_.bodies[static_cast<size_t>(b)].ground ? 0.0 : bodies[static_cast<size_t>(b)].th;
  };

  for (const Joint& j : model_.joints) {
    const Eigen::Vector2d p = point(j.point, row);
    const Eigen::Vector2d force{named(j.name + ".fx"), named(j.name + ".fy")};
    bodies[static_cast<size_t>(j.second)].forces.push_back({j.name, p, force});
    bodies[static_cast<size_t>(j.first)].forces.push_back({j.name, p, -force});
    if (j.type == JointType::prismatic) {
      const double m = named(j.name + ".m");
      bodies[static_cast<size_t>(j.second)].couples.push_back({j.name, m, p});
      bodies[static_cast<size_t>(j.first)].couples.push_back({j.name, -m, p});
    }
  }
  for (const Driver& d : model_.drivers) {
    const Joint& j = model_.joints[static_cast<size_t>(d.joint)];
    const double effort = named(d.name + ".effort");
    if (d.kind == DriverKind::angle) {
      const Eigen::Vector2d p = point(j.point, row);
      bodies[static_cast<size_t>(j.second)].couples.push_back({d.name, effort, p});
      bodies[static_cast<size_t>(j.first)].couples.push_back({d.name, -effort, p});
    } else {
      // Along the line's unit direction, which is fixed in the first body.
      Eigen::Vector2d along{model_.evaluate(j.line.direction.x, subs_),
                            model_.evaluate(j.line.direction.y, subs_)};
      along = rotate(angle(j.first), along.normalized());
      const Eigen::Vector2d p = point(j.point, row);
      bodies[static_cast<size_t>(j.second)].forces.push_back({d.name, p, effort * along});
      bodies[static_cast<size_t>(j.first)].forces.push_back({d.name, p, -effort * along});
    }
  }
  if (!model_.forces.empty()) {
    const double t = value(time_);
    // A point's velocity from its body's centre of mass: v_G + w x (P - G); the ground is still.
    const auto velocity = [&](int b, const Eigen::Vector2d& p) -> Eigen::Vector2d {
      if (model_.bodies[static_cast<size_t>(b)].ground) return Eigen::Vector2d::Zero();
      const BodyColumns& c = body_cols_[static_cast<size_t>(b)];
      const FreeBody& f = bodies[static_cast<size_t>(b)];
      return Eigen::Vector2d{value(c.vx), value(c.vy)} + f.w * perp(p - f.com);
    };
    for (size_t i = 0; i < model_.forces.size(); ++i) {
      const ForceElement& e = model_.forces[i];
      const AppliedLoad& load = applied_[i];
      switch (e.type) {
        case ForceType::spring_damper: {
          const Eigen::Vector2d pa = point(e.point_a, row), pb = point(e.point_b, row);
          const Eigen::Vector2d d = pb - pa;
          const double length = d.norm();
          const Eigen::Vector2d u =
              length > 0 ? Eigen::Vector2d(d / length) : Eigen::Vector2d::Zero();
          const double rate = u.dot(velocity(e.body_b, pb) - velocity(e.body_a, pa));
          const double tension = load.k(t) * (length - load.free_length(t)) + load.c(t) * rate;
          bodies[static_cast<size_t>(e.body_b)].forces.push_back({e.name, pb, -tension * u});
          bodies[static_cast<size_t>(e.body_a)].forces.push_back({e.name, pa, tension * u});
          break;
        }
        case ForceType::force:
          bodies[static_cast<size_t>(e.body_a)].forces.push_back(
              {e.name, point(e.point_a, row), {load.fx(t), load.fy(t)}});
          break;
        case ForceType::torque:
          bodies[static_cast<size_t>(e.body_a)].couples.push_back(
              {e.name, load.torque(t), std::nullopt});
          break;
      }
    }
  }
  return bodies;
}

Resultant resultant(const FreeBody& body, const Eigen::Vector2d& gravity) {
  Resultant r;
  r.force = body.mass * (gravity - body.acc);
  r.moment = -body.inertia * body.al;
  for (const PointLoad& load : body.forces) {
    r.force += load.force;
    r.moment += cross(load.at - body.com, load.force);
  }
  for (const Couple& c : body.couples) r.moment += c.moment;
  return r;
}

}  // namespace mechgen::analysis
