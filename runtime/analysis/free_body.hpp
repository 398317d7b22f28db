// Every load on every body of a mechanism at one sample of a sweep: the free-body diagrams that
// the link-load (beam) analysis and the ground reaction are built from.
//
// Read off DESIGN.md's CSV columns: a joint's <j>.fx, fy (and m) is the force (moment) of its
// first body on its second, at the joint point, so the second body receives +F and the first -F
// at the same place; a driver's effort acts on its joint's second body (a torque for an angle
// driver, a force along the line for a length driver) and its opposite on the first. Applied
// loads (spring_damper, force, torque) are evaluated from the model at the sample's time. Gravity
// and d'Alembert inertia are not listed as loads: each free body carries its mass, inertia and
// acceleration, so a consumer may lump them at the centre of mass or distribute them.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "model/model.hpp"
#include "numeric/time_expression.hpp"

namespace mechgen::analysis {

struct PointLoad {
  std::string source;  // joint, driver or force element name
  Eigen::Vector2d at;  // application point, ground frame (m)
  Eigen::Vector2d force;
};

struct Couple {
  std::string source;
  double moment = 0;  // N m, counter-clockwise
  // Where it acts, for the distribution along a bar: a driver's torque and a prismatic joint's
  // moment at the joint point; a torque element has no point (it acts at the centre of mass).
  std::optional<Eigen::Vector2d> at;
};

struct FreeBody {
  int body = -1;                 // index into Model::bodies
  double mass = 0, inertia = 0;  // kg, kg m^2 about the centre of mass (0 for a massless ground)
  Eigen::Vector2d com = Eigen::Vector2d::Zero();  // ground frame
  Eigen::Vector2d acc = Eigen::Vector2d::Zero();  // of the centre of mass
  double th = 0, w = 0, al = 0;                   // body angle and its rates
  std::vector<PointLoad> forces;
  std::vector<Couple> couples;
};

// Net force and moment about the centre of mass of everything acting on a body, gravity and
// d'Alembert inertia (-m a, -I al) included: zero for a body in dynamic equilibrium.
struct Resultant {
  Eigen::Vector2d force = Eigen::Vector2d::Zero();
  double moment = 0;
};

// The model evaluated once for a parameter set and a table's columns; then one call per row.
class FreeBodies {
 public:
  // Throws ModelError when a model quantity does not evaluate, std::invalid_argument naming the
  // first missing column ("no column 'l3.ax'") when `columns` is not a sweep of this model.
  FreeBodies(const Model& model, const std::vector<double>& parameters,
             const std::vector<std::string>& columns);

  // All bodies, ground included (index = body index), at one row of the table.
  std::vector<FreeBody> at(const std::vector<double>& row) const;

  Eigen::Vector2d gravity() const { return gravity_; }
  const Model& model() const { return model_; }
  // Where the named point is in the ground frame at this row.
  Eigen::Vector2d point(const std::string& name, const std::vector<double>& row) const;

 private:
  struct BodyColumns {
    int x = -1, y = -1, th = -1, vx = -1, vy = -1, w = -1, ax = -1, ay = -1, al = -1;
  };
  int column(const std::string& name) const;

  // An applied load's time-dependent values, compiled once (parameters substituted).
  struct AppliedLoad {
    numeric::TimeExpression k, c, free_length, fx, fy, torque;
  };

  const Model& model_;
  GiNaC::exmap subs_;
  std::unordered_map<std::string, int> index_;  // column name -> position
  std::vector<AppliedLoad> applied_;            // per Model::forces entry
  Eigen::Vector2d gravity_;
  int time_ = -1;
  std::vector<BodyColumns> body_cols_;
  std::vector<double> mass_, inertia_;
  std::vector<Eigen::Vector2d> com_local_;
};

Resultant resultant(const FreeBody& body, const Eigen::Vector2d& gravity);

}  // namespace mechgen::analysis
