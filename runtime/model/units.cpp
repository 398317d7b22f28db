#include "model/units.hpp"

namespace mechgen {

namespace {

struct UnitRow {
  const char* name;
  const char* si;
  double factor;
};

constexpr double kPi = 3.14159265358979323846;

// One row per accepted spelling; SI units map to themselves.
constexpr UnitRow kUnits[] = {
    {"1", "1", 1},  // dimensionless (also an empty unit)
    {"m", "m", 1},
    {"cm", "m", 1e-2},
    {"mm", "m", 1e-3},
    {"rad", "rad", 1},
    {"deg", "rad", kPi / 180},
    {"kg", "kg", 1},
    {"g", "kg", 1e-3},
    {"s", "s", 1},
    {"ms", "s", 1e-3},
    {"rad/s", "rad/s", 1},
    {"deg/s", "rad/s", kPi / 180},
    {"rpm", "rad/s", 2 * kPi / 60},
    {"rad/s^2", "rad/s^2", 1},
    {"m/s", "m/s", 1},
    {"m/s^2", "m/s^2", 1},
    {"N", "N", 1},
    {"N m", "N m", 1},
    {"N/m", "N/m", 1},
    {"N s/m", "N s/m", 1},
    {"N m/rad", "N m/rad", 1},
    {"N m s/rad", "N m s/rad", 1},
    {"kg m^2", "kg m^2", 1},
    {"g cm^2", "kg m^2", 1e-7},
    {"kg mm^2", "kg m^2", 1e-6},
    {"kg/m", "kg/m", 1},
    {"kg/m^2", "kg/m^2", 1},
    {"kg/m^3", "kg/m^3", 1},
    {"g/cm^3", "kg/m^3", 1e3},
    {"m^2", "m^2", 1},
    {"mm^2", "m^2", 1e-6},
    {"m^4", "m^4", 1},
    {"mm^4", "m^4", 1e-12},
    {"Pa", "Pa", 1},
    {"kPa", "Pa", 1e3},
    {"MPa", "Pa", 1e6},
    {"GPa", "Pa", 1e9},
    {"W", "W", 1},
    {"J", "J", 1},
};

// "N*m", "N  m" and " N m " all read as "N m".
std::string normalised(const std::string& unit) {
  std::string out;
  bool space = false;
  for (char c : unit) {
    if (c == ' ' || c == '\t' || c == '*') {
      space = !out.empty();
      continue;
    }
    if (space) out += ' ';
    space = false;
    out += c;
  }
  return out;
}

}  // namespace

std::optional<UnitConversion> find_unit(const std::string& unit) {
  const std::string key = normalised(unit);
  if (key.empty()) return UnitConversion{"1", 1};
  for (const UnitRow& row : kUnits)
    if (key == row.name) return UnitConversion{row.si, row.factor};
  return std::nullopt;
}

std::string known_units() {
  std::string list;
  for (const UnitRow& row : kUnits) list += (list.empty() ? "" : ", ") + std::string(row.name);
  return list;
}

}  // namespace mechgen
