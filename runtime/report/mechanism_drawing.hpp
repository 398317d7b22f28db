// Drawings of a mechanism as SVG, from the point columns of a sweep or walk table: every body as a
// line (two points), a bar through collinear points or a filled polygon (three or more points not
// on one line), every joint location as a circle, the ground body on a hatched floor, labels
// optional. One frame gives a still; several give an animated SVG (SMIL <animate> of the shapes'
// coordinates, looping), whose static attributes are the first frame, so a viewer without
// animation (rsvg-convert) shows the mechanism at the start.
#pragma once

#include <string>
#include <vector>

#include "model/model.hpp"

namespace mechgen::report {

struct PointXY {
  double x = 0, y = 0;
};

// Positions of every named point (Model::named_points() order) at each frame's time.
struct MechanismFrames {
  std::vector<double> times;
  std::vector<std::vector<PointXY>> points;  // [frame][point]
};

// Reads "<point>.x", "<point>.y" (and "t") from a table with the given column names. Throws
// std::runtime_error naming the first missing column.
MechanismFrames frames_from_table(const Model& model, const std::vector<std::string>& columns,
                                  const std::vector<std::vector<double>>& rows);

// World (model ground frame, metres, y up) to SVG pixels (y down), fitted to every frame.
struct DrawingView {
  double scale = 1;             // pixels per metre
  double x_min = 0, y_max = 0;  // world coordinates of the drawing area's top-left corner
  double margin = 0;            // pixels around the drawing area
  int width = 0, height = 0;
  double px(double x) const { return margin + (x - x_min) * scale; }
  double py(double y) const { return margin + (y_max - y) * scale; }
};
DrawingView fit_view(const MechanismFrames& frames, int width);

struct DrawingOptions {
  int width = 900;       // pixels; the height follows the mechanism's extent
  bool labels = false;   // body names at their points' centroid
  std::string title;     // drawn at the top when not empty
  int max_frames = 120;  // an animation is resampled to at most this many frames, evenly in time
  // Bodies whose name ends with this (the flying leg of a biped) are drawn in a second colour.
  std::string mirror_suffix = "p";
  // Named points whose paths are drawn (dashed, under the bodies; a dot follows each on an
  // animation), over `trace_path` when it has frames (a still's step), else over every frame.
  std::vector<std::string> trace;
  MechanismFrames trace_path;
};

// How a body is drawn: its points (indices into named_points()) in drawing order, and whether
// they close a polygon. Bodies with fewer than two points are not drawn.
struct BodyShape {
  int body = -1;
  std::vector<int> points;
  bool polygon = false;
};
std::vector<BodyShape> body_shapes(const Model& model, const std::vector<PointXY>& at);

// The SVG document: a still of frame 0 when there is one frame, else the animation over all of
// them (duration: their time span, real time). Elements: <polyline|polygon id="body-NAME"
// class="body">, <circle id="joint-POINT" class="joint">, a <g id="ground"> floor,
// <polyline id="trace-POINT" class="trace"> and <circle id="tracer-POINT" class="tracer"> per
// traced point. Throws std::runtime_error for a traced name that is not a point.
std::string draw_mechanism(const Model& model, const MechanismFrames& frames,
                           const DrawingOptions& options);

}  // namespace mechgen::report
