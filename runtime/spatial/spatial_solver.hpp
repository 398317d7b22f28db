// The numeric reference solver for spatial models (seed 001), generic over the joint graph:
//  - positions by successive screw displacements (product of exponentials, Rodrigues) along the
//    spanning tree, circuits closed by Newton-Raphson on the secondary coordinates, whose
//    Jacobian is Davies' secondary network matrix N_s;
//  - velocities by Davies' method: N_s q_s' = -N_p q_p' (least squares: exact and unique when N_s
//    has full column rank, also when circuits carry redundant constraint rows);
//  - accelerations exactly, from the circulation law differentiated once more: each screw's rate
//    is the Lie bracket of the twist of the frame carrying it with the screw;
//  - screw Jacobians: each body's twist and each point's velocity as maps of the primary rates.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "geometry/screw.hpp"
#include "model/spatial_graph.hpp"
#include "model/spatial_model.hpp"
#include "numeric/time_expression.hpp"

namespace mechgen::spatial {

using V3 = geometry::Vec3<double>;
using M3 = geometry::Mat3<double>;
using Pose = geometry::Pose<double>;
using Twist = geometry::Twist<double>;
using Wrench = geometry::Wrench<double>;
// Vec3 is a std::array: its operators are not found by argument-dependent lookup.
using geometry::operator+;
using geometry::operator-;
using geometry::operator*;

// The model's numbers at one parameter vector (reference pose, ground frame).
struct SpatialInstance {
  std::vector<geometry::ScrewAxis<double>> axes;  // per column
  std::vector<Twist> unit;                        // per column: unit twist at the reference pose
  std::vector<V3> joint_point;                    // per joint: s0
  std::vector<Pose> body_frame;                   // per body: its frame at the reference pose
  std::vector<double> mass;                       // per body
  std::vector<V3> com;                            // per body: centre of mass, body frame
  std::vector<M3> inertia;                        // per body: about the centre of mass, body frame
  std::vector<std::vector<V3>> points;            // per body: its points, body frame
  std::vector<double> hint;                       // per column: assembly start at t0
  V3 gravity{0, 0, 0};
};

// One configuration with its rates. Bodies are located by their displacement D from the
// reference pose (a point at x at the reference pose is at D x).
struct SpatialState {
  double t = 0;
  Eigen::VectorXd q, qd, qdd;     // per column
  std::vector<Pose> D;            // per body
  std::vector<Twist> V, A;        // per body: ground-origin twist and its time derivative
  std::vector<Twist> screw;       // per column: current unit screw
  std::vector<Twist> screw_rate;  // per column: its time derivative
  std::vector<Twist> carrier;     // per column: twist of the frame that carries the screw
  bool assembled = false;
};

class SpatialSolver {
 public:
  // Throws ModelError for a malformed graph or a bad parameter vector.
  SpatialSolver(const SpatialModel& model, std::vector<double> parameters);

  const SpatialModel& model() const { return model_; }
  const SpatialGraph& graph() const { return graph_; }
  const SpatialInstance& instance() const { return inst_; }
  const std::vector<double>& parameters() const { return parameters_; }

  // The primary coordinates at t (graph().primary order) and their rates.
  void primary_motion(double t, Eigen::VectorXd& q, Eigen::VectorXd& qd,
                      Eigen::VectorXd& qdd) const;

  // Positions, velocities and accelerations at t. The first call (or state.assembled false)
  // starts from the assembly hints and checks the mobility (located ModelError for an over- or
  // under-determined motion, a singular N_s); later calls continue from the state along the
  // model's motion, halving the step where the closure fails or lands far from the rates'
  // prediction (a branch change or 2 pi k between coarse samples). Throws ModelError when the
  // circuits cannot be closed or follow no continuous path.
  void solve(double t, SpatialState& state) const;
  // The same with the primary coordinates and their rates given (graph().primary order, as
  // primary_motion returns them): a motion planned outside the description (a gait) drives the
  // same mechanism.
  void solve(double t, const Eigen::VectorXd& qp, const Eigen::VectorXd& qpd,
             const Eigen::VectorXd& qpdd, SpatialState& state) const;

  // Product of exponentials from state.q: D of every body, current screws (no rates).
  void place(SpatialState& state) const;
  // Davies' network matrix N (6 rows per circuit, one column per coordinate) at state's pose.
  Eigen::MatrixXd network(const SpatialState& state) const;
  // Rates of every coordinate, body twists and twist rates from the primary rates (state placed).
  void rates(SpatialState& state, const Eigen::VectorXd& qpd, const Eigen::VectorXd& qpdd) const;

  // Screw Jacobians at state's pose: a body's twist (6 x primaries: rows w then v) and a point's
  // velocity (3 x primaries; `x` ground frame, current) as linear maps of the primary rates.
  Eigen::MatrixXd body_jacobian(const SpatialState& state, int body) const;
  Eigen::MatrixXd point_jacobian(const SpatialState& state, int body, const V3& x) const;

  // Current positions: a body frame (rotation of the body frame into the ground frame, origin),
  // a body point, the centre of mass; their velocity and acceleration.
  Pose body_pose(const SpatialState& state, int body) const;
  V3 point_position(const SpatialState& state, int body, const V3& local) const;
  V3 point_velocity(const SpatialState& state, int body, const V3& local) const;
  V3 point_acceleration(const SpatialState& state, int body, const V3& local) const;

  // The model's applied loads (`forces:`) at state.t, per body: their resultant wrench about the
  // ground origin, and their power at state's velocities.
  std::vector<Wrench> applied_wrenches(const SpatialState& state) const;
  double applied_power(const SpatialState& state) const;

 private:
  Eigen::MatrixXd secondary_map(const SpatialState& state) const;  // q_s' = S q_p'
  void close_circuits(SpatialState& state, bool first) const;
  void assemble(const Eigen::VectorXd& qp, SpatialState& state) const;
  void canonical_angles(SpatialState& state) const;
  void advance(double t, SpatialState& state, int halvings) const;
  void check_mobility(const Eigen::MatrixXd& N) const;
  Eigen::VectorXd closure_error(const SpatialState& state) const;

  const SpatialModel& model_;
  SpatialGraph graph_;
  std::vector<double> parameters_;
  SpatialInstance inst_;
  // Per primary column: q(t), q'(t), q''(t) minus the reference value.
  std::vector<numeric::TimeExpression> q_, qd_, qdd_;
  std::vector<double> offset_;
  struct Load {
    int body = -1;
    bool torque = false;
    V3 local{0, 0, 0};  // force: the point, body frame
    std::array<numeric::TimeExpression, 3> value;
  };
  std::vector<Load> loads_;
  // Per load: the force (or couple) and where it acts (current, ground frame), at state.t.
  std::vector<std::pair<V3, V3>> load_values(const SpatialState& state) const;
};

// The orientation of a rotation matrix as a unit quaternion [qw, qx, qy, qz] with qw >= 0.
std::array<double, 4> quaternion(const M3& R);
// The rotation vector (axis times angle, |angle| <= pi) of a rotation matrix.
V3 rotation_log(const M3& R);

}  // namespace mechgen::spatial
