// Forward dynamics over time (issue 22, runtime/analysis/simulate.hpp), each against an
// independent expectation:
//  - round trip: the efforts a prescribed-motion solve needs, fed back as laws of t, recover that
//    motion (PASIBOT, planar; the quadruped leg, spatial);
//  - conservation: a model without loads released from rest keeps kinetic + potential energy,
//    the drift falling as dt^4 under RK4 (dt^2 under the implicit midpoint rule);
//  - `sweep --mass-matrix` columns: 1/2 qd^T M qd equals the kinetic energy summed over bodies
//    from the same row's body columns;
//  - the loop's contract on a one-coordinate plant whose M vanishes: the error names t and the
//    rows before it are kept; effort laws of q and qd read from a description;
//  - the generated kernel's plant (M and h from its mass_bias entry) against the numeric
//    solver's, row by row: PASIBOT on its motor from rest across support exchanges, the
//    quadruped leg (a closed chain: the kernel's warm start follows the state) under computed
//    torque, leg6 (an open spatial chain) under PD.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>

#include "analysis/motor_sizing.hpp"
#include "analysis/simulate.hpp"
#include "model/model.hpp"
#include "model/spatial_model.hpp"
#include "numeric/reference_solver.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"
#include "sweep/compiled_kernel.hpp"
#include "sweep/sweep.hpp"

