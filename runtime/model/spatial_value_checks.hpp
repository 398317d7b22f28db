// The checks of a spatial model's numbers at one set of parameter values, as value_checks.hpp
// does for planar models: every real body's mass non-negative (zero: a massless link, with no
// inertia either), a massive body's inertia about the centre of mass
// symmetric and positive definite with principal moments that satisfy the triangle inequality
// (I1 + I2 >= I3: no rigid body has any other). The reader runs them on the file's values;
// apply_overrides (below) on --set values before anything is computed with them.
#pragma once

#include <string>
#include <vector>

#include "model/spatial_model.hpp"

namespace mechgen {

// Throws ModelError at the body's mass location; when `parameters` differ from the model's
// defaults, the message ends with the values that differ ("(with rho = -2700)").
void check_spatial_values(const SpatialModel& model, const std::vector<double>& parameters);

// apply_overrides(model.common, ...) followed by the spatial checks of the result.
void apply_overrides(const SpatialModel& model, const std::vector<std::string>& overrides,
                     std::vector<double>& values);

}  // namespace mechgen
