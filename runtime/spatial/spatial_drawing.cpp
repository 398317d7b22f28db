// Two orthographic views of a spatial model as SVG (spatial_drawing.hpp).
#include "spatial/spatial_drawing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace mechgen::spatial {

namespace {

std::string num(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", v);
  return text;
}

// A view: the world axes drawn to the right (h) and up (v).
struct View {
  const char* id;
  const char* name;
  const char* label;
  int h, v;
};
constexpr View kViews[3] = {{"side", "sagittal", "sagittal (x right, z up)", 0, 2},
                            {"front", "frontal", "frontal (y right, z up)", 1, 2},
                            {"top", "top", "top (x right, y up)", 0, 1}};

// The box around every location of every frame and every traced path.
struct Extent {
  double lo[3], hi[3];
  double span(int k) const { return hi[k] - lo[k]; }
};

Extent extent(const SpatialFrames& f) {
  Extent e;
  std::fill(e.lo, e.lo + 3, std::numeric_limits<double>::infinity());
  std::fill(e.hi, e.hi + 3, -std::numeric_limits<double>::infinity());
  auto extend = [&](const V3& x) {
    for (int k = 0; k < 3; ++k)
      e.lo[k] = std::min(e.lo[k], x[static_cast<size_t>(k)]),
      e.hi[k] = std::max(e.hi[k], x[static_cast<size_t>(k)]);
  };
  for (size_t i = 0; i < f.times.size(); ++i) {
    for (const auto& body : f.bodies[i])
      for (const V3& x : body) extend(x);
    for (const V3& x : f.joints[i]) extend(x);
  }
  for (const auto& path : f.traces)
    for (const V3& x : path) extend(x);
  for (int k = 0; k < 3; ++k)
    if (!(e.hi[k] >= e.lo[k])) e.lo[k] = e.hi[k] = 0;  // nothing drawn
  return e;
}

// Indices into kViews, in their order: the first two whose area is at least 5 % of the largest
// (sagittal and frontal unless one of them is edge-on); one alone for a mechanism in a plane.
std::vector<int> chosen_views(const Extent& e) {
  double area[3], largest = 0;
  for (int i = 0; i < 3; ++i)
    largest = std::max(largest, area[i] = e.span(kViews[i].h) * e.span(kViews[i].v));
  std::vector<int> views;
  for (int i = 0; i < 3 && views.size() < 2; ++i)
    if (area[i] >= 0.05 * largest && (largest > 0 || views.empty())) views.push_back(i);
  return views;
}

// The order in which a body's locations make an outline that does not cross itself: by angle
// about their centroid in the plane of their largest spread, closed back to the first (a trunk's
// hips, shoulders and neck as a polygon, not a zig-zag); collinear ones along their line.
std::vector<size_t> outline(const std::vector<V3>& at) {
  std::vector<size_t> order(at.size());
  std::iota(order.begin(), order.end(), size_t{0});
  if (at.size() < 3) return order;
  V3 c{0, 0, 0};
  for (const V3& x : at) c = c + x;
  c = (1.0 / static_cast<double>(at.size())) * c;
  V3 u{0, 0, 0}, v{0, 0, 0};  // the farthest direction, then the farthest across it
  for (const V3& x : at)
    if (geometry::dot(x - c, x - c) > geometry::dot(u, u)) u = x - c;
  const double farthest = geometry::dot(u, u);
  if (farthest < 1e-24) return order;
  u = (1.0 / std::sqrt(farthest)) * u;
  for (const V3& x : at) {
    const V3 w = (x - c) - geometry::dot(x - c, u) * u;
    if (geometry::dot(w, w) > geometry::dot(v, v)) v = w;
  }
  auto along = [&](size_t k) { return geometry::dot(at[k] - c, u); };
  if (geometry::dot(v, v) < 1e-12 * farthest) {
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return along(a) < along(b); });
    return order;
  }
  v = (1.0 / std::sqrt(geometry::dot(v, v))) * v;
  auto angle = [&](size_t k) { return std::atan2(geometry::dot(at[k] - c, v), along(k)); };
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return angle(a) < angle(b); });
  order.push_back(order.front());
  return order;
}

}  // namespace