namespace mechgen::sim {
namespace {

using Eigen::VectorXd;

size_t column(const std::vector<std::string>& columns, const std::string& name) {
  const auto it = std::find(columns.begin(), columns.end(), name);
  EXPECT_NE(it, columns.end()) << name;
  return static_cast<size_t>(it - columns.begin());
}

// The largest difference of the position columns (driver q, body x, y, z) between a simulation's
// rows and a sweep's rows at the same times.
double position_error(const SimulationResult& sim, const std::vector<std::string>& columns,
                      const std::vector<std::vector<double>>& reference) {
  double worst = 0;
  for (size_t c = 0; c < columns.size(); ++c) {
    const std::string& name = columns[c];
    const bool position = name.ends_with(".q") || name.ends_with(".x") || name.ends_with(".y") ||
                          name.ends_with(".z");
    if (!position) continue;
    for (size_t i = 0; i < sim.rows.size(); ++i)
      worst = std::max(worst, std::abs(sim.rows[i][c] - reference[i][c]));
  }
  return worst;
}

// The largest difference of two runs' rows over every column, each relative to max(1, that
// column's largest magnitude in `reference`).
double row_difference(const SimulationResult& run, const SimulationResult& reference) {
  EXPECT_EQ(run.columns, reference.columns);
  EXPECT_EQ(run.rows.size(), reference.rows.size());
  double worst = 0;
  for (size_t c = 0; c < reference.columns.size(); ++c) {
    double scale = 1;
    for (const std::vector<double>& row : reference.rows) scale = std::max(scale, std::abs(row[c]));
    for (size_t i = 0; i < std::min(run.rows.size(), reference.rows.size()); ++i)
      worst = std::max(worst, std::abs(run.rows[i][c] - reference.rows[i][c]) / scale);
  }
  return worst;
}

const CompiledKernel& compiled(const std::string& model) {
  const CompiledKernel* kernel = find_compiled_kernel(model);
  if (kernel == nullptr) throw std::runtime_error("no compiled kernel " + model);
  return *kernel;
}

TEST(Simulate, RoundTripPasibot) {
  const Model model = read_model(MECHGEN_SOURCE_DIR "/models/pasibot.yaml");
  const std::vector<double> parameters = model.default_parameters();
  const SweepOptions step = default_sweep(model, parameters);
  // The efforts of the model's own motion at t, from a second solver following it.
  numeric::ReferenceSolver prescribed(model, parameters);
  prescribed.assemble(step.t0);
  const std::vector<std::string> columns = column_names(model);
  const size_t effort_column = column(columns, model.drivers[0].name + ".effort");
  std::vector<double> row;
  const EffortFunction sweep_efforts = [&](double t, const VectorXd&, const VectorXd&,
                                           VectorXd& e) {
    ASSERT_EQ(prescribed.solve(t, row), numeric::Status::ok);
    e = VectorXd::Constant(1, row[effort_column]);
  };
  SimulationOptions options;
  options.t0 = step.t0;
  options.t1 = step.t1;
  options.dt = (step.t1 - step.t0) / 400;
  options.every = 20;
  const std::unique_ptr<Plant> plant = planar_plant(model, parameters);
  const SimulationResult result = simulate(*plant, sweep_efforts, options);
  ASSERT_TRUE(result.error.empty()) << result.error;
  ASSERT_EQ(result.rows.size(), 21u);
  // The reference: a sweep at the rows' times.
  SweepOptions times = step;
  times.solver = "numeric";
  times.samples = 21;
  const SweepResult sweep = run_sweep(model, times);
  for (size_t i = 0; i < sweep.rows.size(); ++i)
    ASSERT_NEAR(result.rows[i][0], sweep.rows[i][0], 1e-12);
  const double error = position_error(result, columns, sweep.rows);
  std::cout << "PASIBOT round trip, one step (" << result.steps << " RK4 steps of " << options.dt
            << " s): worst position error " << error << "\n";
  EXPECT_LT(error, 1e-8);
}

TEST(Simulate, RoundTripQuadrupedLeg) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/quadruped_leg.yaml");
  const spatial::SpatialSweepOptions step = spatial::default_spatial_sweep(model);
  const spatial::SpatialSolver prescribed(model, step.parameters);
  const std::vector<spatial::SpatialDriverGroup> groups =
      spatial::spatial_driver_groups(prescribed);
  spatial::SpatialState state;
  const EffortFunction sweep_efforts = [&](double t, const VectorXd&, const VectorXd&,
                                           VectorXd& e) {
    prescribed.solve(t, state);
    const VectorXd effort = spatial::inverse_dynamics(prescribed, state).effort;
    e.resize(static_cast<Eigen::Index>(groups.size()));
    for (size_t g = 0; g < groups.size(); ++g)
      e[static_cast<Eigen::Index>(g)] = effort[groups[g].primary];
  };
  SimulationOptions options;
  options.t0 = step.t0;
  options.t1 = step.t1;
  // 400 steps leave 2.5e-8 (the cylinders' accelerations vary faster than PASIBOT's crank's).
  options.dt = (step.t1 - step.t0) / 800;
  options.every = 40;
  const std::unique_ptr<Plant> plant = spatial_plant(model, step.parameters);
  const SimulationResult result = simulate(*plant, sweep_efforts, options);
  ASSERT_TRUE(result.error.empty()) << result.error;
  spatial::SpatialSweepOptions times = step;
  times.samples = 21;
  const spatial::SpatialSweepResult sweep = spatial::run_spatial_sweep(model, times);
  ASSERT_EQ(result.rows.size(), sweep.rows.size());
  const double error = position_error(result, sweep.columns, sweep.rows);
  std::cout << "quadruped leg round trip, one step (" << result.steps << " RK4 steps of "
            << options.dt << " s): worst position error " << error << "\n";
  EXPECT_LT(error, 1e-8);
}

// The first quarter of a spatial model's step at a fixed step dt.
SimulationOptions quarter_step(const spatial::SpatialSweepOptions& step, double dt) {
  SimulationOptions options;
  options.t0 = step.t0;
  options.t1 = step.t0 + (step.t1 - step.t0) / 4;
  options.dt = dt;
  return options;
}

// Computed torque with M and h from a second plant holds the quadruped leg's own cylinder motion
// to the integration error (an exact model: the servo terms stay at round-off), from the model's
// own initial state.
TEST(Simulate, ComputedTorqueHoldsTheQuadrupedLegsMotion) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/quadruped_leg.yaml");
  const spatial::SpatialSweepOptions step = spatial::default_spatial_sweep(model);
  // 4 ms leave 6.6e-10, 2 ms 4e-11: the RK4 error, falling as dt^4.
  const SimulationOptions options = quarter_step(step, 2e-3);
  std::vector<SimulationResult> runs;
  for (const bool generated : {false, true}) {
    // The controller's M and h from a second plant of the same solver.
    const CompiledKernel& kernel = compiled("quadruped_leg");
    const std::shared_ptr<Plant> controller =
        generated ? spatial_kernel_plant(model, step.parameters, kernel)
                  : spatial_plant(model, step.parameters);
    const std::unique_ptr<Plant> plant = generated
                                             ? spatial_kernel_plant(model, step.parameters, kernel)
                                             : spatial_plant(model, step.parameters);
    const auto n = static_cast<Eigen::Index>(plant->drivers().size());
    const SimulationResult result = simulate(
        *plant,
        tracking_controller(controller, Control::computed_torque, 400, 40, VectorXd::Ones(n)),
        options);
    ASSERT_TRUE(result.error.empty()) << result.error;
    double worst = 0;
    for (const std::vector<double>& row : result.rows) {
      VectorXd qr, qdr;
      plant->motion(row[0], qr, qdr);
      for (Eigen::Index d = 0; d < n; ++d)
        worst = std::max(
            worst,
            std::abs(qr[d] -
                     row[column(result.columns, plant->drivers()[static_cast<size_t>(d)] + ".q")]));
    }
    std::cout << "quadruped leg, computed torque (" << (generated ? "generated" : "numeric")
              << "): largest tracking error " << worst << " m\n";
    EXPECT_LT(worst, 1e-9);
    runs.push_back(result);
  }
  const double difference = row_difference(runs[1], runs[0]);
  std::cout << "quadruped leg, computed torque: generated - numeric, every column " << difference
            << "\n";
  EXPECT_LT(difference, 1e-9);
}

