#include "report/svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace mechgen::report {
namespace {

// A tick step m * 10^e with m in {1, 2, 5}.
struct Step {
  int mantissa = 1;
  int exponent = 0;
  double value() const { return scaled(1); }
  // k * m * 10^e rounded once (powers of ten up to 1e22 are exact), so 3 * 0.2 gives 0.6.
  double scaled(long long k) const {
    const double digits = static_cast<double>(k * mantissa);
    return exponent >= 0 ? digits * std::pow(10.0, exponent) : digits / std::pow(10.0, -exponent);
  }
};

Step choose_step(double span, int target) {
  if (!(span > 0) || !std::isfinite(span)) return {};
  const double raw = span / std::max(target, 1);
  int e = static_cast<int>(std::floor(std::log10(raw)));
  double f = raw / std::pow(10.0, e);  // about [1, 10)
  int m;
  if (f <= 1 + 1e-9) {
    m = 1;
  } else if (f <= 2 + 1e-9) {
    m = 2;
  } else if (f <= 5 + 1e-9) {
    m = 5;
  } else {
    m = 1;
    ++e;
  }
  return {m, e};
}

std::vector<double> ticks_with(double lo, double hi, Step step) {
  std::vector<double> ticks;
  const double s = step.value();
  const double first = std::ceil(lo / s - 1e-9);
  const double last = std::floor(hi / s + 1e-9);
  if (!(last - first < 1000)) return ticks;  // degenerate span for its magnitude
  for (double k = first; k <= last; k += 1) {
    const double v = step.scaled(static_cast<long long>(k));
    ticks.push_back(v == 0 ? 0.0 : v);  // no -0
  }
  return ticks;
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string px(double v) {
  v = std::clamp(v, -1e6, 1e6);  // far outside the clip rectangle; keeps renderers in range
  std::string s = fixed(v, 2);
  return s == "-0.00" ? "0.00" : s;
}

// Typographic minus for display.
std::string display_number(const std::string& s) {
  return !s.empty() && s[0] == '-' ? "&#8722;" + s.substr(1) : s;
}

// Rough text width for layout: sans-serif digits and letters average ~0.6 em.
double text_width(const std::string& s, double font_size) {
  return 0.6 * font_size * static_cast<double>(s.size());
}

constexpr double kTickFont = 12, kLabelFont = 13, kTitleFont = 16, kLegendFont = 12;

// A range that is never empty: a constant pads by 10 % of its magnitude (or 1 around zero).
void ensure_span(double& lo, double& hi) {
  const double mag = std::max(std::abs(lo), std::abs(hi));
  if (hi - lo > mag * 1e-12 && hi > lo) return;
  const double c = 0.5 * (lo + hi);
  const double pad = c != 0 ? 0.1 * std::abs(c) : 1.0;
  lo = c - pad;
  hi = c + pad;
}

struct Extent {
  double xlo = INFINITY, xhi = -INFINITY, ylo = INFINITY, yhi = -INFINITY;
  bool any() const { return xlo <= xhi; }
};

void check_lengths(const PlotSpec& spec) {
  for (const Series& s : spec.series) {
    if (s.x.size() != s.y.size()) {
      throw std::invalid_argument("plot series '" + s.label + "': " + std::to_string(s.x.size()) +
                                  " x values but " + std::to_string(s.y.size()) + " y values");
    }
  }
}

Extent data_extent(const PlotSpec& spec) {
  Extent e;
  for (const Series& s : spec.series) {
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      e.xlo = std::min(e.xlo, s.x[i]);
      e.xhi = std::max(e.xhi, s.x[i]);
      e.ylo = std::min(e.ylo, s.y[i]);
      e.yhi = std::max(e.yhi, s.y[i]);
    }
  }
  return e;
}

// Legend entries: at most a quarter of the width, so long labels cannot squeeze the plot.
constexpr double kLegendCharWidth = 7.2, kLegendChrome = 58;
std::size_t legend_chars(double width) {
  return static_cast<std::size_t>(std::max(8.0, (0.25 * width - kLegendChrome) / kLegendCharWidth));
}
std::string legend_text(const std::string& label, std::size_t max_chars) {
  if (label.size() <= max_chars) return label;
  return label.substr(0, max_chars - 3) + "...";
}

const char* const kColours[] = {"#1b5fa8", "#d9541e", "#2e8b3d", "#b8202f", "#7048a8",
                                "#8a6a2e", "#d4449a", "#4d4d4d", "#1a9ba8", "#a8a019"};
constexpr int kColourCount = sizeof kColours / sizeof kColours[0];
const char* const kDashes[] = {"", "6 3", "2 3", "8 3 2 3"};

}  // namespace

