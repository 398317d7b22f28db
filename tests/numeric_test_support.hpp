// Helpers shared by the reference solver's tests: column lookup and an independent power balance.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "model/columns.hpp"
#include "model/model.hpp"
#include "numeric/reference_solver.hpp"

namespace mechgen::numeric::testing {

// Column name -> index in a solver row.
class Columns {
 public:
  explicit Columns(const Model& model) {
    const std::vector<std::string> names = column_names(model);
    for (size_t i = 0; i < names.size(); ++i) index_[names[i]] = i;
  }
  size_t operator()(const std::string& name) const {
    const auto it = index_.find(name);
    if (it == index_.end()) ADD_FAILURE() << "no column " << name;
    return it == index_.end() ? 0 : it->second;
  }
  bool has(const std::string& name) const { return index_.count(name) > 0; }

 private:
  std::map<std::string, size_t> index_;
};

struct PowerBalance {
  double residual = 0;  // driver power + load power - dT/dt - dV/dt
  double scale = 0;     // sum of the magnitudes of every term
};

// The power balance of one solved row, from the row's own columns: driver effort x rate, the power
// of every applied load (evaluated here from the model, independently of the solver), and the exact
// derivative of the kinetic and gravitational energy dT/dt = sum m v.a + I w al,
// dV/dt = -sum m g.v.
inline PowerBalance power_balance(const Model& model, const std::vector<double>& parameters,
                                  const std::vector<double>& row) {
  const Columns col(model);
  GiNaC::exmap subs = model.substitutions(parameters);
  subs[model.t] = row[col("t")];
  auto eval = [&](const Expr& e) { return model.evaluate(e, subs); };
  const Eigen::Vector2d g(eval(model.gravity.x), eval(model.gravity.y));
  PowerBalance out;
  auto term = [&](double p) {
    out.residual += p;
    out.scale += std::abs(p);
  };
  for (const Driver& d : model.drivers)
    term(row[col(d.name + ".effort")] * row[col(d.name + ".qd")]);
  // World position and velocity of a body's point, from the body's centre-of-mass columns.
  auto point_state = [&](int body, const std::string& point, Eigen::Vector2d& p,
                         Eigen::Vector2d& v) {
    const BodyPoint* bp = model.bodies[body].find_point(point);
    const Eigen::Vector2d local(eval(bp->local.x), eval(bp->local.y));
    if (model.bodies[body].ground) {
      p = local;
      v.setZero();
      return;
    }
    const std::string& n = model.bodies[body].name;
    const double th = row[col(n + ".th")], w = row[col(n + ".w")];
    Eigen::Vector2d com = Eigen::Vector2d::Zero();
    if (model.bodies[body].mass.source != MassProperties::Source::none)
      com =
          Eigen::Vector2d(eval(model.bodies[body].mass.com.x), eval(model.bodies[body].mass.com.y));
    const Eigen::Rotation2Dd R(th);
    const Eigen::Vector2d gpos(row[col(n + ".x")], row[col(n + ".y")]);
    const Eigen::Vector2d gvel(row[col(n + ".vx")], row[col(n + ".vy")]);
    const Eigen::Vector2d rel = R * (local - com);
    p = gpos + rel;
    v = gvel + w * Eigen::Vector2d(-rel.y(), rel.x());
  };
  for (const ForceElement& f : model.forces) {
    switch (f.type) {
      case ForceType::spring_damper: {
        Eigen::Vector2d pa, va, pb, vb;
        point_state(f.body_a, f.point_a, pa, va);
        point_state(f.body_b, f.point_b, pb, vb);
        const Eigen::Vector2d d = pb - pa;
        const double length = d.norm(), rate = d.dot(vb - va) / length;
        const double tension =
            eval(f.stiffness) * (length - eval(f.free_length)) + eval(f.damping) * rate;
        term(-tension * rate);
        break;
      }
      case ForceType::force: {
        Eigen::Vector2d p, v;
        point_state(f.body_a, f.point_a, p, v);
        term(Eigen::Vector2d(eval(f.force.x), eval(f.force.y)).dot(v));
        break;
      }
      case ForceType::torque:
        if (!model.bodies[f.body_a].ground)
          term(eval(f.torque) * row[col(model.bodies[f.body_a].name + ".w")]);
        break;
    }
  }
  for (const Body& b : model.bodies) {
    if (b.ground || b.mass.source == MassProperties::Source::none) continue;
    const double m = eval(b.mass.mass), inertia = eval(b.mass.inertia);
    const Eigen::Vector2d v(row[col(b.name + ".vx")], row[col(b.name + ".vy")]);
    const Eigen::Vector2d a(row[col(b.name + ".ax")], row[col(b.name + ".ay")]);
    const double w = row[col(b.name + ".w")], al = row[col(b.name + ".al")];
    term(-m * v.dot(a));      // - dT/dt (translation)
    term(-inertia * w * al);  // - dT/dt (rotation)
    term(m * g.dot(v));       // - dV/dt = + m g.v
  }
  return out;
}

// The Newton-Euler balance of every moving body recomputed from the row alone: joint forces
// (first on second, at the joint point's reported position; prismatic moments), driver efforts,
// gravity and the applied loads (evaluated here from the model) against m a_G and I alpha from the
// row. Returns the worst |residual| over bodies and components, relative to the largest sum of
// term magnitudes of any body in the sample (forces and moments separately): an independent check
// of the reported reactions' values, points and signs.
inline double newton_euler_balance(const Model& model, const std::vector<double>& parameters,
                                   const std::vector<double>& row) {
  const Columns col(model);
  GiNaC::exmap subs = model.substitutions(parameters);
  subs[model.t] = row[col("t")];
  auto eval = [&](const Expr& e) { return model.evaluate(e, subs); };
  const Eigen::Vector2d g(eval(model.gravity.x), eval(model.gravity.y));
  const size_t n = model.bodies.size();
  std::vector<Eigen::Vector3d> sum(n, Eigen::Vector3d::Zero()), scale(n, Eigen::Vector3d::Zero());
  auto centre = [&](size_t b) {
    const std::string& name = model.bodies[b].name;
    return Eigen::Vector2d(row[col(name + ".x")], row[col(name + ".y")]);
  };
  auto angle = [&](int b) {
    return model.bodies[b].ground ? 0.0 : row[col(model.bodies[b].name + ".th")];
  };
  auto add = [&](int b, const Eigen::Vector2d& f, const Eigen::Vector2d& p, double moment) {
    if (model.bodies[b].ground) return;
    const Eigen::Vector2d rho = p - centre(b);
    const Eigen::Vector3d term(f.x(), f.y(), rho.x() * f.y() - rho.y() * f.x() + moment);
    sum[b] += term;
    scale[b] += term.cwiseAbs();
  };
  auto point = [&](const std::string& name) {
    return Eigen::Vector2d(row[col(name + ".x")], row[col(name + ".y")]);
  };
  auto body_point = [&](int b, const std::string& name) {
    const BodyPoint* bp = model.bodies[b].find_point(name);
    const Eigen::Vector2d local(eval(bp->local.x), eval(bp->local.y));
    if (model.bodies[b].ground) return local;
    Eigen::Vector2d com = Eigen::Vector2d::Zero();
    if (model.bodies[b].mass.source != MassProperties::Source::none)
      com = Eigen::Vector2d(eval(model.bodies[b].mass.com.x), eval(model.bodies[b].mass.com.y));
    return Eigen::Vector2d(centre(b) + Eigen::Rotation2Dd(angle(b)) * (local - com));
  };
  for (const Joint& j : model.joints) {
    const Eigen::Vector2d f(row[col(j.name + ".fx")], row[col(j.name + ".fy")]);
    const double m = j.type == JointType::prismatic ? row[col(j.name + ".m")] : 0.0;
    const Eigen::Vector2d p = point(j.point);
    add(j.second, f, p, m);
    add(j.first, -f, p, -m);
  }
  for (const Driver& d : model.drivers) {
    const Joint& j = model.joints[d.joint];
    const double effort = row[col(d.name + ".effort")];
    if (d.kind == DriverKind::angle) {
      add(j.second, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), effort);
      add(j.first, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), -effort);
    } else {
      const Eigen::Vector2d dir(eval(j.line.direction.x), eval(j.line.direction.y));
      const Eigen::Vector2d f = effort * (Eigen::Rotation2Dd(angle(j.first)) * dir.normalized());
      add(j.second, f, point(j.point), 0);
      add(j.first, -f, point(j.point), 0);
    }
  }
  for (const ForceElement& fe : model.forces) {
    switch (fe.type) {
      case ForceType::spring_damper: {
        const Eigen::Vector2d pa = body_point(fe.body_a, fe.point_a);
        const Eigen::Vector2d pb = body_point(fe.body_b, fe.point_b);
        // Spring rate from the power-balance helper's point velocities is not needed here: the
        // damping force uses the length rate, computed from the centre-of-mass velocities.
        auto velocity = [&](int b, const Eigen::Vector2d& p) {
          if (model.bodies[b].ground) return Eigen::Vector2d(Eigen::Vector2d::Zero());
          const std::string& name = model.bodies[b].name;
          const Eigen::Vector2d rel = p - centre(static_cast<size_t>(b));
          return Eigen::Vector2d(Eigen::Vector2d(row[col(name + ".vx")], row[col(name + ".vy")]) +
                                 row[col(name + ".w")] * Eigen::Vector2d(-rel.y(), rel.x()));
        };
        const Eigen::Vector2d d = pb - pa;
        const Eigen::Vector2d u = d.normalized();
        const double rate = u.dot(velocity(fe.body_b, pb) - velocity(fe.body_a, pa));
        const double tension =
            eval(fe.stiffness) * (d.norm() - eval(fe.free_length)) + eval(fe.damping) * rate;
        add(fe.body_a, tension * u, pa, 0);
        add(fe.body_b, -tension * u, pb, 0);
        break;
      }
      case ForceType::force:
        add(fe.body_a, Eigen::Vector2d(eval(fe.force.x), eval(fe.force.y)),
            body_point(fe.body_a, fe.point_a), 0);
        break;
      case ForceType::torque:
        add(fe.body_a, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), eval(fe.torque));
        break;
    }
  }
  std::vector<Eigen::Vector3d> residual(n, Eigen::Vector3d::Zero());
  Eigen::Vector3d largest = Eigen::Vector3d::Zero();  // force and moment scales of the sample
  for (size_t b = 0; b < n; ++b) {
    const Body& body = model.bodies[b];
    if (body.ground) continue;
    double m = 0, inertia = 0;
    if (body.mass.source != MassProperties::Source::none) {
      m = eval(body.mass.mass);
      inertia = eval(body.mass.inertia);
    }
    add(static_cast<int>(b), m * g, centre(b), 0);
    const Eigen::Vector3d inertial(m * row[col(body.name + ".ax")], m * row[col(body.name + ".ay")],
                                   inertia * row[col(body.name + ".al")]);
    residual[b] = sum[b] - inertial;
    largest = largest.cwiseMax(scale[b] + inertial.cwiseAbs());
  }
  const double force_scale = std::max(largest.x(), largest.y());
  double worst = 0;
  for (size_t b = 0; b < n; ++b)
    for (int k = 0; k < 3; ++k) {
      const double s = k < 2 ? force_scale : largest.z();
      if (s > 0) worst = std::max(worst, std::abs(residual[b][k]) / s);
    }
  return worst;
}

}  // namespace mechgen::numeric::testing
