// mechgen size-motor: the seed's iterative motor-gearbox selection from a catalogue.
#include <algorithm>
#include <iostream>
#include <string>
#include <vector>

#include "analysis/motor_sizing.hpp"
#include "cli/command.hpp"
#include "sweep/sweep.hpp"

namespace mechgen::cli {

namespace {

const char* const kSizeMotorHelp =
    R"(usage: mechgen size-motor MODEL.yaml --catalogue FILE.csv [--safety FACTOR]
                          [--driver NAME] [--mass-parameter NAME] [--set NAME=VALUE]...
                          [--solver generated|numeric] [--samples N]

Motor selection as in the seed: sweep the step -> the crank's peak torque, RMS torque and peak
speed -> the smallest catalogue motor-gearbox covering them times the safety factor (output peak
torque = motor peak torque x gear ratio x efficiency against the peak, output rated torque
against the RMS, no-load speed / gear ratio against the peak speed) -> its mass added to the hip
parameter -> sweep again -> the next larger motor, until the motor on the hip covers what it
causes. Prints the iteration table and the choice.
  --catalogue FILE.csv  columns name,rated_torque[N m],peak_torque[N m],no_load_speed[rpm],
                        mass[kg],gear_ratio,efficiency ('#' lines are comments)
  --safety FACTOR       multiplies every requirement (default 1.5; at least 1)
  --driver NAME         the motor's driver (default: the model's first active driver; a
                        passive one, a spring, takes no motor)
  --mass-parameter NAME the parameter the motor's mass is added to (default m_load)
Exit 1 with one line when no motor of the catalogue suffices.
)";

int run_size_motor(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  if (!args.has("--catalogue")) throw UsageError("missing --catalogue FILE.csv");
  const double safety = args.number("--safety", 1.5);
  if (safety < 1) throw UsageError("--safety must be at least 1");
  const std::string solver = solver_option(args);
  const int samples = args.integer("--samples", 0);
  if (args.has("--samples") && samples < 1) throw UsageError("--samples must be at least 1");

  const Model model = load_model(path);
  std::vector<double> parameters = model.default_parameters();
  apply_overrides(model, args.all("--set"), parameters);
  if (model.drivers.empty()) throw UsageError("the model has no driver to size a motor for");
  const auto active = std::find_if(model.drivers.begin(), model.drivers.end(),
                                   [](const Driver& d) { return !d.passive; });
  if (active == model.drivers.end()) throw UsageError("every driver is passive: no motor to size");
  const std::string driver = args.get("--driver", active->name);
  const auto chosen = std::find_if(model.drivers.begin(), model.drivers.end(),
                                   [&](const Driver& d) { return d.name == driver; });
  if (chosen == model.drivers.end())
    throw UsageError("--driver: no driver '" + driver + "' in the model");
  if (chosen->passive)
    throw UsageError("--driver: '" + driver +
                     "' is passive (its effort is its law, not a motor's)");
  const std::string mass_parameter = args.get("--mass-parameter", "m_load");
  size_t mass_index = model.parameters.size();
  for (size_t i = 0; i < model.parameters.size(); ++i)
    if (model.parameters[i].name == mass_parameter) mass_index = i;
  if (mass_index == model.parameters.size())
    throw UsageError("--mass-parameter: no parameter '" + mass_parameter + "' in the model");

  const std::string catalogue_path = args.get("--catalogue");
  g_current_file = catalogue_path;
  const std::vector<Motor> catalogue = read_catalogue(catalogue_path);

  const double base_mass = parameters[mass_index];
  auto requirement_with_mass = [&](double added) {
    g_current_file = path;  // a failing sweep is the model's error
    const MotorRequirement need =
        step_requirement(model, parameters, mass_parameter, added, driver, solver, samples);
    g_current_file = catalogue_path;
    return need;
  };
  std::cout << "size-motor " << model.name << ": driver " << driver << ", motor mass added to "
            << mass_parameter << " (" << fixed(base_mass) << " kg without it), catalogue "
            << catalogue_path << " (" << catalogue.size() << " motors)\n";
  try {
    std::cout << format_sizing(catalogue, safety,
                               size_motor(catalogue, safety, requirement_with_mass));
  } catch (const MotorSizingError& error) {
    std::cout << format_sizing(catalogue, safety, error.partial) << std::flush;
    throw;  // the one-line error on stderr, exit 1
  }
  return 0;
}

}  // namespace

Command size_motor_command() {
  return {"size-motor",
          "pick the smallest catalogue motor-gearbox that carries its own mass (seed's iteration)",
          kSizeMotorHelp,
          {{"--catalogue", "", true},
           {"--safety", "", true},
           {"--driver", "", true},
           {"--mass-parameter", "", true},
           {"--set", "", true, true},
           {"--solver", "", true},
           {"--samples", "", true}},
          &run_size_motor};
}

}  // namespace mechgen::cli
