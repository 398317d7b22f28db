// Motor selection as in the seed (000, section 4): the torque and speed the crank needs over a
// step -> the smallest catalogue motor-gearbox that covers them with a safety factor -> its mass
// added to the hip -> the requirement recomputed -> the next larger motor until one holds.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "sweep/sweep.hpp"

namespace mechgen {

// One motor-gearbox of a catalogue. Torques and speed are the motor shaft's; the gearbox
// multiplies torque by ratio x efficiency and divides speed by the ratio.
struct Motor {
  std::string name;
  double rated_torque = 0;   // N m, continuous
  double peak_torque = 0;    // N m, short-term
  double no_load_speed = 0;  // rad/s (the catalogue gives rpm)
  double mass = 0;           // kg, motor and gearbox
  double gear_ratio = 1;     // motor turns per output turn
  double efficiency = 1;     // of the gearbox, in (0, 1]
  double rotor_inertia = 0;  // kg m^2, the motor's rotor (optional column; `mechgen simulate`)

  double output_rated_torque() const { return rated_torque * gear_ratio * efficiency; }
  double output_peak_torque() const { return peak_torque * gear_ratio * efficiency; }
  double output_speed() const { return no_load_speed / gear_ratio; }
};

// The catalogue CSV: '#' comment lines, then the header
//   name,rated_torque[N m],peak_torque[N m],no_load_speed[rpm],mass[kg],gear_ratio,efficiency
// (columns in any order; an optional rotor_inertia[g cm^2] is read when present), then one motor
// per line. Throws report::CsvError "FILE:LINE: MESSAGE"
// for a missing column, a bad number, a non-positive value or an efficiency above 1.
std::vector<Motor> parse_catalogue(const std::string& text, const std::string& path);
std::vector<Motor> read_catalogue(const std::string& path);

// What the crank needs over a step (magnitudes).
struct MotorRequirement {
  double peak_torque = 0;  // max |effort|, N m
  double rms_torque = 0;   // RMS of the effort over time, N m
  double peak_speed = 0;   // max |qd|, rad/s
};

// Read off a sweep: the columns <driver>.effort, <driver>.qd and t. Throws std::invalid_argument
// when one is missing.
MotorRequirement requirement_of(const SweepResult& sweep, const std::string& driver);

// The requirement of the model's step with `added_mass` kg added to parameter `mass_parameter`
// (on top of its value in `parameters`): one sweep (solver "generated" or "numeric"; samples 0:
// the step's). Throws ModelError for an unknown parameter or a failing sweep.
MotorRequirement step_requirement(const Model& model, std::vector<double> parameters,
                                  const std::string& mass_parameter, double added_mass,
                                  const std::string& driver,
                                  const std::string& solver = "generated", int samples = 0);

// Peak vs peak, RMS vs rated, speed vs no-load speed, each requirement multiplied by `safety`.
bool covers(const Motor& motor, const MotorRequirement& need, double safety);

struct SizingIteration {
  double added_mass = 0;  // kg on the hip while the requirement was computed
  MotorRequirement need;
  int tried = -1;      // index (catalogue order) of the motor whose mass is added; -1: none yet
  bool holds = false;  // `tried` covers `need`
  int proposed = -1;   // the smallest motor covering `need` (larger than `tried`); -1 when holds
};

struct SizingResult {
  std::vector<SizingIteration> iterations;
  int chosen = -1;  // catalogue index
};

// No motor (or no larger one) covers the requirement; `partial` holds the iterations so far.
class MotorSizingError : public std::runtime_error {
 public:
  MotorSizingError(const std::string& message, SizingResult partial_result)
      : std::runtime_error(message), partial(std::move(partial_result)) {}
  SizingResult partial;
};

// "Smallest" orders the catalogue by output rated torque, then output peak torque, then mass.
// Iteration 0 computes the requirement without a motor and proposes the smallest motor covering
// it; each later iteration adds the proposed motor's mass, recomputes, and stops when that motor
// still covers the requirement, else proposes the smallest larger one that covers the new
// requirement. `requirement_with_mass(m)` recomputes the requirement with m kg added to the hip.
// Throws MotorSizingError naming the requirement when no (larger) motor covers it.
SizingResult size_motor(const std::vector<Motor>& catalogue, double safety,
                        const std::function<MotorRequirement(double)>& requirement_with_mass);

// The iteration table and the choice, as `mechgen size-motor` prints them.
std::string format_sizing(const std::vector<Motor>& catalogue, double safety,
                          const SizingResult& result);

}  // namespace mechgen
