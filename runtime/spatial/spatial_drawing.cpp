// Two orthographic views of a spatial model as SVG (spatial_drawing.hpp).
#include "spatial/spatial_drawing.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>

namespace mechgen::spatial {

namespace {

std::string num(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", v);
  return text;
}

// A view: which world axis is horizontal (0 = x, 1 = y); z is always vertical.
struct View {
  const char* id;
  const char* label;
  int horizontal;
  double offset;  // pixels: the view's left edge
};

}  // namespace

SpatialFrames spatial_frames(const SpatialSolver& solver, const std::vector<double>& times) {
  const SpatialModel& m = solver.model();
  const SpatialInstance& in = solver.instance();
  SpatialFrames f;
  f.times = times;
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
    f.bodies.push_back(bodies);
    f.joints.push_back(joints);
  }
  return f;
}

std::string draw_spatial(const SpatialFrames& f, const SpatialDrawingOptions& options) {
  // One scale for both views, fitted to every location of every frame.
  double lo[3], hi[3];
  std::fill(lo, lo + 3, std::numeric_limits<double>::infinity());
  std::fill(hi, hi + 3, -std::numeric_limits<double>::infinity());
  auto extend = [&](const V3& x) {
    for (int k = 0; k < 3; ++k)
      lo[k] = std::min(lo[k], x[static_cast<size_t>(k)]),
      hi[k] = std::max(hi[k], x[static_cast<size_t>(k)]);
  };
  for (size_t i = 0; i < f.times.size(); ++i) {
    for (const auto& body : f.bodies[i])
      for (const V3& x : body) extend(x);
    for (const V3& x : f.joints[i]) extend(x);
  }
  for (int k = 0; k < 3; ++k)
    if (!(hi[k] - lo[k] > 1e-9)) lo[k] -= 0.05, hi[k] += 0.05;
  const double margin = 30, gap = 40, title = options.title.empty() ? 0 : 24;
  const double span = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  const double scale = (options.width - 2 * margin - gap) / (hi[0] - lo[0] + hi[1] - lo[1]);
  const double s = std::min(scale, 600 / span);
  const double view_w0 = (hi[0] - lo[0]) * s, view_w1 = (hi[1] - lo[1]) * s;
  const double height = 2 * margin + title + 20 + (hi[2] - lo[2]) * s;
  const View views[2] = {{"side", "sagittal (x right, z up)", 0, margin},
                         {"front", "frontal (y right, z up)", 1, margin + view_w0 + gap}};
  auto px = [&](const View& v, const V3& x) {
    return v.offset + (x[static_cast<size_t>(v.horizontal)] - lo[v.horizontal]) * s;
  };
  auto py = [&](const V3& x) { return margin + title + 20 + (hi[2] - x[2]) * s; };
  auto polyline = [&](const View& v, const std::vector<V3>& at) {
    std::string p;
    for (const V3& x : at) p += (p.empty() ? "" : " ") + num(px(v, x)) + "," + num(py(x));
    return p;
  };
  const bool animate = f.times.size() > 1;
  const double duration = animate ? std::max(1e-3, f.times.back() - f.times.front()) : 0;
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
                    num(2 * margin + gap + view_w0 + view_w1) + "\" height=\"" + num(height) +
                    "\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  if (!options.title.empty())
    svg += "<text x=\"" + num(margin) + "\" y=\"" + num(margin) +
           "\" font-family=\"sans-serif\" font-size=\"16\">" + options.title + "</text>\n";
  for (const View& v : views) {
    svg += "<text x=\"" + num(v.offset) + "\" y=\"" + num(margin + title + 8) +
           "\" font-family=\"sans-serif\" font-size=\"12\" fill=\"#555\">" + v.label + "</text>\n";
    for (size_t b = 0; b < f.body_names.size(); ++b) {
      svg += "<polyline id=\"" + std::string(v.id) + "-" + f.body_names[b] +
             "\" class=\"body\" fill=\"none\" stroke=\"#1f5fa8\" stroke-width=\"3\" "
             "stroke-linejoin=\"round\" points=\"" +
             polyline(v, f.bodies[0][b]) + "\">";
      if (animate) {
        std::string values;
        for (size_t i = 0; i < f.times.size(); ++i)
          values += (i ? ";" : "") + polyline(v, f.bodies[i][b]);
        svg += "<animate attributeName=\"points\" dur=\"" + num(duration) +
               "s\" repeatCount=\"indefinite\" values=\"" + values + "\"/>";
      }
      svg += "</polyline>\n";
    }
    for (size_t j = 0; j < f.joints[0].size(); ++j) {
      svg +=
          "<circle class=\"joint\" r=\"4\" fill=\"white\" stroke=\"#c0392b\" stroke-width=\"2\" "
          "cx=\"" +
          num(px(v, f.joints[0][j])) + "\" cy=\"" + num(py(f.joints[0][j])) + "\">";
      if (animate) {
        std::string cx, cy;
        for (size_t i = 0; i < f.times.size(); ++i) {
          cx += (i ? ";" : "") + num(px(v, f.joints[i][j]));
          cy += (i ? ";" : "") + num(py(f.joints[i][j]));
        }
        for (const auto& [attribute, values] : {std::pair{"cx", cx}, std::pair{"cy", cy}})
          svg += std::string("<animate attributeName=\"") + attribute + "\" dur=\"" +
                 num(duration) + "s\" repeatCount=\"indefinite\" values=\"" + values + "\"/>";
      }
      svg += "</circle>\n";
    }
  }
  return svg + "</svg>\n";
}

}  // namespace mechgen::spatial