// leg6 (an open spatial chain, no warm start) from its own initial state under PD about its own
// motion: every column of the generated kernel's run equals the numeric solver's.
TEST(Simulate, GeneratedEqualsNumericOnLeg6) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/leg6.yaml");
  const spatial::SpatialSweepOptions step = spatial::default_spatial_sweep(model);
  SimulationOptions options = quarter_step(step, (step.t1 - step.t0) / 400);
  options.every = 10;
  // PD scaled by the diagonal of M at the start (as `simulate --track pd`): 10 rad/s, damped.
  VectorXd inertia;
  {
    const std::unique_ptr<Plant> start = spatial_plant(model, step.parameters);
    VectorXd q, qd;
    start->motion(options.t0, q, qd);
    numeric::MassBias mb;
    std::string why;
    ASSERT_TRUE(start->place(options.t0, q, qd, mb, why)) << why;
    inertia = mb.M.diagonal();
  }
  std::vector<SimulationResult> runs;
  for (const bool generated : {false, true}) {
    const std::shared_ptr<Plant> plant =
        generated ? spatial_kernel_plant(model, step.parameters, compiled("leg6"))
                  : spatial_plant(model, step.parameters);
    runs.push_back(
        simulate(*plant, tracking_controller(plant, Control::pd, 100, 20, inertia), options));
    ASSERT_TRUE(runs.back().error.empty())
        << (generated ? "generated: " : "numeric: ") << runs.back().error;
  }
  const double difference = row_difference(runs[1], runs[0]);
  std::cout << "leg6 under PD, " << runs[0].steps
            << " RK4 steps: generated - numeric, every column " << difference << "\n";
  EXPECT_LT(difference, 1e-9);
}

// The largest |E.balance - E.balance(t0)| of a run, relative to its largest kinetic energy.
double energy_drift(const SimulationResult& result) {
  const size_t balance = column(result.columns, "E.balance");
  const size_t kinetic = column(result.columns, "E.kinetic");
  double drift = 0, peak = 0;
  for (const std::vector<double>& row : result.rows) {
    drift = std::max(drift, std::abs(row[balance] - result.rows.front()[balance]));
    peak = std::max(peak, row[kinetic]);
  }
  EXPECT_GT(peak, 0);
  return drift / peak;
}

