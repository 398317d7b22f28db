// `mechgen info --json`: the model metadata of DESIGN.md as JSON text, and the number and string
// formatting the command line shares.
#pragma once

#include <string>

#include "model/model.hpp"
#include "model/spatial_model.hpp"

namespace mechgen::spatial {
class SpatialSolver;
}

namespace mechgen::cli {

// {"name", "gravity", "parameters" (defaults), "bodies" (mass and inertia about the centre of mass
// at the defaults, ground flag), "points", "joints" (name, type, first, second, point), "drivers"
// (name, joint, kind)}, one body, joint or driver per line. Throws ModelError when a mass or the
// gravity does not evaluate.
std::string model_info_json(const Model& model);

// The same for a spatial model (DESIGN.md's "Spatial models"): name, dimension, gravity,
// parameters, reference_points, bodies, joints and drivers at the solver's parameters.
std::string spatial_model_info_json(const SpatialModel& model,
                                    const spatial::SpatialSolver& solver);

// The shortest decimal that reads back as the same double (at most 17 significant digits, "%.17g"
// style); "nan", "inf", "-inf" for non-finite values (never written to JSON: masses are finite).
std::string number_text(double value);

// A JSON string literal: quotes, backslashes and control characters escaped.
std::string json_string(const std::string& text);

// Mass and inertia about the centre of mass at the given parameters; 0 for the ground.
std::pair<double, double> mass_properties(const Model& model, const Body& body,
                                          const GiNaC::exmap& subs);

}  // namespace mechgen::cli