double nice_step(double span, int target) {
  return choose_step(span, target).value();
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || lo > hi) return {};
  if (lo == hi) return {lo == 0 ? 0.0 : lo};
  return ticks_with(lo, hi, choose_step(hi - lo, target));
}

std::vector<std::string> tick_labels(const std::vector<double>& ticks) {
  std::vector<std::string> labels;
  if (ticks.empty()) return labels;
  double step = 0, max_abs = 0;
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    max_abs = std::max(max_abs, std::abs(ticks[i]));
    if (i > 0) step = step == 0 ? ticks[i] - ticks[i - 1] : std::min(step, ticks[i] - ticks[i - 1]);
  }
  if (!(step > 0)) step = max_abs > 0 ? max_abs : 1;
  const int step_exp = static_cast<int>(std::floor(std::log10(step) + 1e-9));
  const int decimals = std::max(0, -step_exp);
  const bool scientific = max_abs >= 1e7 || decimals > 6;
  for (double v : ticks) {
    if (std::abs(v) < step * 1e-6) v = 0;
    std::string s;
    if (scientific && v != 0) {
      const int mag_exp = static_cast<int>(std::floor(std::log10(max_abs)));
      const int significant = std::clamp(mag_exp - step_exp + 1, 1, 17);
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.*e", significant - 1, v);
      s = buf;
    } else {
      s = fixed(v, scientific ? 0 : decimals);
    }
    labels.push_back(s);
  }
  return labels;
}

std::string xml_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

namespace {
PlotLayout free_layout(const PlotSpec& spec);

// Pixels per data unit of an axis.
double pixels_per_unit(const Axis& a) {
  return std::abs(a.px_hi - a.px_lo) / (a.hi - a.lo);
}
}  // namespace

PlotLayout compute_layout(const PlotSpec& spec) {
  if (!spec.equal_scale) return free_layout(spec);
  // Widen one axis's range until both scales agree; the margins depend on the tick labels, so
  // lay out again (they settle in a pass or two), then make the last range exact.
  PlotSpec fixed = spec;
  fixed.equal_scale = false;
  PlotLayout L = free_layout(fixed);
  for (int pass = 0; pass < 4; ++pass) {
    const double sx = pixels_per_unit(L.x), sy = pixels_per_unit(L.y);
    if (std::abs(sx - sy) <= 1e-12 * std::max(sx, sy)) break;
    Axis& wide = sx > sy ? L.x : L.y;
    const double scale = std::min(sx, sy);
    const double centre = (wide.lo + wide.hi) / 2;
    const double half = std::abs(wide.px_hi - wide.px_lo) / scale / 2;
    if (sx > sy) {
      fixed.x_min = centre - half, fixed.x_max = centre + half;
      fixed.y_min = L.y.lo, fixed.y_max = L.y.hi;
    } else {
      fixed.y_min = centre - half, fixed.y_max = centre + half;
      fixed.x_min = L.x.lo, fixed.x_max = L.x.hi;
    }
    L = free_layout(fixed);
  }
  const double sx = pixels_per_unit(L.x), sy = pixels_per_unit(L.y);
  Axis& wide = sx > sy ? L.x : L.y;
  const double centre = (wide.lo + wide.hi) / 2;
  const double half = std::abs(wide.px_hi - wide.px_lo) / std::min(sx, sy) / 2;
  wide.lo = centre - half;
  wide.hi = centre + half;
  return L;
}

