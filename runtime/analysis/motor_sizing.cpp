#include "analysis/motor_sizing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <numeric>
#include <sstream>

#include "report/csv_table.hpp"
#include "sweep/summary.hpp"

namespace mechgen {

namespace {

std::string trimmed(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) cells.push_back(trimmed(cell));
  if (!line.empty() && line.back() == ',') cells.push_back("");
  return cells;
}

std::string number(double value, int digits = 4) {
  char text[40];
  std::snprintf(text, sizeof text, "%.*g", digits, value);
  return text;
}

constexpr double kRpm = 2 * std::numbers::pi / 60;  // rad/s per rpm

}  // namespace

std::vector<Motor> parse_catalogue(const std::string& text, const std::string& path) {
  static const std::vector<std::string> kColumns{
      "name",     "rated_torque[N m]", "peak_torque[N m]", "no_load_speed[rpm]",
      "mass[kg]", "gear_ratio",        "efficiency"};
  auto fail = [&](int line, const std::string& message) {
    throw report::CsvError(path + ":" + std::to_string(line) + ": " + message);
  };
  std::vector<Motor> motors;
  std::vector<int> where;  // column of each of kColumns
  int rotor_column = -1;   // optional: rotor_inertia[g cm^2]
  size_t header_size = 0;
  std::stringstream in(text);
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    line = trimmed(line);
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> cells = split_commas(line);
    if (where.empty()) {
      for (const std::string& column : kColumns) {
        const auto it = std::find(cells.begin(), cells.end(), column);
        if (it == cells.end()) {
          std::string expected;
          for (const std::string& c : kColumns) expected += (expected.empty() ? "" : ",") + c;
          fail(line_number,
               "the header has no column '" + column + "' (expected " + expected + ")");
        }
        where.push_back(static_cast<int>(it - cells.begin()));
      }
      header_size = cells.size();
      const auto rotor = std::find(cells.begin(), cells.end(), "rotor_inertia[g cm^2]");
      if (rotor != cells.end()) rotor_column = static_cast<int>(rotor - cells.begin());
      continue;
    }
    if (cells.size() != header_size)
      fail(line_number, "expected " + std::to_string(header_size) +
                            " cells as in the header, got " + std::to_string(cells.size()));
    double values[6] = {};
    for (size_t c = 1; c < kColumns.size(); ++c) {
      const size_t at = static_cast<size_t>(where[c]);
      const std::string& cell = cells[at];
      size_t used = 0;
      try {
        values[c - 1] = std::stod(cell, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (cell.empty() || used != cell.size() || !std::isfinite(values[c - 1]))
        fail(line_number, kColumns[c] + ": '" + cell + "' is not a number");
      if (values[c - 1] <= 0) fail(line_number, kColumns[c] + " must be positive, got " + cell);
    }
    Motor motor;
    motor.name = cells[static_cast<size_t>(where[0])];
    if (motor.name.empty()) fail(line_number, "a motor without a name");
    motor.rated_torque = values[0];
    motor.peak_torque = values[1];
    motor.no_load_speed = values[2] * kRpm;
    motor.mass = values[3];
    motor.gear_ratio = values[4];
    motor.efficiency = values[5];
    if (rotor_column >= 0) {
      const std::string& cell = cells[static_cast<size_t>(rotor_column)];
      size_t used = 0;
      try {
        motor.rotor_inertia = std::stod(cell, &used) * 1e-7;  // g cm^2 -> kg m^2
      } catch (const std::exception&) {
        used = 0;
      }
      if (cell.empty() || used != cell.size() || !(motor.rotor_inertia >= 0) ||
          !std::isfinite(motor.rotor_inertia))
        fail(line_number, "rotor_inertia[g cm^2]: '" + cell + "' is not a non-negative number");
    }
    if (motor.efficiency > 1)
      fail(line_number, "efficiency must be at most 1, got " + number(motor.efficiency));
    if (motor.peak_torque < motor.rated_torque)
      fail(line_number, "peak torque below the rated torque");
    motors.push_back(motor);
  }
  if (where.empty()) fail(line_number, "no header line");
  if (motors.empty()) fail(line_number, "no motor in the catalogue");
  return motors;
}

std::vector<Motor> read_catalogue(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw report::CsvError(path + ":0: cannot read the file");
  std::stringstream text;
  text << file.rdbuf();
  return parse_catalogue(text.str(), path);
}

MotorRequirement requirement_of(const SweepResult& sweep, const std::string& driver) {
  auto column = [&](const std::string& name) {
    const auto it = std::find(sweep.columns.begin(), sweep.columns.end(), name);
    if (it == sweep.columns.end())
      throw std::invalid_argument("the sweep has no column '" + name + "'");
    std::vector<double> values;
    const auto c = static_cast<size_t>(it - sweep.columns.begin());
    for (const std::vector<double>& row : sweep.rows) values.push_back(row[c]);
    return values;
  };
  const std::vector<double> t = column("t"), effort = column(driver + ".effort"),
                            speed = column(driver + ".qd");
  MotorRequirement need;
  for (double e : effort) need.peak_torque = std::max(need.peak_torque, std::abs(e));
  for (double s : speed) need.peak_speed = std::max(need.peak_speed, std::abs(s));
  need.rms_torque = time_rms(t, effort);
  return need;
}

MotorRequirement step_requirement(const Model& model, std::vector<double> parameters,
                                  const std::string& mass_parameter, double added_mass,
                                  const std::string& driver, const std::string& solver,
                                  int samples) {
  size_t index = model.parameters.size();
  for (size_t i = 0; i < model.parameters.size(); ++i)
    if (model.parameters[i].name == mass_parameter) index = i;
  if (index == model.parameters.size())
    throw ModelError({model.file, 0, 0},
                     "no parameter '" + mass_parameter + "' for the motor's mass");
  parameters[index] += added_mass;
  SweepOptions options = default_sweep(model, parameters);
  options.solver = solver;
  if (samples > 0) options.samples = samples;
  return requirement_of(run_sweep(model, options), driver);
}

bool covers(const Motor& motor, const MotorRequirement& need, double safety) {
  return motor.output_peak_torque() >= safety * need.peak_torque &&
         motor.output_rated_torque() >= safety * need.rms_torque &&
         motor.output_speed() >= safety * need.peak_speed;
}

namespace {

std::vector<int> by_size(const std::vector<Motor>& catalogue) {
  std::vector<int> order(catalogue.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    const Motor &x = catalogue[static_cast<size_t>(a)], &y = catalogue[static_cast<size_t>(b)];
    if (x.output_rated_torque() != y.output_rated_torque())
      return x.output_rated_torque() < y.output_rated_torque();
    if (x.output_peak_torque() != y.output_peak_torque())
      return x.output_peak_torque() < y.output_peak_torque();
    return x.mass < y.mass;
  });
  return order;
}

std::string describe(const MotorRequirement& need, double safety) {
  return "peak " + number(safety * need.peak_torque) + " N m, RMS " +
         number(safety * need.rms_torque) + " N m, speed " + number(safety * need.peak_speed) +
         " rad/s (safety factor " + number(safety) + " included)";
}

}  // namespace

