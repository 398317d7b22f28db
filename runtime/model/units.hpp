// Units a parameter's `unit:` may name. Values are converted to SI when a description is read
// (38 with unit mm is 0.038 m); a unit that is not in the list is an error, never ignored.
#pragma once

#include <optional>
#include <string>

namespace mechgen {

struct UnitConversion {
  std::string si;     // the SI unit the value is converted to ("m" for "mm")
  double factor = 1;  // SI value = factor * written value
};

// The conversion of `unit` (spaces and '*' between factors are equivalent: "N m", "N*m"), or
// nothing when the unit is not known. The empty unit is dimensionless.
std::optional<UnitConversion> find_unit(const std::string& unit);

// Every known unit, comma separated, for error messages and docs/model_format.md.
std::string known_units();

}  // namespace mechgen