TEST(Simulate, ConservativeModelFromRestKeepsItsEnergy) {
  // Chebyshev's lambda linkage: no applied loads, the crank free (effort 0) under gravity,
  // released 1 rad past the step's start (there, crank upright, it is in equilibrium).
  const Model model = read_model(MECHGEN_SOURCE_DIR "/models/chebyshev.yaml");
  const std::vector<double> parameters = model.default_parameters();
  const EffortFunction none = [](double, const VectorXd& q, const VectorXd&, VectorXd& e) {
    e = VectorXd::Zero(q.size());
  };
  std::map<double, double> rk4, midpoint;
  for (const double dt : {1e-3, 5e-4, 2.5e-4}) {
    SimulationOptions options;
    options.t0 = 0;
    options.t1 = 1;
    options.dt = dt;
    options.initial = {VectorXd::Constant(1, M_PI / 2 + 1), VectorXd::Zero(1)};
    const std::unique_ptr<Plant> plant = planar_plant(model, parameters);
    const SimulationResult result = simulate(*plant, none, options);
    ASSERT_TRUE(result.error.empty()) << result.error;
    rk4[dt] = energy_drift(result);
    // The generated kernel's plant gives the same rows, under either integrator (dt 1 ms).
    const auto same_through_kernel = [&](const SimulationResult& numeric) {
      if (dt != 1e-3) return;
      const std::unique_ptr<Plant> kernel =
          planar_kernel_plant(model, parameters, compiled("chebyshev"));
      const double difference = row_difference(simulate(*kernel, none, options), numeric);
      std::cout << "chebyshev, " << to_string(options.integrator)
                << ": generated - numeric, every column " << difference << "\n";
      EXPECT_LT(difference, 1e-9);
    };
    same_through_kernel(result);
    if (dt == 2.5e-4) continue;
    options.integrator = Integrator::implicit_midpoint;
    const std::unique_ptr<Plant> plant2 = planar_plant(model, parameters);
    const SimulationResult implicit = simulate(*plant2, none, options);
    ASSERT_TRUE(implicit.error.empty()) << implicit.error;
    midpoint[dt] = energy_drift(implicit);
    same_through_kernel(implicit);
  }
  const double order = std::log2(rk4[5e-4] / rk4[2.5e-4]);
  const double order_midpoint = std::log2(midpoint[1e-3] / midpoint[5e-4]);
  std::cout << "chebyshev from rest, 1 s: RK4 relative energy drift " << rk4[1e-3] << " (dt 1 ms), "
            << rk4[5e-4] << " (0.5 ms), " << rk4[2.5e-4] << " (0.25 ms): order " << order
            << "; implicit midpoint " << midpoint[1e-3] << " (1 ms), " << midpoint[5e-4]
            << " (0.5 ms): order " << order_midpoint << "\n";
  EXPECT_LT(rk4[2.5e-4], 1e-7);
  EXPECT_NEAR(order, 4, 0.5);
  EXPECT_NEAR(order_midpoint, 2, 0.5);
}

TEST(Simulate, MassMatrixColumnsGiveTheBodiesKineticEnergy) {
  const Model model = read_model(MECHGEN_SOURCE_DIR "/models/pasibot.yaml");
  SweepOptions options = default_sweep(model);
  options.solver = "numeric";
  options.samples = 11;
  options.mass_matrix = true;
  const SweepResult sweep = run_sweep(model, options);
  const std::string a = model.drivers[0].name;
  const size_t m = column(sweep.columns, "M." + a + "." + a);
  const size_t qd = column(sweep.columns, a + ".qd");
  const GiNaC::exmap subs = model.substitutions(model.default_parameters());
  double worst = 0, peak = 0;
  for (const std::vector<double>& row : sweep.rows) {
    double bodies = 0;
    for (const Body& body : model.bodies) {
      if (body.ground || body.mass.source == MassProperties::Source::none) continue;
      const double mass = model.evaluate(body.mass.mass, subs),
                   inertia = model.evaluate(body.mass.inertia, subs);
      const double vx = row[column(sweep.columns, body.name + ".vx")],
                   vy = row[column(sweep.columns, body.name + ".vy")],
                   w = row[column(sweep.columns, body.name + ".w")];
      bodies += 0.5 * mass * (vx * vx + vy * vy) + 0.5 * inertia * w * w;
    }
    const double quadratic = 0.5 * row[m] * row[qd] * row[qd];
    peak = std::max(peak, bodies);
    worst = std::max(worst, std::abs(quadratic - bodies));
  }
  ASSERT_GT(peak, 0);
  std::cout << "PASIBOT: |1/2 qd M qd - sum of body kinetic energies| / peak " << worst / peak
            << "\n";
  EXPECT_LT(worst / peak, 1e-11);
}