namespace {
PlotLayout free_layout(const PlotSpec& spec) {
  check_lengths(spec);
  PlotLayout L;
  const double width = std::max(spec.width, 200), height = std::max(spec.height, 150);
  const Extent e = data_extent(spec);
  L.has_data = e.any();

  double xlo = L.has_data ? e.xlo : 0, xhi = L.has_data ? e.xhi : 1;
  double ylo = L.has_data ? e.ylo : 0, yhi = L.has_data ? e.yhi : 1;
  for (const PlotSpec::Limit& limit : spec.y_limits)
    if (std::isfinite(limit.y) && L.has_data)
      ylo = std::min(ylo, limit.y), yhi = std::max(yhi, limit.y);
  if (L.has_data) {
    const double pad = 0.05 * (yhi - ylo);
    ylo -= pad;
    yhi += pad;
  }
  if (std::isfinite(spec.x_min)) xlo = spec.x_min;
  if (std::isfinite(spec.x_max)) xhi = spec.x_max;
  if (std::isfinite(spec.y_min)) ylo = spec.y_min;
  if (std::isfinite(spec.y_max)) yhi = spec.y_max;
  ensure_span(xlo, xhi);
  ensure_span(ylo, yhi);

  // Vertical extent first: it fixes the y ticks, whose labels fix the left margin.
  L.top = spec.title.empty() ? 20 : 48;
  L.bottom = height - (spec.x_label.empty() ? 36 : 58);
  const int y_target = std::max(2, static_cast<int>((L.bottom - L.top) / 55));
  L.y_ticks = nice_ticks(ylo, yhi, y_target);
  double y_label_width = 0;
  for (const std::string& s : tick_labels(L.y_ticks)) {
    y_label_width = std::max(y_label_width, text_width(s, kTickFont));
  }
  L.left = 14 + (spec.y_label.empty() ? 0 : 24) + y_label_width + 10;

  std::size_t chars = 0;
  for (const Series& s : spec.series) {
    chars = std::max(chars, legend_text(s.label, legend_chars(width)).size());
  }
  const double legend_width = chars > 0 ? kLegendChrome + kLegendCharWidth * chars : 0;
  L.right = width - 16 - legend_width;
  if (L.right - L.left < 80) L.right = std::min(width - 10, L.left + 80);

  // Fewer x ticks until their labels fit side by side.
  for (int x_target = std::max(2, static_cast<int>((L.right - L.left) / 90));; --x_target) {
    L.x_ticks = nice_ticks(xlo, xhi, x_target);
    double widest = 0;
    for (const std::string& s : tick_labels(L.x_ticks)) {
      widest = std::max(widest, text_width(s, kTickFont));
    }
    const double room = (L.right - L.left) / std::max<std::size_t>(L.x_ticks.size(), 1);
    if (widest + 12 <= room || x_target <= 1) break;
  }

  L.x = {xlo, xhi, L.left, L.right};
  L.y = {ylo, yhi, L.bottom, L.top};
  return L;
}
}  // namespace

