// The generic numeric reference solver: the ground truth the generated kernels are compared with.
//
// It knows nothing of closed forms or of particular models. Formulation (planar, absolute
// coordinates): q = (x, y, th) of every moving body's frame origin, the ground body fixed at the
// world origin with angle 0.
//   revolute      r2 + R2 p2 - r1 - R1 p1 = 0                                    (2 equations)
//   pin_in_slot   (r2 + R2 p2 - r1 - R1 o1) . (R1 n1) = 0, n1 the unit normal of the line
//   prismatic     pin_in_slot and th2 - th1 - angle = 0
//   driver angle  th2 - th1 - f(t) = 0
//   driver length (r2 + R2 p2 - r1 - R1 o1) . (R1 u1) - f(t) = 0, u1 the unit line direction
// Positions: Newton-Raphson on Phi(q, t) = 0 from a second-order Taylor prediction of the previous
// sample (retried with continuation sub-steps before giving up). Velocities Phi_q qd = -Phi_t,
// accelerations Phi_q qdd = gamma with the exact analytic gamma: exact linear solves, no finite
// differences. Dynamics: Newton-Euler for every moving body (forces, moments about the centre of
// mass), every joint reaction component and driver effort an unknown, solved densely with a
// rank-revealing LU; a singular or non-square system is reported, never solved.
//
// Every time-independent number (points, masses, centres of mass, inertias, lines, gravity) is
// evaluated once per parameter set; only the driver functions and applied loads that depend on t
// are evaluated per sample.
#pragma once

#include <ginac/ginac.h>
#include <Eigen/Dense>

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "model/columns.hpp"
#include "model/model.hpp"
#include "numeric/time_expression.hpp"

namespace mechgen::numeric {

enum class Status {
  ok,
  diverged,             // no configuration found at t (Newton-Raphson, then continuation, failed)
  branch_jump,          // a configuration was found at t but on another branch: a body angle
                        // jumped, or det(Phi_q) changed sign (the path crossed a singularity)
  singular_kinematics,  // constraint Jacobian rank-deficient: velocities are not determined
  singular_dynamics,    // Newton-Euler system singular or non-square: statically indeterminate
};
const char* to_string(Status status);

struct Options {
  // Newton-Raphson converges when its last step and the residual max |Phi| are both within
  // tolerance * L (or the residual within 1e-3 of that), angle equations and angle steps scaled by
  // L, the model's characteristic length (largest coordinate of any point, line or centre of
  // mass). Since the error after such a step is of the order of its square, positions come out at
  // round-off level, not at the tolerance.
  double tolerance = 1e-12;
  int max_iterations = 50;  // per Newton solve (assembly: 4 times this, with line search)
  // A body angle that moves by more than this between successive samples AND farther than this
  // from its second-order Taylor prediction is a branch jump (rad per sample).
  double branch_jump_angle = 0.2;
  // Rank decisions on the scaled (unit-free) matrices: a square system is regular when its
  // reciprocal condition estimate exceeds this; the numerical rank of a singular or rectangular
  // one counts the full-pivoting LU pivots above this fraction of the largest.
  double rank_tolerance = 1e-10;
  // When a step diverges or jumps, it is retried with 2, 4, ... up to this many sub-steps.
  int max_substeps = 64;
  // Accept consistent redundant constraints (over-constrained mechanisms such as a parallelogram
  // with an extra bar): kinematics by least squares, dynamics reported as singular_dynamics.
  bool allow_redundant = false;
};

class ReferenceSolver {
 public:
  // The model must outlive the solver. `parameters` is in Model::parameters order. Throws
  // ModelError when a time-independent quantity does not evaluate to a finite number.
  ReferenceSolver(const Model& model, std::vector<double> parameters, Options options = {});

  // Newton-Raphson (with line search) from the assembly hints at time t: hinted angles (0 where
  // none), positions chained from the ground through the joints. Throws ModelError (at the
  // offending body's `assembly:` hint, the offending joint, or the model file) when it does not
  // converge, when a converged angle is farther than model.assembly_tolerance from its hint (modulo
  // 2 pi), or when the constraints are redundant or leave bodies undetermined (the message names
  // the joints and bodies involved).
  void assemble(double t);

  // Positions (Newton from the previous configuration), velocities, accelerations and the
  // Newton-Euler solve at time t; fills `row` in column_names(model) order. Columns that the status
  // makes meaningless are NaN: all but t (diverged, branch_jump; the previous configuration is
  // kept), velocities, accelerations and forces (singular_kinematics), efforts and joint forces
  // (singular_dynamics). Throws std::logic_error before assemble().
  Status solve(double t, std::vector<double>& row);

  // Body frame origin and angle (ground frame) of the last solve/assemble, indexed by body.
  struct Pose {
    double x, y, th;
  };
  const std::vector<Pose>& poses() const { return poses_; }