TEST(Simulate, SpatialMassMatrixColumnsGiveTheBodiesKineticEnergy) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/quadruped_leg.yaml");
  spatial::SpatialSweepOptions options = spatial::default_spatial_sweep(model);
  options.samples = 7;
  options.mass_matrix = true;
  const spatial::SpatialSweepResult sweep = spatial::run_spatial_sweep(model, options);
  const spatial::SpatialSolver solver(model, options.parameters);
  const std::vector<spatial::SpatialDriverGroup> groups = spatial::spatial_driver_groups(solver);
  const auto n = static_cast<Eigen::Index>(groups.size());
  const spatial::SpatialInstance& in = solver.instance();
  double worst = 0, peak = 0;
  for (const std::vector<double>& row : sweep.rows) {
    Eigen::MatrixXd M(n, n);
    VectorXd qd(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const std::string ai = groups[static_cast<size_t>(i)].name;
      qd[i] = row[column(sweep.columns, ai + ".qd")];
      for (Eigen::Index j = i; j < n; ++j) {
        const std::string aj = groups[static_cast<size_t>(j)].name;
        M(i, j) = M(j, i) = row[column(sweep.columns, "M." + ai + "." + aj)];
      }
    }
    double bodies = 0;
    for (size_t b = 0; b < model.bodies.size(); ++b) {
      const SpatialBody& body = model.bodies[b];
      if (body.ground || body.is_virtual) continue;
      auto at = [&](const char* s) { return row[column(sweep.columns, body.name + s)]; };
      const Eigen::Quaterniond q(at(".qw"), at(".qx"), at(".qy"), at(".qz"));
      // The body frame's rotation now, times its rotation at the reference pose: the inertia is
      // given in the body frame, the quaternion is the frame's orientation in the ground frame.
      Eigen::Matrix3d I;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) I(r, c) = in.inertia[b](r, c);
      const Eigen::Matrix3d R = q.toRotationMatrix();
      const Eigen::Vector3d v(at(".vx"), at(".vy"), at(".vz")), w(at(".wx"), at(".wy"), at(".wz"));
      bodies += 0.5 * in.mass[b] * v.squaredNorm() + 0.5 * w.dot(R * I * R.transpose() * w);
    }
    const double quadratic = 0.5 * qd.dot(M * qd);
    peak = std::max(peak, bodies);
    worst = std::max(worst, std::abs(quadratic - bodies));
  }
  ASSERT_GT(peak, 0);
  std::cout << "quadruped leg: |1/2 qd^T M qd - sum of body kinetic energies| / peak "
            << worst / peak << "\n";
  EXPECT_LT(worst / peak, 1e-12);
}

// A one-coordinate plant with M = 0.97 - q (no mechanism): singular at q = 0.97.
class VanishingMass : public Plant {
 public:
  const std::vector<std::string>& drivers() const override { return drivers_; }
  const std::vector<std::string>& columns() const override { return columns_; }
  void motion(double, VectorXd& q, VectorXd& qd, VectorXd*) const override {
    q = VectorXd::Zero(1);
    qd = VectorXd::Ones(1);
  }
  bool place(double, const VectorXd& q, const VectorXd&, numeric::MassBias& mb,
             std::string&) override {
    mb.M = Eigen::MatrixXd::Constant(1, 1, 0.97 - q[0]);
    mb.h = VectorXd::Zero(1);
    return true;
  }
  double load_power(double) const override { return 0; }
  void restart() override {}
  bool row(double t, const VectorXd& q, const VectorXd& qd, const VectorXd& qdd,
           std::vector<double>& out, double& kinetic, double& potential, std::string&) override {
    out = {t, q[0], qd[0], qdd[0], 0};
    kinetic = 0.5 * (0.97 - q[0]) * qd[0] * qd[0];
    potential = 0;
    return true;
  }

 private:
  std::vector<std::string> drivers_{"a"}, columns_{"t", "a.q", "a.qd", "a.qdd", "a.effort"};
};