SizingResult size_motor(const std::vector<Motor>& catalogue, double safety,
                        const std::function<MotorRequirement(double)>& requirement_with_mass) {
  if (catalogue.empty()) throw std::runtime_error("the motor catalogue is empty");
  if (!(safety >= 1)) throw std::invalid_argument("the safety factor must be at least 1");
  const std::vector<int> order = by_size(catalogue);
  SizingResult result;
  size_t rank = 0;  // where in `order` the next search starts
  int tried = -1;
  // Each motor is tried at most once and only larger ones after it: at most size() + 1 rounds.
  for (;;) {
    SizingIteration step;
    step.tried = tried;
    step.added_mass = tried < 0 ? 0.0 : catalogue[static_cast<size_t>(tried)].mass;
    step.need = requirement_with_mass(step.added_mass);
    step.holds = tried >= 0 && covers(catalogue[static_cast<size_t>(tried)], step.need, safety);
    if (!step.holds) {
      while (rank < order.size() &&
             !covers(catalogue[static_cast<size_t>(order[rank])], step.need, safety))
        ++rank;
      if (rank == order.size()) {
        result.iterations.push_back(step);
        throw MotorSizingError(
            std::string("no ") + (tried < 0 ? "" : "larger ") + "motor in the catalogue covers " +
                describe(step.need, safety) +
                (tried < 0 ? "" : " with " + number(step.added_mass) + " kg of motor on the hip") +
                "; the largest gives peak " +
                number(catalogue[static_cast<size_t>(order.back())].output_peak_torque()) +
                " N m, rated " +
                number(catalogue[static_cast<size_t>(order.back())].output_rated_torque()) +
                " N m, " + number(catalogue[static_cast<size_t>(order.back())].output_speed()) +
                " rad/s",
            result);
      }
      step.proposed = order[rank++];
    }
    result.iterations.push_back(step);
    if (step.holds) {
      result.chosen = tried;
      return result;
    }
    tried = step.proposed;
  }
}