  // The Newton-Euler system of the last solve: A x = b, rows (fx, fy, moment about the centre of
  // mass) per moving body in body order, one unknown per joint reaction component and driver
  // effort, named "<joint>.fx", "<joint>.fy" (revolute), "<joint>.n" (pin_in_slot, prismatic:
  // force along the world normal of the line), "<joint>.m" (prismatic), "<driver>.effort".
  const Eigen::MatrixXd& ne_matrix() const { return ne_a_; }
  const Eigen::VectorXd& ne_rhs() const { return ne_b_; }
  const std::vector<std::string>& ne_unknowns() const { return ne_names_; }
  const Eigen::VectorXd& ne_solution() const { return ne_x_; }

  // Forward-dynamics quantities in the drivers' coordinates (issue 22) at the configuration and
  // velocities of the last ok solve at time t: effort = M qdd + h, h the Newton-Euler driver
  // efforts with the drivers' accelerations set to 0, column i of M those with driver i's
  // acceleration 1 minus h. M is returned symmetrised (its triangles agree to round-off;
  // asymmetry() says by how much, relative to its largest entry). The solve's own accelerations and
  // Newton-Euler solution are kept. False when the last solve was not ok or a Newton-Euler solve is
  // singular.
  bool mass_matrix_bias(double t, Eigen::MatrixXd& M, Eigen::VectorXd& h,
                        double* asymmetry = nullptr);

  // Simulation (issue 22, `mechgen simulate`): the drivers' coordinates, rates and accelerations
  // (model order) given instead of their time functions, for assemble, solve and
  // mass_matrix_bias until cleared. Loads keep their laws of t.
  void set_driver_motion(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                         const Eigen::VectorXd& qdd);
  void clear_driver_motion();
  // At the last solve: the gravity potential energy (-sum m g . c, zero at the ground origin),
  // the kinetic energy summed over bodies, and the power of the applied loads (forces, torques,
  // spring-dampers) at time t.
  double potential_energy() const;
  double kinetic_energy() const;
  double applied_power(double t) const;

  // Rank of the constraint Jacobian at the last solve/assemble, and its size.
  int constraint_rank() const { return rank_; }
  int constraint_count() const { return static_cast<int>(rows_.size()); }
  int coordinate_count() const { return 3 * moving_; }
  // Names of the constraint equations ("<joint>.x", "<joint>.y", "<joint>.n", "<joint>.angle",
  // "<driver>") in row order.
  std::vector<std::string> constraint_names() const;

  // Generalised coordinates and their rates of the last solve/assemble: (x, y, th) per moving body.
  const Eigen::VectorXd& q() const { return q_; }
  const Eigen::VectorXd& qd() const { return qd_; }
  const Eigen::VectorXd& qdd() const { return qdd_; }

  double characteristic_length() const { return length_; }
  const Options& options() const { return options_; }
  const Model& model() const { return model_; }

 private:
  // A quantity that may depend on t: a constant when it does not.
  class TimeFunction {
   public:
    TimeFunction() = default;
    TimeFunction(const GiNaC::ex& e, const GiNaC::exmap& subs, const GiNaC::symbol& t,
                 SourceLoc loc, std::string what);
    double operator()(double t) const;

   private:
    bool constant_ = true;
    double value_ = 0;
    TimeExpression ex_;
    SourceLoc loc_;
    std::string what_;
  };

  struct BodyData {
    int slot = -1;  // first column of (x, y, th) in q; -1 for the ground
    double mass = 0, inertia = 0;
    Eigen::Vector2d com = Eigen::Vector2d::Zero();
  };
  struct JointData {
    JointType type = JointType::revolute;
    int first = -1, second = -1;
    // Joint point on the first body (revolute) or line.through (others); point on the second.
    Eigen::Vector2d p1 = Eigen::Vector2d::Zero(), p2 = Eigen::Vector2d::Zero();
    // Unit line direction and normal, first body frame.
    Eigen::Vector2d u1 = Eigen::Vector2d::Zero(), n1 = Eigen::Vector2d::Zero();
    double angle = 0;  // prismatic
    int row = 0;       // first constraint row
    int unknown = 0;   // first Newton-Euler unknown
  };
  struct DriverData {
    DriverKind kind = DriverKind::angle;
    int joint = -1;
    TimeFunction f, fd, fdd;
    int row = 0, unknown = 0;
  };
  struct ForceData {
    ForceType type = ForceType::force;
    int a = -1, b = -1;
    Eigen::Vector2d pa = Eigen::Vector2d::Zero(), pb = Eigen::Vector2d::Zero();
    TimeFunction k, c, free_length, fx, fy, torque;
  };
  struct Row {
    enum Kind { joint_x, joint_y, joint_line, joint_angle, driver } kind;
    int index;  // joint or driver
  };
  struct Kinematic {  // world-frame pose, velocity and acceleration of one body
    Eigen::Vector2d r, v, a;
    double th, w, al;
    Eigen::Matrix2d R;
  };
  struct Newton {
    bool converged = false;
    int iterations = 0;
    double residual = 0;
  };
  // The scaled constraint Jacobian at a configuration, factorised: partial pivoting when square
  // and well-conditioned (reciprocal condition estimate above Options::rank_tolerance), else full
  // pivoting for the numerical rank.
  struct Factor {
    Eigen::MatrixXd jac;
    Eigen::PartialPivLU<Eigen::MatrixXd> partial;
    Eigen::FullPivLU<Eigen::MatrixXd> lu;
    bool full = false;
    int rank = 0;
    int det_sign = 0;  // sign of det(Phi_q) when square and regular, else 0
  };