TEST(Simulate, SingularConfigurationStopsWithTheRowsSoFar) {
  // No effort: q'' = 0 while M > 0, so q = t; the step from 0.9 meets M < 0 at its last stage.
  VanishingMass plant;
  SimulationOptions options;
  options.t0 = 0;
  options.t1 = 2;
  options.dt = 0.1;
  const SimulationResult result = simulate(
      plant, [](double, const VectorXd&, const VectorXd&, VectorXd& e) { e = VectorXd::Zero(1); },
      options);
  EXPECT_NE(result.error.find("singular"), std::string::npos) << result.error;
  EXPECT_NE(result.error.find("t = 1 s"), std::string::npos) << result.error;
  ASSERT_EQ(result.rows.size(), 10u);  // t = 0 .. 0.9
  EXPECT_NEAR(result.rows.back()[1], 0.9, 1e-12);
}

TEST(Simulate, EffortLawsOfTheDriversOwnState) {
  const Model model = read_model_text(R"(
name: pendulum
parameters: {k: 3, c: 0.5}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - name: arm
    points: {O: [0, 0], P: [1, 0]}
    mass: {mass: 1, com: [1, 0], inertia: 0.1}
joints:
  - {name: pivot, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: pivot, kind: angle, value: 0, effort: -k*q - c*qd + sin(t)}
step: {t0: 0, t1: 1, samples: 11}
)",
                                      "pendulum.yaml");
  ASSERT_TRUE(model.drivers[0].effort.has_value());
  const EffortFunction laws = model_effort_laws(model, model.default_parameters());
  VectorXd e;
  laws(0.5, VectorXd::Constant(1, 0.2), VectorXd::Constant(1, -1.0), e);
  EXPECT_DOUBLE_EQ(e[0], -3 * 0.2 + 0.5 + std::sin(0.5));
  // A parameter named q would hide the coordinate: refused at the law.
  EXPECT_THROW(read_model_text(R"(
name: bad
parameters: {q: 1}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: arm, points: {O: [0, 0]}, mass: {mass: 1, com: [1, 0], inertia: 0.1}}
joints:
  - {name: pivot, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: pivot, kind: angle, value: 0, effort: -q}
step: {t0: 0, t1: 1, samples: 11}
)",
                               "bad.yaml"),
               ModelError);
  // A driver without a law (and no motor) is an error naming it.
  const Model pasibot = read_model(MECHGEN_SOURCE_DIR "/models/pasibot.yaml");
  EXPECT_THROW(model_effort_laws(pasibot, pasibot.default_parameters()), ModelError);
  EXPECT_NO_THROW(model_effort_laws(pasibot, pasibot.default_parameters(), {"theta8"}));
}

