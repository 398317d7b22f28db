// The checks of a model's numbers (positive masses, inertias, bar and section sizes, material
// values; finite everything; t1 > t0) for one set of parameter values. The reader runs them on
// the file's values; every run-time value (--set, a grid value, a catalogue motor's mass) goes
// through the same checks before anything is computed with it.
#pragma once

#include <vector>

#include "model/model.hpp"

namespace mechgen {

// Throws ModelError at the offending expression's location; when `parameters` differ from the
// model's defaults, the message ends with the values that differ ("(with m_hip = -4)").
void check_values(const Model& model, const std::vector<double>& parameters);

}  // namespace mechgen