  Kinematic body_state(int body, const Eigen::VectorXd& q, const Eigen::VectorXd* qd = nullptr,
                       const Eigen::VectorXd* qdd = nullptr) const;
  std::vector<Kinematic> states(const Eigen::VectorXd& q, const Eigen::VectorXd* qd = nullptr,
                                const Eigen::VectorXd* qdd = nullptr) const;
  void residual(const Eigen::VectorXd& q, double t, Eigen::VectorXd& phi) const;  // scaled
  void jacobian(const Eigen::VectorXd& q, Eigen::MatrixXd& jac) const;            // scaled
  void gamma(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, double t,
             Eigen::VectorXd& g) const;                    // scaled
  void velocity_rhs(double t, Eigen::VectorXd& nu) const;  // scaled
  Newton newton(Eigen::VectorXd& q, double t, int max_iterations, bool line_search) const;
  Factor factor(const Eigen::VectorXd& q) const;
  // Solves the scaled Jacobian system for a coordinate increment (least squares when over-
  // determined); returns unscaled coordinates.
  Eigen::VectorXd solve_kinematic(const Factor& f, const Eigen::VectorXd& rhs) const;
  // Velocities and accelerations at configuration q, time t; false when Phi_q is rank-deficient.
  bool rates(const Factor& f, const Eigen::VectorXd& q, double t, Eigen::VectorXd& qd,
             Eigen::VectorXd& qdd) const;
  enum class Step { ok, diverged, branch_jump };
  // Chord iterations with `f`, a factorised Jacobian of a nearby configuration; false when they do
  // not converge fast (the caller then runs a full Newton-Raphson).
  bool chord(Eigen::VectorXd& q, double t, const Factor& f) const;
  // One continuation step: prediction from (q0, qd0, qdd0) at t_from, correction at t_to (chord
  // iterations with `previous` when given, else or on failure Newton), branch checks; `f` is the
  // factorised Jacobian at the result.
  Step step_to(double t_from, double t_to, const Eigen::VectorXd& q0, const Eigen::VectorXd& qd0,
               const Eigen::VectorXd& qdd0, int det_sign0, const Factor* previous,
               Eigen::VectorXd& q, Factor& f) const;
  bool dynamics(double t);
  // Driver d's value (order 0), rate (1) or acceleration (2) at t: given or its time function.
  double drive(const DriverData& dr, int order, double t) const;
  void update_poses();
  void fill_row(double t, Status status, std::vector<double>& row) const;
  [[noreturn]] void report_rank_problem(const Eigen::VectorXd& q) const;
  std::string row_name(int row) const;

  const Model& model_;
  std::vector<double> parameters_;
  Options options_;
  GiNaC::exmap subs_;
  ColumnLayout layout_;
  std::vector<std::pair<std::string, int>> points_;
  std::vector<Eigen::Vector2d> point_local_;

  int moving_ = 0;
  double length_ = 1;
  Eigen::Vector2d gravity_ = Eigen::Vector2d::Zero();
  std::vector<BodyData> bodies_;
  std::vector<JointData> joints_;
  std::vector<DriverData> drivers_;
  std::vector<ForceData> forces_;
  std::vector<Row> rows_;
  Eigen::VectorXd row_scale_;  // length_ for angle rows, 1 otherwise
  Eigen::VectorXd col_scale_;  // 1 / length_ for angle columns, 1 otherwise

  bool assembled_ = false;
  double t_ = 0;
  int det_sign_ = 0;
  int rank_ = 0;
  Eigen::VectorXd q_, qd_, qdd_;
  Factor factor_;  // of the Jacobian at q_
  std::vector<Pose> poses_;
  Eigen::MatrixXd ne_a_;
  Eigen::VectorXd ne_b_, ne_x_;
  std::vector<std::string> ne_names_;
  int ne_rank_ = 0;
  std::optional<std::array<Eigen::VectorXd, 3>> given_;  // set_driver_motion
};

}  // namespace mechgen::numeric
