// mechgen simulate: forward dynamics over time (issue 22): the drivers become free coordinates
// under their effort laws or a DC motor, integrated with a fixed step (analysis/simulate.hpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "analysis/motor_sizing.hpp"
#include "analysis/simulate.hpp"
#include "cli/command.hpp"
#include "cli/model_info.hpp"
#include "model/spatial_model.hpp"
#include "model/spatial_value_checks.hpp"
#include "ondemand/kernel_resolver.hpp"
#include "sweep/sweep.hpp"

namespace mechgen::cli {

namespace {

const char* const kSimulateHelp =
    R"(usage: mechgen simulate MODEL.yaml --out FILE.csv [--t1 T] [--dt DT] [--set NAME=VALUE]...
                         [--solver generated|numeric] [--from-rest]
                         [--integrator rk4|implicit-midpoint] [--every K]
                         [--motor NAME --catalogue CSV [--driver NAME] [--voltage V]]
                         [--track computed-torque|pd [--kp KP] [--kd KD]]

Forward dynamics: the drivers become free coordinates under given efforts, q'' = M^-1 (effort -
h) with M and h from the model's generated kernel or the numeric solver at every stage (planar and
spatial models). Each driver's
effort is its `effort:` law in the model (of t, the parameters and its own q and qd:
docs/model_format.md), or a DC motor and gearbox from a size-motor catalogue. A `passive:`
driver (a joint's spring, e.g. from `mechgen import --springs`) always takes its law: --motor
and --track act on the other drivers only.
  --out FILE.csv      the sweep's columns (efforts: those the mechanism receives, M q'' + h) and
                      E.kinetic, E.potential (gravity), W.efforts, W.loads (work since t0) and
                      E.balance = kinetic + potential - works (constant up to the integration error)
  --solver S          generated (default: the kernel's mass_bias entry and rows; a kernel not
                      compiled in is built on demand and cached, as for sweep) or numeric
  --t1 T              end time (default: the model's step end); starts at the step's t0
  --dt DT             fixed step (default 1e-3 s)
  --from-rest         start at the step's t0 position with zero rates (default: the model's own
                      q and q' at t0)
  --integrator NAME   rk4 (default: classical, 4th order) or implicit-midpoint (2nd order,
                      symplectic and A-stable: for stiff springs, gains or motors)
  --every K           one row every K steps (default 1; the last step always)
  --periodic          a periodic gait (PASIBOT): when the motor's driver (else the first) has
                      moved by its advance over the model's step, it is moved back by it (the
                      same configuration, the legs' roles swapped) and the solver re-assembles;
                      so every step is the model's step, support foot alternating
  --motor NAME        a motor of --catalogue drives --driver (default: the first active one):
                      torque-speed line at the rated voltage from the peak torque at stall (also
                      the current limit) to zero at the no-load speed, through the gearbox ratio
                      and efficiency; the rotor inertia x ratio^2 is added to M; it drives in the
                      sense of the model's own motion at t0. Its mass is not added: --set it.
  --voltage V         the motor's supply as a fraction of its rated voltage (default 1): stall
                      torque and no-load speed scale with it
  --track CONTROL     the drivers as force-controlled actuators holding the model's own motion
                      (their `value:`) as the reference instead of their effort laws:
                      computed-torque (M (q_r'' + kd e' + kp e) + h, M and h from --solver at
                      the current state; with passive drivers, on the active coordinates only)
                      or pd (J (kp e + kd e'), J the diagonal of M at the start); prints the
                      largest tracking error of each driver
  --kp KP, --kd KD    the tracking gains (default 400 1/s^2 and 40 1/s: 20 rad/s, critically
                      damped)
A singular configuration reached (M not positive definite, or the solver cannot place the
mechanism) stops the run: the rows computed so far are written, then the error names t (exit 1).
)";

int run_simulate(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  if (!args.has("--out")) throw UsageError("missing --out FILE.csv");
  if (args.has("--motor") != args.has("--catalogue"))
    throw UsageError("--motor NAME and --catalogue CSV go together");
  if (args.has("--track") && args.has("--motor"))
    throw UsageError("--track drives every driver by its controller: no --motor with it");
  if ((args.has("--kp") || args.has("--kd")) && !args.has("--track"))
    throw UsageError("--kp and --kd are the gains of --track");
  if ((args.has("--driver") || args.has("--voltage")) && !args.has("--motor"))
    throw UsageError("--driver and --voltage are the motor's: give --motor too");
  sim::SimulationOptions options;
  options.dt = args.number("--dt", 1e-3);
  if (!(options.dt > 0)) throw UsageError("--dt must be positive");
  options.every = args.integer("--every", 1);
  if (options.every < 1) throw UsageError("--every must be at least 1");
  options.from_rest = args.has("--from-rest");
  try {
    options.integrator = sim::integrator_from_string(args.get("--integrator", "rk4"));
  } catch (const std::invalid_argument& error) {
    throw UsageError(std::string("--integrator: ") + error.what());
  }

  g_current_file = path;
  const bool spatial = is_spatial_description(path);
  std::unique_ptr<SpatialModel> spatial_model;
  std::unique_ptr<Model> planar_model;
  std::vector<double> parameters;
  std::string name;
  double t0 = 0, t1 = 0;
  if (spatial) {
    spatial_model = std::make_unique<SpatialModel>(read_spatial_model(path));
    parameters = spatial_model->common.default_parameters();
    apply_overrides(*spatial_model, args.all("--set"), parameters);
    name = spatial_model->common.name;
    const GiNaC::exmap subs = spatial_model->common.substitutions(parameters);
    t0 = spatial_model->evaluate(spatial_model->common.step.t0, subs);
    t1 = spatial_model->evaluate(spatial_model->common.step.t1, subs);
  } else {
    planar_model = std::make_unique<Model>(load_model(path));
    parameters = planar_model->default_parameters();
    apply_overrides(*planar_model, args.all("--set"), parameters);
    name = planar_model->name;
    const GiNaC::exmap subs = planar_model->substitutions(parameters);
    t0 = planar_model->evaluate(planar_model->step.t0, subs);
    t1 = planar_model->evaluate(planar_model->step.t1, subs);
  }
  options.t0 = t0;
  options.t1 = args.number("--t1", t1);
  if (!(options.t1 > options.t0)) throw UsageError("--t1 must be after the step's t0");

  // The kernel is resolved once (built on demand if need be); every plant shares it.
  const bool generated = solver_option(args) == "generated";
  const CompiledKernel* kernel = !generated ? nullptr
                                 : spatial  ? &ondemand::kernel_for(*spatial_model)
                                            : &ondemand::kernel_for(*planar_model);
  auto make_plant = [&]() -> std::unique_ptr<sim::Plant> {
    if (spatial)
      return kernel ? sim::spatial_kernel_plant(*spatial_model, parameters, *kernel)
                    : sim::spatial_plant(*spatial_model, parameters);
    return kernel ? sim::planar_kernel_plant(*planar_model, parameters, *kernel)
                  : sim::planar_plant(*planar_model, parameters);
  };
  std::unique_ptr<sim::Plant> plant = make_plant();
  const std::vector<std::string>& drivers = plant->drivers();
  // Passive drivers (plant order): their laws always apply.
  std::vector<bool> passive(drivers.size(), false);
  for (size_t d = 0; d < drivers.size(); ++d) {
    if (spatial)
      for (const SpatialDriver& sd : spatial_model->drivers)
        passive[d] = passive[d] || (sd.passive && sd.name == drivers[d]);
    else
      for (const Driver& pd : planar_model->drivers)
        passive[d] = passive[d] || (pd.passive && pd.name == drivers[d]);
  }
  const auto first_active = std::find(passive.begin(), passive.end(), false);
  if (first_active == passive.end() && (args.has("--motor") || args.has("--track")))
    throw UsageError("every driver is passive: nothing for --motor or --track to drive");
  const auto first_active_index = static_cast<size_t>(first_active - passive.begin());
  std::vector<std::string> free;
  std::optional<sim::MotorDrive> motor;
  if (args.has("--motor")) {
    const std::string driver = args.get("--driver", drivers[first_active_index]);
    int index = -1;
    for (size_t d = 0; d < drivers.size(); ++d)
      if (drivers[d] == driver) index = static_cast<int>(d);
    if (index < 0) throw UsageError("--driver: no driver '" + driver + "' in the model");
    if (passive[static_cast<size_t>(index)])
      throw UsageError("--driver: '" + driver + "' is passive (its effort is its law)");
    const std::string catalogue_path = args.get("--catalogue");
    g_current_file = catalogue_path;
    const std::vector<Motor> catalogue = read_catalogue(catalogue_path);
    g_current_file = path;
    for (const Motor& m : catalogue)
      if (m.name == args.get("--motor")) motor = sim::MotorDrive{index, m, 1};
    if (!motor)
      throw UsageError("--motor: no motor '" + args.get("--motor") + "' in " + catalogue_path);
    Eigen::VectorXd q, qd;
    plant->motion(options.t0, q, qd);
    motor->direction = qd[index] < 0 ? -1 : 1;
    motor->voltage = args.number("--voltage", 1);
    if (!(motor->voltage > 0)) throw UsageError("--voltage must be positive");
    options.extra_inertia = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(drivers.size()));
    options.extra_inertia[index] = motor->reflected_inertia();
    free.push_back(driver);
  }
  if (args.has("--periodic")) {
    if (drivers.empty()) throw UsageError("--periodic: the model has no driver");
    options.periodic_driver = motor                           ? motor->driver
                              : first_active != passive.end() ? static_cast<int>(first_active_index)
                                                              : 0;
    Eigen::VectorXd q0, q1, qd;
    plant->motion(t0, q0, qd);
    plant->motion(t1, q1, qd);
    options.period = std::abs(q1[options.periodic_driver] - q0[options.periodic_driver]);
    if (!(options.period > 0))
      throw UsageError("--periodic: the driver does not move over the model's step");
  }
  // A second plant for the controller (it is placed at the states the controller sees).
  std::shared_ptr<sim::Plant> control_plant;
  if (args.has("--track")) {
    const std::string kind = args.get("--track");
    if (kind != "computed-torque" && kind != "pd")
      throw UsageError("--track: '" + kind + "' is not computed-torque or pd");
    for (size_t d = 0; d < drivers.size(); ++d)
      if (!passive[d]) free.push_back(drivers[d]);
    control_plant = make_plant();
  }
  const sim::EffortFunction laws = spatial
                                       ? sim::model_effort_laws(*spatial_model, parameters, free)
                                       : sim::model_effort_laws(*planar_model, parameters, free);
  sim::EffortFunction effort = laws;
  if (motor)
    effort = [laws, drive = *motor](double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                    Eigen::VectorXd& e) {
      laws(t, q, qd, e);
      e[drive.driver] = drive.output_torque(qd[drive.driver]);
    };

  if (control_plant) {
    Eigen::VectorXd q, qd;
    control_plant->motion(options.t0, q, qd);
    if (options.from_rest) qd.setZero();
    numeric::MassBias mb;
    std::string why;
    if (!control_plant->place(options.t0, q, qd, mb, why))
      throw ModelError({path, 0, 0}, "simulate --track: at t0: " + why);
    effort = sim::tracking_controller(
        control_plant,
        args.get("--track") == "pd" ? sim::Control::pd : sim::Control::computed_torque,
        args.number("--kp", 400), args.number("--kd", 40), mb.M.diagonal(), passive, laws);
  }
  const auto start = std::chrono::steady_clock::now();
  const sim::SimulationResult result = sim::simulate(*plant, effort, options);
  const double elapsed = seconds_since(start);
  const std::string out = args.get("--out");
  g_current_file = out;
  write_csv(out, SweepResult{result.columns, result.rows});
  std::cout << "simulate " << name << " (" << (generated ? "generated" : "numeric")
            << " solver): " << sim::to_string(options.integrator) << ", dt " << fixed(options.dt, 6)
            << " s, " << result.steps << " steps, t = " << number_text(options.t0) << " .. "
            << number_text(result.rows.empty() ? options.t0 : result.rows.back().front()) << " s, "
            << result.rows.size() << " rows, " << fixed(elapsed, 4) << " s";
  if (motor)
    std::cout << ", motor " << motor->motor.name << " on " << drivers[motor->driver] << " at "
              << fixed(motor->voltage, 4) << " x rated voltage (reflected rotor inertia "
              << fixed(motor->reflected_inertia(), 4) << " kg m^2)";
  if (options.periodic_driver >= 0)
    std::cout << ", " << result.periods << " periods of " << fixed(options.period, 6) << " on "
              << drivers[static_cast<size_t>(options.periodic_driver)];
  std::cout << " -> " << out << "\n";
  if (!result.rows.empty()) {
    const std::vector<double>& first = result.rows.front();
    const std::vector<double>& last = result.rows.back();
    std::cout << "energy balance: " << fixed(first.back(), 10) << " J at t0, "
              << fixed(last.back(), 10) << " J at the end (drift "
              << fixed(last.back() - first.back(), 3) << " J)\n";
  }
  if (control_plant && !result.rows.empty()) {
    std::cout << "tracking (" << args.get("--track") << ", kp " << fixed(args.number("--kp", 400))
              << ", kd " << fixed(args.number("--kd", 40)) << "): largest |q_ref - q|";
    for (size_t d = 0; d < drivers.size(); ++d) {
      size_t c = 0;
      while (result.columns[c] != drivers[d] + ".q") ++c;
      double worst = 0;
      for (const std::vector<double>& row : result.rows) {
        Eigen::VectorXd qr, qdr;
        plant->motion(row.front(), qr, qdr);
        worst = std::max(worst, std::abs(qr[static_cast<Eigen::Index>(d)] - row[c]));
      }
      std::cout << (d ? ", " : " ") << drivers[d] << (passive[d] ? " (passive) " : " ")
                << fixed(worst, 4);
    }
    std::cout << "\n";
  }
  g_current_file = path;
  if (!result.error.empty())
    throw ModelError({path, 0, 0},
                     "simulate: " + result.error + " (the rows up to there are in " + out + ")");
  return 0;
}

}  // namespace

Command simulate_command() {
  return {"simulate",
          "forward dynamics: the drivers free under effort laws or a DC motor -> CSV",
          kSimulateHelp,
          {{"--out", "-o", true},
           {"--t1", "", true},
           {"--dt", "", true},
           {"--set", "", true, true},
           {"--from-rest", "", false},
           {"--solver", "", true},
           {"--integrator", "", true},
           {"--every", "", true},
           {"--periodic", "", false},
           {"--motor", "", true},
           {"--catalogue", "", true},
           {"--driver", "", true},
           {"--voltage", "", true},
           {"--track", "", true},
           {"--kp", "", true},
           {"--kd", "", true}},
          &run_simulate};
}

}  // namespace mechgen::cli