SpatialFrames spatial_frames(const SpatialSolver& solver, const std::vector<double>& times,
                             const std::vector<std::string>& trace) {
  const SpatialModel& m = solver.model();
  const SpatialInstance& in = solver.instance();
  SpatialFrames f;
  f.times = times;
  f.trace_names = trace;
  f.traces.resize(trace.size());
  std::vector<std::pair<int, V3>> traced;  // (body, body-frame position)
  for (const std::string& name : trace) {
    const auto points = m.named_points();
    const auto at = std::find_if(points.begin(), points.end(),
                                 [&](const auto& point) { return point.first == name; });
    if (at == points.end()) {
      std::string known;
      for (const auto& point : points) known += (known.empty() ? "" : ", ") + point.first;
      throw std::invalid_argument("model '" + m.common.name + "' has no point '" + name +
                                  "' (points: " + (known.empty() ? "none" : known) + ")");
    }
    const std::vector<SpatialPoint>& own = m.bodies[static_cast<size_t>(at->second)].points;
    const auto k = std::find_if(own.begin(), own.end(),
                                [&](const SpatialPoint& p) { return p.name == name; }) -
                   own.begin();
    traced.emplace_back(at->second,
                        in.points[static_cast<size_t>(at->second)][static_cast<size_t>(k)]);
  }
  std::vector<int> drawn;
  for (size_t b = 0; b < m.bodies.size(); ++b) {
    if (m.bodies[b].is_virtual) continue;
    size_t count = m.bodies[b].points.size();
    for (const SpatialJoint& j : m.joints)
      if (!j.is_virtual && (j.first == static_cast<int>(b) || j.second == static_cast<int>(b)))
        ++count;
    if (count < 2 || m.bodies[b].ground) continue;
    drawn.push_back(static_cast<int>(b));
    f.body_names.push_back(m.bodies[b].name);
  }
  SpatialState s;
  std::vector<std::vector<size_t>> order;  // per drawn body: its locations in outline order
  for (const double t : times) {
    solver.solve(t, s);
    std::vector<V3> joints;
    for (size_t j = 0; j < m.joints.size(); ++j)
      if (!m.joints[j].is_virtual)
        joints.push_back(
            geometry::apply(s.D[static_cast<size_t>(m.joints[j].second)], in.joint_point[j]));
    std::vector<std::vector<V3>> bodies;
    for (const int b : drawn) {
      std::vector<V3> at;
      size_t real = 0;
      for (const SpatialJoint& j : m.joints) {
        if (j.is_virtual) continue;
        if (j.first == b || j.second == b) at.push_back(joints[real]);
        ++real;
      }
      for (const V3& local : in.points[static_cast<size_t>(b)]) {
        const V3 x = solver.point_position(s, b, local);
        bool seen = false;  // a point at a joint is drawn once
        for (const V3& y : at) seen = seen || geometry::dot(x - y, x - y) < 1e-20;
        if (!seen) at.push_back(x);
      }
      bodies.push_back(at);
    }
    if (f.bodies.empty())  // each body's outline, from the first frame
      for (const auto& at : bodies) order.push_back(outline(at));
    for (size_t k = 0; k < bodies.size(); ++k) {
      std::vector<V3> ordered;
      for (const size_t i : order[k]) ordered.push_back(bodies[k][i]);
      bodies[k] = ordered;
    }
    f.bodies.push_back(bodies);
    f.joints.push_back(joints);
    for (size_t k = 0; k < traced.size(); ++k)
      f.traces[k].push_back(solver.point_position(s, traced[k].first, traced[k].second));
  }
  return f;
}

std::vector<std::string> spatial_views(const SpatialFrames& frames) {
  std::vector<std::string> ids;
  for (const int i : chosen_views(extent(frames))) ids.push_back(kViews[i].id);
  return ids;
}