std::string format_sizing(const std::vector<Motor>& catalogue, double safety,
                          const SizingResult& result) {
  std::vector<std::vector<std::string>> rows{{"iter", "motor on hip", "added [kg]", "peak [N m]",
                                              "RMS [N m]", "speed [rad/s]", "holds",
                                              "next proposal"}};
  for (size_t i = 0; i < result.iterations.size(); ++i) {
    const SizingIteration& it = result.iterations[i];
    auto name = [&](int k) {
      return k < 0 ? std::string("-") : catalogue[static_cast<size_t>(k)].name;
    };
    rows.push_back({std::to_string(i), name(it.tried), number(it.added_mass),
                    number(it.need.peak_torque), number(it.need.rms_torque),
                    number(it.need.peak_speed), it.tried < 0 ? "-" : (it.holds ? "yes" : "no"),
                    it.holds ? "(chosen)" : (it.proposed < 0 ? "(none fits)" : name(it.proposed))});
  }
  std::vector<size_t> width(rows.front().size(), 0);
  for (const auto& row : rows)
    for (size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
  std::string out = "motor sizing: the crank's requirement at each iteration (times the safety " +
                    std::string("factor ") + number(safety) +
                    " against the catalogue's output side)\n";
  for (const auto& row : rows) {
    std::string line = " ";
    for (size_t c = 0; c < row.size(); ++c)
      line += "  " + row[c] + std::string(width[c] - row[c].size(), ' ');
    while (line.back() == ' ') line.pop_back();
    out += line + "\n";
  }
  if (result.chosen >= 0) {
    const Motor& m = catalogue[static_cast<size_t>(result.chosen)];
    const MotorRequirement& need = result.iterations.back().need;
    out += "chosen: " + m.name + " (" + number(m.mass) + " kg, gear ratio " + number(m.gear_ratio) +
           ", efficiency " + number(m.efficiency) + ")\n";
    out += "  output peak torque  " + number(m.output_peak_torque()) +
           " N m >= " + number(safety * need.peak_torque) + " N m needed (" +
           number(need.peak_torque) + " x " + number(safety) + ")\n";
    out += "  output rated torque " + number(m.output_rated_torque()) +
           " N m >= " + number(safety * need.rms_torque) + " N m needed (RMS " +
           number(need.rms_torque) + " x " + number(safety) + ")\n";
    out += "  output speed        " + number(m.output_speed()) +
           " rad/s >= " + number(safety * need.peak_speed) + " rad/s needed (" +
           number(need.peak_speed) + " x " + number(safety) + ")\n";
  }
  return out;
}

}  // namespace mechgen