// A passive driver (planar here; the spatial ones come from `mechgen import --springs`): a hip
// servo and a free knee on a spring. Computed torque on the hip alone (collocated partial
// feedback) holds the hip's motion to the integration error while the knee swings on its spring,
// and the energy balance (the spring's work counted) stays constant. A passive driver without a
// law is refused at its key.
TEST(Simulate, APassiveDriverSwingsOnItsLawWhileTheOthersAreTracked) {
  const std::string text = R"(
name: sprung_leg
parameters: {k: 40, c: 0.3}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - {name: thigh, points: {O: [0, 0], K: [0.4, 0]}, mass: {mass: 2, com: [0.2, 0], inertia: 0.03}}
  - {name: shin, points: {K: [0.4, 0]}, mass: {mass: 1, com: [0.7, 0], inertia: 0.02}}
joints:
  - {name: hip, type: revolute, first: ground, second: thigh, point: O}
  - {name: knee, type: revolute, first: thigh, second: shin, point: K}
drivers:
  - {name: hip_angle, joint: hip, kind: angle, value: 0.3*sin(2*t)}
  - {name: knee_angle, joint: knee, kind: angle, value: 0, passive: true, effort: -k*q - c*qd}
step: {t0: 0, t1: 1, samples: 11}
)";
  const Model model = read_model_text(text, "sprung_leg.yaml");
  ASSERT_TRUE(model.drivers[1].passive);
  const std::vector<double> p = model.default_parameters();
  std::shared_ptr<Plant> plant = planar_plant(model, p), controller = planar_plant(model, p);
  const EffortFunction laws = model_effort_laws(model, p, {"hip_angle"});
  SimulationOptions options;
  options.t1 = 1;
  options.dt = 1e-3;
  for (const Control control : {Control::computed_torque, Control::pd}) {
    plant->restart();  // each run from t0 again
    controller->restart();
    const SimulationResult result = simulate(
        *plant,
        tracking_controller(controller, control, 400, 40, VectorXd::Ones(2), {false, true}, laws),
        options);
    ASSERT_TRUE(result.error.empty()) << result.error;
    double worst_hip = 0, largest_knee = 0;
    for (const std::vector<double>& row : result.rows) {
      VectorXd qr, qdr;
      plant->motion(row.front(), qr, qdr);
      worst_hip = std::max(worst_hip, std::abs(row[column(result.columns, "hip_angle.q")] - qr[0]));
      largest_knee = std::max(largest_knee, std::abs(row[column(result.columns, "knee_angle.q")]));
    }
    const double drift = result.rows.back().back() - result.rows.front().back();
    if (control == Control::computed_torque) {
      EXPECT_LT(worst_hip, 1e-8);
    }
    EXPECT_GT(largest_knee, 0.05) << "the knee swings on its spring";
    EXPECT_LT(std::abs(drift), 1e-6);
    std::cout << (control == Control::pd ? "pd" : "computed torque") << ": hip tracked to "
              << worst_hip << " rad, knee swing up to " << largest_knee << " rad, energy drift "
              << drift << " J\n";
  }
  std::string lawless = text;
  lawless.replace(lawless.find(", effort: -k*q - c*qd"), 21, "");
  try {
    read_model_text(lawless, "lawless.yaml");
    FAIL() << "a passive driver without a law was read";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("lawless.yaml:13:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("needs an `effort:` law"), std::string::npos) << e.what();
  }
}

// PASIBOT from rest on the catalogue motor size-motor chooses (GM25-150, its mass on the hip),
// stepping periodically (the support foot alternating): the energy balance (kinetic + potential
// - work of the motor) holds across the support exchanges, which the step lands on exactly.
TEST(Simulate, PasibotOnItsMotorKeepsTheEnergyBalanceAcrossSteps) {
  const Model model = read_model(MECHGEN_SOURCE_DIR "/models/pasibot.yaml");
  std::vector<double> parameters = model.default_parameters();
  apply_overrides(model, {"m_load=0.2"}, parameters);
  std::optional<MotorDrive> drive;
  for (const Motor& m : read_catalogue(MECHGEN_SOURCE_DIR "/models/motor_catalogue.csv"))
    if (m.name == "GM25-150") drive = MotorDrive{0, m, 1};
  ASSERT_TRUE(drive.has_value());
  SimulationOptions options;
  options.t0 = 0;
  options.t1 = 1.5;
  options.dt = 1e-3;
  options.every = 10;
  options.from_rest = true;
  options.extra_inertia = VectorXd::Constant(1, drive->reflected_inertia());
  options.periodic_driver = 0;
  options.period = M_PI;
  std::vector<SimulationResult> runs;
  for (const bool generated : {false, true}) {
    const std::unique_ptr<Plant> plant =
        generated ? planar_kernel_plant(model, parameters, compiled("pasibot"))
                  : planar_plant(model, parameters);
    const SimulationResult result = simulate(
        *plant,
        [&](double, const VectorXd&, const VectorXd& qd, VectorXd& e) {
          e = VectorXd::Constant(1, drive->output_torque(qd[0]));
        },
        options);
    ASSERT_TRUE(result.error.empty()) << result.error;
    EXPECT_GE(result.periods, 2);
    const size_t balance = column(result.columns, "E.balance");
    double drift = 0;
    for (const std::vector<double>& row : result.rows)
      drift = std::max(drift, std::abs(row[balance] - result.rows.front()[balance]));
    const size_t work = column(result.columns, "W.efforts");
    std::cout << "PASIBOT on GM25-150 from rest (" << (generated ? "generated" : "numeric") << "), "
              << result.periods << " support exchanges in 1.5 s: motor work "
              << result.rows.back()[work] << " J, energy balance drift " << drift << " J\n";
    EXPECT_GT(result.rows.back()[work], 0.1);  // the balance is not trivially zero work
    EXPECT_LT(drift, 1e-6);
    runs.push_back(result);
  }
  // The two solvers' runs, every column (positions, rates, efforts, energies) row by row.
  const double difference = row_difference(runs[1], runs[0]);
  std::cout << "PASIBOT on its motor: generated - numeric, every column " << difference << "\n";
  EXPECT_LT(difference, 1e-9);
}