std::string draw_spatial(const SpatialFrames& f, const SpatialDrawingOptions& options) {
  Extent e = extent(f);
  const std::vector<int> chosen = chosen_views(e);
  // Every axis spans at least a tenth of the largest (0.1 m when nothing moves), centred: an
  // edge-on direction gets a readable canvas, not a sliver.
  const double largest = std::max({e.span(0), e.span(1), e.span(2)});
  for (int k = 0; k < 3; ++k) {
    const double least = largest > 0 ? 0.1 * largest : 0.1, middle = 0.5 * (e.lo[k] + e.hi[k]);
    if (e.span(k) < least) e.lo[k] = middle - 0.5 * least, e.hi[k] = middle + 0.5 * least;
  }
  // One scale for every view: the widths side by side fill the width, the tallest at most 600 px.
  const double margin = 30, gap = 40, title = options.title.empty() ? 0 : 24;
  double across = 0, tallest = 0;
  for (const int i : chosen)
    across += e.span(kViews[i].h), tallest = std::max(tallest, e.span(kViews[i].v));
  const double room = options.width - 2 * margin - gap * static_cast<double>(chosen.size() - 1);
  const double s = std::min(room / across, 600 / tallest);
  std::vector<double> offset;  // pixels: each view's left edge
  double right = margin;
  for (const int i : chosen)  // at least as wide as its label (about 7 px a character)
    offset.push_back(right),
        right += std::max(e.span(kViews[i].h) * s, 7.0 * std::strlen(kViews[i].label)) + gap;
  // The views left out, said under the drawing.
  std::string left_out;
  for (int i = 0; i < 3; ++i)
    if (std::find(chosen.begin(), chosen.end(), i) == chosen.end() && i < 2)
      left_out += std::string(left_out.empty() ? "" : " and ") + kViews[i].name;
  const std::string note =
      left_out.empty() ? ""
                       : left_out + " view left out: the mechanism is edge-on there (views " +
                             "chosen from its extent)";
  const double top = margin + title + 20;
  double longest_name = 0;  // labels stand right of their body: room for the last view's
  if (options.labels)
    for (const std::string& name : f.body_names)
      longest_name = std::max(longest_name, 7.0 * static_cast<double>(name.size()));
  const double width = std::max({right - gap + margin + longest_name,
                                 2 * margin + 7.0 * static_cast<double>(note.size()),
                                 2 * margin + 9.0 * static_cast<double>(options.title.size())});
  const double height = top + tallest * s + margin + (note.empty() ? 0 : 20);

  auto px = [&](size_t view, const V3& x) {
    const int h = kViews[chosen[view]].h;
    return offset[view] + (x[static_cast<size_t>(h)] - e.lo[h]) * s;
  };
  auto py = [&](size_t view, const V3& x) {
    const int v = kViews[chosen[view]].v;
    return top + (e.hi[v] - x[static_cast<size_t>(v)]) * s;
  };
  auto polyline = [&](size_t view, const std::vector<V3>& at) {
    std::string p;
    for (const V3& x : at) p += (p.empty() ? "" : " ") + num(px(view, x)) + "," + num(py(view, x));
    return p;
  };
  const bool animate = f.times.size() > 1;
  const std::string timing = "\" dur=\"" +
                             num(animate ? std::max(1e-3, f.times.back() - f.times.front()) : 0) +
                             "s\" repeatCount=\"indefinite\" values=\"";
  // A circle at path[0], moving through path (one position a frame) in an animation.
  auto moving_circle = [&](size_t view, const std::vector<V3>& path, const std::string& attrs) {
    std::string c = "<circle " + attrs + " cx=\"" + num(px(view, path[0])) + "\" cy=\"" +
                    num(py(view, path[0])) + "\">";
    if (animate) {
      std::string cx, cy;
      for (size_t i = 0; i < path.size(); ++i) {
        cx += (i ? ";" : "") + num(px(view, path[i]));
        cy += (i ? ";" : "") + num(py(view, path[i]));
      }
      c += "<animate attributeName=\"cx" + timing + cx + "\"/><animate attributeName=\"cy" +
           timing + cy + "\"/>";
    }
    return c + "</circle>\n";
  };
  const std::string w = num(width), h = num(height);
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + w + "\" height=\"" + h +
                    "\" viewBox=\"0 0 " + w + " " + h +
                    "\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  if (!options.title.empty())
    svg += "<text x=\"" + num(margin) + "\" y=\"" + num(margin) +
           "\" font-family=\"sans-serif\" font-size=\"16\">" + options.title + "</text>\n";
  if (!note.empty())
    svg += "<text class=\"views\" x=\"" + num(margin) + "\" y=\"" + num(height - margin + 10) +
           "\" font-family=\"sans-serif\" font-size=\"12\" fill=\"#555\">" + note + "</text>\n";
  for (size_t view = 0; view < chosen.size(); ++view) {
    const std::string id = kViews[chosen[view]].id;
    svg += "<text x=\"" + num(offset[view]) + "\" y=\"" + num(margin + title + 8) +
           "\" font-family=\"sans-serif\" font-size=\"12\" fill=\"#555\">" +
           kViews[chosen[view]].label + "</text>\n";
    for (size_t t = 0; t < f.traces.size(); ++t)
      svg += "<polyline id=\"" + id + "-trace-" + f.trace_names[t] +
             "\" class=\"trace\" fill=\"none\" stroke=\"#7f8c8d\" stroke-width=\"1.5\" "
             "stroke-dasharray=\"5 3\" points=\"" +
             polyline(view, f.traces[t]) + "\"/>\n";
    for (size_t b = 0; b < f.body_names.size(); ++b) {
      svg += "<polyline id=\"" + id + "-" + f.body_names[b] +
             "\" class=\"body\" fill=\"none\" stroke=\"#1f5fa8\" stroke-width=\"3\" "
             "stroke-linejoin=\"round\" points=\"" +
             polyline(view, f.bodies[0][b]) + "\">";
      if (animate) {
        std::string values;
        for (size_t i = 0; i < f.times.size(); ++i)
          values += (i ? ";" : "") + polyline(view, f.bodies[i][b]);
        svg += "<animate attributeName=\"points" + timing + values + "\"/>";
      }
      svg += "</polyline>\n";
    }
    for (size_t j = 0; j < f.joints[0].size(); ++j) {
      std::vector<V3> path;
      for (const auto& joints : f.joints) path.push_back(joints[j]);
      svg += moving_circle(view, path,
                           "class=\"joint\" r=\"4\" fill=\"white\" stroke=\"#c0392b\" "
                           "stroke-width=\"2\"");
    }
    // A dot along each traced path that has a position a frame (the animation's own times).
    for (size_t t = 0; t < f.traces.size(); ++t)
      if (animate && f.traces[t].size() == f.times.size())
        svg += moving_circle(view, f.traces[t],
                             "id=\"" + id + "-tracer-" + f.trace_names[t] +
                                 "\" class=\"tracer\" r=\"3\" fill=\"#7f8c8d\"");
    if (options.labels)
      for (size_t b = 0; b < f.body_names.size(); ++b) {
        const std::vector<V3>& at = f.bodies[0][b];
        const size_t n = at.size() > 2 && at.front() == at.back() ? at.size() - 1 : at.size();
        V3 mean{0, 0, 0};
        for (size_t k = 0; k < n; ++k) mean = mean + at[k];
        mean = (1.0 / static_cast<double>(n)) * mean;
        svg += "<text class=\"label\" x=\"" + num(px(view, mean) + 6) + "\" y=\"" +
               num(py(view, mean) - 6) +
               "\" font-family=\"sans-serif\" font-size=\"11\" fill=\"#333\">" + f.body_names[b] +
               "</text>\n";
      }
  }
  return svg + "</svg>\n";
}

}  // namespace mechgen::spatial