namespace {

// One plot (render_svg's panel); `clip` is the id of its plot area's clip path.
std::string render_panel(const PlotSpec& spec, const std::string& clip) {
  const PlotLayout L = compute_layout(spec);
  const int width = std::max(spec.width, 200), height = std::max(spec.height, 150);
  std::string o;
  auto line = [&](double x1, double y1, double x2, double y2, const std::string& attrs) {
    o += "<line x1=\"" + px(x1) + "\" y1=\"" + px(y1) + "\" x2=\"" + px(x2) + "\" y2=\"" + px(y2) +
         "\"" + attrs + "/>\n";
  };
  auto text = [&](double x, double y, const std::string& attrs, const std::string& body) {
    o += "<text x=\"" + px(x) + "\" y=\"" + px(y) + "\"" + attrs + ">" + body + "</text>\n";
  };

  o += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(width) +
       "\" height=\"" + std::to_string(height) + "\" viewBox=\"0 0 " + std::to_string(width) + " " +
       std::to_string(height) +
       "\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" font-size=\"12\">\n";
  if (!spec.title.empty()) o += "<title>" + xml_escape(spec.title) + "</title>\n";
  o += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  const std::string area = "x=\"" + px(L.left) + "\" y=\"" + px(L.top) + "\" width=\"" +
                           px(L.right - L.left) + "\" height=\"" + px(L.bottom - L.top) + "\"";
  o += "<defs><clipPath id=\"" + clip + "\"><rect " + area + "/></clipPath></defs>\n";

  // Grid, then a stronger line at zero when it lies inside the range.
  o += "<g class=\"grid\" stroke=\"#e4e4e4\" stroke-width=\"1\">\n";
  for (double t : L.x_ticks) line(L.x.to_px(t), L.top, L.x.to_px(t), L.bottom, "");
  for (double t : L.y_ticks) line(L.left, L.y.to_px(t), L.right, L.y.to_px(t), "");
  o += "</g>\n";
  if (L.y.lo < 0 && L.y.hi > 0) {
    line(L.left, L.y.to_px(0), L.right, L.y.to_px(0), " stroke=\"#a8a8a8\" stroke-width=\"1\"");
  }

  // Limits along y, under the data: beyond a maximum or a minimum shaded. Labels alternate
  // between the right and the left end (limits close together stay readable), above the line
  // (below a minimum's, and a line's at the left).
  for (std::size_t k = 0; k < spec.y_limits.size(); ++k) {
    const PlotSpec::Limit& limit = spec.y_limits[k];
    if (!std::isfinite(limit.y) || limit.y < L.y.lo || limit.y > L.y.hi) continue;
    using Side = PlotSpec::Limit::Side;
    const bool right = k % 2 == 0;
    const bool above = limit.side == Side::max || (limit.side == Side::line && right);
    const double y = L.y.to_px(limit.y), edge = limit.side == Side::max ? L.top : L.bottom;
    if (limit.side != PlotSpec::Limit::Side::line)
      o += "<rect class=\"beyond-limit\" x=\"" + px(L.left) + "\" y=\"" + px(std::min(y, edge)) +
           "\" width=\"" + px(L.right - L.left) + "\" height=\"" + px(std::abs(edge - y)) +
           "\" fill=\"#b8202f\" fill-opacity=\"0.08\"/>\n";
    line(L.left, y, L.right, y,
         " class=\"limit\" stroke=\"#b8202f\" stroke-width=\"1.2\" stroke-dasharray=\"7 4\"");
    text(right ? L.right - 6 : L.left + 6, above ? y - 5 : y + 14,
         std::string(" text-anchor=\"") + (right ? "end" : "start") + "\" fill=\"#b8202f\"",
         xml_escape(limit.label));
  }

  // Events along x, under the data.
  for (const double x : spec.x_marks)
    if (std::isfinite(x) && x >= L.x.lo && x <= L.x.hi)
      line(L.x.to_px(x), L.top, L.x.to_px(x), L.bottom,
           " class=\"x-mark\" stroke=\"#888888\" stroke-width=\"1\" stroke-dasharray=\"4 3\"");

  // Data: one path per series, a new sub-path after every non-finite value, a dot for a point
  // that has no finite neighbour.
  o += "<g class=\"series\" clip-path=\"url(#" + clip +
       ")\" fill=\"none\" stroke-width=\"1.8\" stroke-linejoin=\"round\" "
       "stroke-linecap=\"round\">\n";
  std::vector<std::string> paths, dashes;
  for (std::size_t k = 0; k < spec.series.size(); ++k) {
    const Series& s = spec.series[k];
    const std::string colour = kColours[k % kColourCount];
    std::string d, dots;
    const std::size_t n = s.x.size();
    auto finite = [&](std::size_t i) { return std::isfinite(s.x[i]) && std::isfinite(s.y[i]); };
    for (std::size_t i = 0; i < n; ++i) {
      if (!finite(i)) continue;
      const bool starts = i == 0 || !finite(i - 1);
      const std::string xy = px(L.x.to_px(s.x[i])) + "," + px(L.y.to_px(s.y[i]));
      d += (starts ? (d.empty() ? "M" : " M") : " L") + xy;
      if (starts && (i + 1 == n || !finite(i + 1))) {
        dots += "<circle cx=\"" + px(L.x.to_px(s.x[i])) + "\" cy=\"" + px(L.y.to_px(s.y[i])) +
                "\" r=\"2.5\" fill=\"" + colour + "\" stroke=\"none\"/>\n";
      }
    }
    // A series drawn exactly over an earlier one (the same pixels) is dashed with long gaps, so
    // that the one beneath still shows.
    std::string dash = kDashes[(k / kColourCount) % 4];
    if (!d.empty() && std::find(paths.begin(), paths.end(), d) != paths.end()) dash = "5 7";
    paths.push_back(d), dashes.push_back(dash);
    if (!d.empty()) {
      o += "<path class=\"series-" + std::to_string(k) + "\" stroke=\"" + colour + "\"";
      if (!dash.empty()) o += " stroke-dasharray=\"" + dash + "\"";
      o += " d=\"" + d + "\"/>\n";
    }
    o += dots;
  }
  o += "</g>\n";

  // Frame, ticks and their labels.
  o += "<rect " + area + " fill=\"none\" stroke=\"#333333\" stroke-width=\"1\"/>\n";
  o += "<g class=\"ticks\" stroke=\"#333333\" stroke-width=\"1\">\n";
  for (double t : L.x_ticks) line(L.x.to_px(t), L.bottom, L.x.to_px(t), L.bottom + 5, "");
  for (double t : L.y_ticks) line(L.left - 5, L.y.to_px(t), L.left, L.y.to_px(t), "");
  o += "</g>\n<g class=\"tick-labels\" fill=\"#222222\">\n";
  const std::vector<std::string> xl = tick_labels(L.x_ticks), yl = tick_labels(L.y_ticks);
  for (std::size_t i = 0; i < xl.size(); ++i) {
    text(L.x.to_px(L.x_ticks[i]), L.bottom + 20, " text-anchor=\"middle\"", display_number(xl[i]));
  }
  for (std::size_t i = 0; i < yl.size(); ++i) {
    text(L.left - 8, L.y.to_px(L.y_ticks[i]) + 4, " text-anchor=\"end\"", display_number(yl[i]));
  }
  o += "</g>\n";

  const double cx = 0.5 * (L.left + L.right), cy = 0.5 * (L.top + L.bottom);
  if (!L.has_data) {
    text(cx, cy, " text-anchor=\"middle\" fill=\"#888888\" font-size=\"14\"", "no data");
  }
  if (!spec.x_label.empty()) {
    text(cx, L.bottom + 44,
         " class=\"x-label\" text-anchor=\"middle\" font-size=\"" + fixed(kLabelFont, 0) + "\"",
         xml_escape(spec.x_label));
  }
  if (!spec.y_label.empty()) {
    o += "<text class=\"y-label\" transform=\"translate(" + px(18) + "," + px(cy) +
         ") rotate(-90)\" text-anchor=\"middle\" font-size=\"" + fixed(kLabelFont, 0) + "\">" +
         xml_escape(spec.y_label) + "</text>\n";
  }
  if (!spec.title.empty()) {
    text(0.5 * width, 28,
         " class=\"title\" text-anchor=\"middle\" font-weight=\"bold\" font-size=\"" +
             fixed(kTitleFont, 0) + "\"",
         xml_escape(spec.title));
  }

  // Legend, right of the plot area, one row per labelled series.
  const bool marks_row = !spec.x_marks.empty() && !spec.x_marks_label.empty();
  bool any_label = marks_row;
  for (const Series& s : spec.series) any_label = any_label || !s.label.empty();
  if (any_label) {
    const double x0 = L.right + 12;
    const std::size_t max_chars = legend_chars(width);
    double y = L.top + 4;
    double rows = 0, widest = 0;
    for (const Series& s : spec.series) {
      if (s.label.empty()) continue;
      rows += 1;
      widest = std::max(widest, kLegendCharWidth * legend_text(s.label, max_chars).size());
    }
    if (marks_row) {
      rows += 1;
      widest =
          std::max(widest, kLegendCharWidth * legend_text(spec.x_marks_label, max_chars).size());
    }
    o += "<g class=\"legend\" font-size=\"" + fixed(kLegendFont, 0) + "\">\n";
    o += "<rect x=\"" + px(x0) + "\" y=\"" + px(y) + "\" width=\"" + px(28 + 8 + widest + 14) +
         "\" height=\"" + px(rows * 20 + 8) +
         "\" fill=\"white\" stroke=\"#cccccc\" stroke-width=\"1\"/>\n";
    y += 4;
    for (std::size_t k = 0; k < spec.series.size(); ++k) {
      const Series& s = spec.series[k];
      if (s.label.empty()) continue;
      std::string attrs =
          std::string(" stroke=\"") + kColours[k % kColourCount] + "\" stroke-width=\"2.2\"";
      if (!dashes[k].empty()) attrs += " stroke-dasharray=\"" + dashes[k] + "\"";
      line(x0 + 7, y + 10, x0 + 7 + 26, y + 10, attrs);
      text(x0 + 7 + 26 + 8, y + 14, " class=\"legend-entry\"",
           xml_escape(legend_text(s.label, max_chars)));
      y += 20;
    }
    if (marks_row) {
      line(x0 + 20, y + 2, x0 + 20, y + 18,
           " stroke=\"#888888\" stroke-width=\"1\" stroke-dasharray=\"4 3\"");
      text(x0 + 7 + 26 + 8, y + 14, " class=\"legend-entry\"",
           xml_escape(legend_text(spec.x_marks_label, max_chars)));
    }
    o += "</g>\n";
  }
  o += "</svg>\n";
  return o;
}

}  // namespace

