// Line plots as self-contained SVG text, drawn by the project itself (no plotting dependency):
// axes with "nice" 1-2-5 ticks, grid, axis labels, title, legend, one colour per series, clipping
// to the plot area. Non-finite values break a line; empty or constant data still give a valid plot.
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace mechgen::report {

struct Series {
  std::string label;
  std::vector<double> x, y;  // same length; NaN or infinite entries leave a gap in the line
};

struct PlotSpec {
  std::string title, x_label, y_label;  // units in the labels, e.g. "time t [s]"
  std::vector<Series> series;
  // Axis range; NaN means automatic (x: the data's extent, y: the data's extent plus 5 %).
  double x_min = std::numeric_limits<double>::quiet_NaN();
  double x_max = std::numeric_limits<double>::quiet_NaN();
  double y_min = std::numeric_limits<double>::quiet_NaN();
  double y_max = std::numeric_limits<double>::quiet_NaN();
  int width = 800, height = 500;  // SVG pixels
  // One scale on both axes (an x-y path keeps its shape): the axis with more pixels per unit
  // gets a wider range, centred on its data.
  bool equal_scale = false;
  // Events along x (a walk's support changes): dashed vertical lines, `x_marks_label` in the
  // legend.
  std::vector<double> x_marks;
  std::string x_marks_label;
  // Limits along y (a yield stress, the end of a stroke): dashed horizontal lines with their
  // labels, the side beyond shaded (above a maximum, below a minimum; `line`: no side shaded, as
  // for one of several cylinders' strokes on one axis); the y range includes them.
  struct Limit {
    enum class Side { line, max, min };
    double y;
    std::string label;
    Side side = Side::line;
  };
  std::vector<Limit> y_limits;
};

// Series on one axis at the most; render_svg splits more into panels.
inline constexpr std::size_t kMostSeriesPerPanel = 8;

// The whole plot as an SVG document (with a viewBox). More than kMostSeriesPerPanel series are
// split into panels (nested <svg class="panel">, titled "TITLE (i of n)") stacked one above the
// other, each spec.height tall, on the data's common x range. A series that lies exactly over an
// earlier one is dashed, so both show. Throws std::invalid_argument when a series' x and y differ
// in length (a caller's bug, not a data problem).
std::string render_svg(const PlotSpec& spec);

// ---- Building blocks, exposed for tests and for other figures ----

// Tick positions inside [lo, hi] at a step of 1, 2 or 5 times a power of ten, chosen as the
// smallest such step that gives at most about `target` intervals. Each tick is the double closest
// to its decimal value (0.6, not 0.6000000000000001). Empty when lo > hi or either is not finite.
std::vector<double> nice_ticks(double lo, double hi, int target);

// The tick step nice_ticks() uses for this span (> 0).
double nice_step(double span, int target);

// Labels for ticks at a common step: the same number of decimals for all ("0.0", "0.2", ...),
// scientific notation for very large or very small magnitudes; never "-0".
std::vector<std::string> tick_labels(const std::vector<double>& ticks);

// A data interval mapped linearly onto a pixel interval (px_lo may exceed px_hi: the y axis).
struct Axis {
  double lo = 0, hi = 1;        // data
  double px_lo = 0, px_hi = 1;  // pixels
  double to_px(double v) const { return px_lo + (v - lo) / (hi - lo) * (px_hi - px_lo); }
};

// Where everything goes: the plot area in pixels (left < right, top < bottom) and both axes.
struct PlotLayout {
  double left = 0, right = 0, top = 0, bottom = 0;
  Axis x, y;  // x: lo -> left, hi -> right; y: lo -> bottom, hi -> top
  std::vector<double> x_ticks, y_ticks;
  bool has_data = false;  // false: nothing finite to draw
};
PlotLayout compute_layout(const PlotSpec& spec);

// Text with &, <, >, " and ' escaped for SVG/XML.
std::string xml_escape(const std::string& text);

}  // namespace mechgen::report
