// Drawings of a spatial model as SVG: orthographic views side by side on one scale, chosen from the
// mechanism's extent: of sagittal (x right, z up: seen from the side, along y), frontal (y right,
// z up: seen from the front, along -x) and top (x right, y up: seen from above), the two with the
// largest spread; one alone when the mechanism lies in a plane (the others would be lines). Each
// body is a polyline through the joint points on it and its own points; each joint is a circle.
// One frame gives a still; several an animated SVG (SMIL, looping in real time) whose static
// attributes are the first frame. Optional: body names beside the bodies, the paths of named
// points (dashed; a dot follows each point in an animation).
#pragma once

#include <string>
#include <vector>

#include "model/spatial_model.hpp"
#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {

struct SpatialFrames {
  std::vector<double> times;
  std::vector<std::string> body_names;  // drawn bodies (two or more locations)
  // [frame][drawn body][location]: a body of three or more locations as an outline that does not
  // cross itself (ordered about their centroid, the first repeated at the end to close it).
  std::vector<std::vector<std::vector<V3>>> bodies;
  std::vector<std::vector<V3>> joints;   // [frame][real joint]: joint point
  std::vector<std::string> trace_names;  // traced named points
  std::vector<std::vector<V3>> traces;   // [traced point][sample]: its path
};

// Solves the model at each time (in order, continuing from one to the next), with the paths of the
// named points `trace` over those times. Throws ModelError, and std::invalid_argument for a name
// that is no point of the model (naming the points it has).
SpatialFrames spatial_frames(const SpatialSolver& solver, const std::vector<double>& times,
                             const std::vector<std::string>& trace = {});

struct SpatialDrawingOptions {
  int width = 1000;  // pixels for both views; the height follows the extent
  std::string title;
  bool labels = false;  // body names beside the bodies
};

// The views draw_spatial chooses for these frames, by id: "side", "front", "top".
std::vector<std::string> spatial_views(const SpatialFrames& frames);

// SVG elements: <polyline id="VIEW-BODY" class="body"> (VIEW: side, front, top), <circle
// class="joint">, <text class="label">, <polyline id="VIEW-trace-POINT" class="trace">.
std::string draw_spatial(const SpatialFrames& frames, const SpatialDrawingOptions& options);

}  // namespace mechgen::spatial
