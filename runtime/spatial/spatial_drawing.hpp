// Drawings of a spatial model as SVG: two orthographic views side by side, sagittal (x right,
// z up: seen from the side, along y) and frontal (y right, z up: seen from the front, along -x),
// on one scale. Each body is a polyline through the joint points on it and its own points; each
// joint is a circle. One frame gives a still; several an animated SVG (SMIL, looping in real
// time) whose static attributes are the first frame.
#pragma once

#include <string>
#include <vector>

#include "model/spatial_model.hpp"
#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {

struct SpatialFrames {
  std::vector<double> times;
  std::vector<std::string> body_names;               // drawn bodies (two or more locations)
  std::vector<std::vector<std::vector<V3>>> bodies;  // [frame][drawn body][location]
  std::vector<std::vector<V3>> joints;               // [frame][real joint]: joint point
};

// Solves the model at each time (in order, continuing from one to the next). Throws ModelError.
SpatialFrames spatial_frames(const SpatialSolver& solver, const std::vector<double>& times);

struct SpatialDrawingOptions {
  int width = 1000;  // pixels for both views; the height follows the extent
  std::string title;
};

// SVG elements: <polyline id="side-BODY" / "front-BODY" class="body">, <circle class="joint">.
std::string draw_spatial(const SpatialFrames& frames, const SpatialDrawingOptions& options);

}  // namespace mechgen::spatial