std::string render_svg(const PlotSpec& spec) {
  if (spec.series.size() <= kMostSeriesPerPanel) return render_panel(spec, "plot-area");
  // More series than one axis shows legibly: panels of at most kMostSeriesPerPanel, as equal as
  // can be, stacked one above the other on the same x range, each `spec.height` tall.
  const std::size_t n = spec.series.size();
  const std::size_t panels = (n + kMostSeriesPerPanel - 1) / kMostSeriesPerPanel;
  const std::size_t per = (n + panels - 1) / panels;
  const int width = std::max(spec.width, 200), height = std::max(spec.height, 150);
  const std::string w = std::to_string(width),
                    h = std::to_string(height * static_cast<int>(panels));
  std::string o = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + w + "\" height=\"" + h +
                  "\" viewBox=\"0 0 " + w + " " + h + "\">\n";
  if (!spec.title.empty()) o += "<title>" + xml_escape(spec.title) + "</title>\n";
  for (std::size_t p = 0; p < panels; ++p) {
    PlotSpec part = spec;
    part.series.assign(
        spec.series.begin() + static_cast<std::ptrdiff_t>(p * per),
        spec.series.begin() + static_cast<std::ptrdiff_t>(std::min(n, (p + 1) * per)));
    if (std::isnan(part.x_min) || std::isnan(part.x_max)) {  // one x range for every panel
      const PlotLayout all = compute_layout(spec);
      if (all.has_data) part.x_min = all.x.lo, part.x_max = all.x.hi;
    }
    if (!spec.title.empty())
      part.title =
          spec.title + " (" + std::to_string(p + 1) + " of " + std::to_string(panels) + ")";
    std::string panel = render_panel(part, "plot-area-" + std::to_string(p + 1));
    panel.insert(4, " class=\"panel\" y=\"" + std::to_string(height * static_cast<int>(p)) + "\"");
    o += panel;
  }
  return o + "</svg>\n";
}

}  // namespace mechgen::report