// A stiff spring on a pendulum (omega = sqrt(k / I) = 950 rad/s) stepped at dt = 10 ms
// (omega dt = 9.5, beyond RK4's stability limit of 2.8): RK4 blows up, the implicit midpoint
// rule (A-stable, symplectic) keeps the energy.
TEST(Simulate, StiffSpringNeedsTheImplicitMidpointRule) {
  const Model model = read_model_text(R"(
name: stiff
parameters: {k: 1e6}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0]}}
  - name: arm
    points: {O: [0, 0], P: [1, 0]}
    mass: {mass: 1, com: [1, 0], inertia: 0.108}
joints:
  - {name: pivot, type: revolute, first: ground, second: arm, point: O}
drivers:
  - {name: theta, joint: pivot, kind: angle, value: 0.001*cos(t), effort: -k*q}
step: {t0: 0, t1: 1, samples: 11}
)",
                                      "stiff.yaml");
  const EffortFunction laws = model_effort_laws(model, model.default_parameters());
  SimulationOptions options;
  options.t0 = 0;
  options.t1 = 0.5;
  options.dt = 1e-2;
  const std::unique_ptr<Plant> explicit_plant = planar_plant(model, model.default_parameters());
  const SimulationResult rk4 = simulate(*explicit_plant, laws, options);
  options.integrator = Integrator::implicit_midpoint;
  const std::unique_ptr<Plant> implicit_plant = planar_plant(model, model.default_parameters());
  const SimulationResult midpoint = simulate(*implicit_plant, laws, options);
  ASSERT_TRUE(midpoint.error.empty()) << midpoint.error;
  // The spring's energy is the work of its law: E.balance is kinetic + gravity - that work.
  const double midpoint_drift = energy_drift(midpoint);
  const double rk4_drift = rk4.error.empty() ? energy_drift(rk4) : INFINITY;
  std::cout << "stiff spring, omega dt = 9.5: RK4 " << (rk4.error.empty() ? "" : rk4.error + ", ")
            << "relative energy drift " << rk4_drift << "; implicit midpoint " << midpoint_drift
            << "\n";
  EXPECT_GT(rk4_drift, 1.0);
  EXPECT_LT(midpoint_drift, 1e-2);
}

TEST(Simulate, MotorTorqueSpeedLine) {
  Motor motor;
  motor.peak_torque = 0.25;
  motor.no_load_speed = 600;  // rad/s at the shaft
  motor.gear_ratio = 300;
  motor.efficiency = 0.6;
  motor.rotor_inertia = 1.2e-6;
  const MotorDrive drive{0, motor, 1};
  EXPECT_DOUBLE_EQ(drive.output_torque(0), 0.25 * 300 * 0.6);            // stall
  EXPECT_NEAR(drive.output_torque(1.0), 0.25 * (1 - 0.5) * 180, 1e-12);  // half the no-load speed
  EXPECT_NEAR(drive.output_torque(-5), 0.25 * 180, 1e-12);               // current limit
  EXPECT_NEAR(drive.reflected_inertia(), 1.2e-6 * 9e4, 1e-15);
  const MotorDrive reverse{0, motor, -1};
  EXPECT_NEAR(reverse.output_torque(-1.0), -0.25 * 0.5 * 180, 1e-12);
  const MotorDrive half{0, motor, 1, 0.5};                      // half the rated voltage
  EXPECT_NEAR(half.output_torque(0), 0.5 * 0.25 * 180, 1e-12);  // half the stall torque
  EXPECT_NEAR(half.output_torque(1.0), 0, 1e-12);               // no-load speed halved
}

}  // namespace
}  // namespace mechgen::sim
