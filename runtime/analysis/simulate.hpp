// Forward dynamics over time (issue 22, `mechgen simulate`): the drivers become free coordinates
// under given efforts. At every stage a plant is placed at the drivers' (q, qd) and gives the mass
// matrix and bias of effort = M qdd + h: the numeric reference solver's (planar
// ReferenceSolver::mass_matrix_bias, spatial::mass_matrix_bias) or a generated kernel's
// (CompiledKernel::mass_bias_double); qdd = (M + J)^-1 (effort - h),
// J the inertia the drivers carry outside the mechanism (a motor's rotor reflected through its
// gearbox). Fixed step: classical RK4, or the implicit midpoint rule (symplectic and A-stable,
// second order; Newton iterations with a finite-difference Jacobian) for stiff efforts.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "analysis/motor_sizing.hpp"
#include "model/model.hpp"
#include "model/spatial_model.hpp"
#include "numeric/mass_bias.hpp"
#include "sweep/compiled_kernel.hpp"

namespace mechgen::sim {

// A mechanism whose drivers are free coordinates, seen through a solver. Driver vectors
// are in the sweep's driver column order.
class Plant {
 public:
  virtual ~Plant() = default;
  // Driver coordinate names (as in their `<a>.q` columns) and the sweep's columns.
  virtual const std::vector<std::string>& drivers() const = 0;
  virtual const std::vector<std::string>& columns() const = 0;
  // The model's own (prescribed) driver motion at t: the initial state of a simulation, a
  // controller's reference (with the accelerations when qdd is given).
  virtual void motion(double t, Eigen::VectorXd& q, Eigen::VectorXd& qd,
                      Eigen::VectorXd* qdd = nullptr) const = 0;
  // Places the mechanism at the drivers' (q, qd) at time t and returns M and h there. False when
  // the solver cannot place it (no configuration, a branch jump, singular kinematics or dynamics);
  // `why` says which.
  virtual bool place(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                     numeric::MassBias& mb, std::string& why) = 0;
  // After place(): the power of the applied loads (forces, torques, spring-dampers; not
  // gravity).
  virtual double load_power(double t) const = 0;
  // The sweep row at (t, q, qd, qdd) (driver efforts: those the mechanism needs, M qdd + h), and
  // the kinetic and gravity potential energy there (summed over bodies).
  virtual bool row(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                   const Eigen::VectorXd& qdd, std::vector<double>& out, double& kinetic,
                   double& potential,
                   std::string& why) = 0;  // Forgets the configuration followed so far: the next
                                           // place() assembles anew (at the model's
  // own configuration, then moving the drivers to the state asked for).
  virtual void restart() = 0;
};

std::unique_ptr<Plant> planar_plant(const Model& model, const std::vector<double>& parameters);
// Joint drivers and pose drivers' prescribed coordinates, in the spatial sweep's order.
std::unique_ptr<Plant> spatial_plant(const SpatialModel& model,
                                     const std::vector<double>& parameters);
// The same through the model's generated kernel (which must outlive the plant): M and h from its
// mass_bias entry, rows from its driven evaluation, the kinetic energy 1/2 qd^T M qd, the
// potential from the rows' centre-of-mass columns. A spatial closed chain's warm start (per
// thread) is seeded from the numeric solver's assembly at the first placement and then follows
// the placements. The numeric solver is placed at every stage only when the model has applied
// loads (their power). Throws std::runtime_error when the kernel's columns, parameters or
// drivers are not the description's.
std::unique_ptr<Plant> planar_kernel_plant(const Model& model,
                                           const std::vector<double>& parameters,
                                           const CompiledKernel& kernel);
std::unique_ptr<Plant> spatial_kernel_plant(const SpatialModel& model,
                                            const std::vector<double>& parameters,
                                            const CompiledKernel& kernel);

// The efforts on the drivers at (t, q, qd): one per driver.
using EffortFunction = std::function<void(double t, const Eigen::VectorXd& q,
                                          const Eigen::VectorXd& qd, Eigen::VectorXd& effort)>;

// The drivers' `effort:` laws of a description (t, parameters, their own q and qd), at the given
// parameter values; a driver without one is a ModelError at the driver unless `free` names it
// (the effort another law sets, e.g. a motor's), in which case its law gives 0.
EffortFunction model_effort_laws(const Model& model, const std::vector<double>& parameters,
                                 const std::vector<std::string>& free = {});
EffortFunction model_effort_laws(const SpatialModel& model, const std::vector<double>& parameters,
                                 const std::vector<std::string>& free = {});

// A DC motor and gearbox on one driver: the torque-speed line at the rated voltage from the
// stall torque (taken as the catalogue's peak torque, also the current limit) down to zero at the
// no-load speed, through the gearbox (output torque = motor torque x ratio x efficiency, output
// speed = motor speed / ratio); `direction` (+1 or -1) the sense it drives the coordinate in;
// `voltage` the supply as a fraction of the rated voltage (stall torque and no-load speed scale
// with it; the current limit does not).
struct MotorDrive {
  int driver = 0;
  Motor motor;
  double direction = 1;
  double voltage = 1;
  double output_torque(double qd) const;  // at the driver's rate
  double reflected_inertia() const;       // rotor inertia x ratio^2
};

// Drivers as force-controlled actuators holding the model's own motion (the drivers' `value:`)
// as the reference q_r(t): computed torque, effort = M(q) (q_r'' + kd e' + kp e) + h(q, q') with M
// and h from `model` (a plant of its own, placed at the simulation's state), or PD only, effort =
// J (kp e + kd e') with J `inertia` (per driver: the diagonal of M at the start, so that both
// have the same nominal bandwidth). e = q_r - q. Drivers flagged in `passive` (a joint's spring)
// are not actuated: their effort is `passive_laws`'s, and computed torque then linearises the
// active coordinates only (collocated partial feedback: the passive accelerations are those
// their laws give while the active ones follow the servo).
enum class Control { computed_torque, pd };
EffortFunction tracking_controller(std::shared_ptr<Plant> model, Control control, double kp,
                                   double kd, const Eigen::VectorXd& inertia,
                                   const std::vector<bool>& passive = {},
                                   const EffortFunction& passive_laws = {});

enum class Integrator { rk4, implicit_midpoint };

struct SimulationOptions {
  double t0 = 0, t1 = 1, dt = 1e-3;
  Integrator integrator = Integrator::rk4;
  int every = 1;  // a row every `every` steps (and the last)
  // Initial state: the model's motion at t0, or at rest there (qd = 0, the position kept).
  bool from_rest = false;
  // Extra inertia on the diagonal of M (per driver; empty: none).
  Eigen::VectorXd extra_inertia;
  // When set, replaces the initial state (q, qd at t0).
  std::optional<std::pair<Eigen::VectorXd, Eigen::VectorXd>> initial;
  // A periodic gait (PASIBOT: the support foot alternates every half crank turn, and the model's
  // step is one of them): when driver `periodic_driver` has moved by `period` from its initial
  // value, it is moved back by `period` (the same configuration with the legs' roles swapped)
  // and the plant restarted. -1: none.
  int periodic_driver = -1;
  double period = 0;
};

struct SimulationResult {
  // The sweep's columns, then E.kinetic (mechanism + extra inertia), E.potential (gravity),
  // W.efforts and W.loads (work done since t0), E.balance (kinetic + potential - works: constant
  // up to the integration error).
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::string error;  // empty when the run reached t1; else what stopped it, naming t
  int steps = 0;
  int periods = 0;  // how many times the periodic driver was moved back
};

SimulationResult simulate(Plant& plant, const EffortFunction& effort,
                          const SimulationOptions& options);

std::string to_string(Integrator integrator);
Integrator integrator_from_string(const std::string& name);  // std::invalid_argument

}  // namespace mechgen::sim
