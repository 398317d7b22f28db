#include "report/mechanism_drawing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "report/svg_plot.hpp"

namespace mechgen::report {

namespace {

std::string num(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", value);
  return text;
}

// "x,y x,y ..." of some points in pixels.
std::string point_list(const DrawingView& view, const std::vector<PointXY>& at,
                       const std::vector<int>& indices) {
  std::string text;
  for (int i : indices) {
    const PointXY& p = at[static_cast<size_t>(i)];
    text += (text.empty() ? "" : " ") + num(view.px(p.x)) + "," + num(view.py(p.y));
  }
  return text;
}

// One looping SMIL animation of an attribute, or nothing for a still.
std::string animate(const std::string& attribute, const std::vector<std::string>& values,
                    double duration) {
  if (values.size() < 2) return "";
  std::string text = "<animate attributeName=\"" + attribute + "\" dur=\"" + num(duration) +
                     "s\" repeatCount=\"indefinite\" values=\"";
  for (size_t i = 0; i < values.size(); ++i) text += (i ? ";" : "") + values[i];
  return text + "\"/>";
}

bool ends_with(const std::string& text, const std::string& suffix) {
  return !suffix.empty() && text.size() > suffix.size() && text.ends_with(suffix);
}

}  // namespace

MechanismFrames frames_from_table(const Model& model, const std::vector<std::string>& columns,
                                  const std::vector<std::vector<double>>& rows) {
  auto index = [&](const std::string& name) {
    const auto it = std::find(columns.begin(), columns.end(), name);
    if (it == columns.end()) throw std::runtime_error("no column '" + name + "' to draw from");
    return static_cast<size_t>(it - columns.begin());
  };
  const size_t t = index("t");
  std::vector<std::pair<size_t, size_t>> xy;
  for (const auto& [name, body] : model.named_points())
    xy.emplace_back(index(name + ".x"), index(name + ".y"));
  MechanismFrames frames;
  for (const std::vector<double>& row : rows) {
    frames.times.push_back(row.at(t));
    std::vector<PointXY> at;
    for (const auto& [x, y] : xy) at.push_back({row.at(x), row.at(y)});
    frames.points.push_back(std::move(at));
  }
  return frames;
}

DrawingView fit_view(const MechanismFrames& frames, int width) {
  double x_min = std::numeric_limits<double>::infinity(), x_max = -x_min;
  double y_min = x_min, y_max = -x_min;
  for (const std::vector<PointXY>& at : frames.points)
    for (const PointXY& p : at) {
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
      x_min = std::min(x_min, p.x);
      x_max = std::max(x_max, p.x);
      y_min = std::min(y_min, p.y);
      y_max = std::max(y_max, p.y);
    }
  if (!(x_min <= x_max)) x_min = x_max = y_min = y_max = 0;  // nothing finite: an empty view
  DrawingView view;
  view.margin = 40;
  view.width = std::max(width, 100);
  const double span = std::max({x_max - x_min, y_max - y_min, 1e-9});
  view.scale = (view.width - 2 * view.margin) / std::max(x_max - x_min, span * 0.25);
  view.x_min = x_min;
  view.y_max = y_max;
  view.height = static_cast<int>(std::ceil((y_max - y_min) * view.scale + 2 * view.margin));
  return view;
}

std::vector<BodyShape> body_shapes(const Model& model, const std::vector<PointXY>& at) {
  const auto names = model.named_points();
  std::vector<BodyShape> shapes;
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    BodyShape shape;
    shape.body = static_cast<int>(b);
    for (const BodyPoint& p : model.bodies[b].points)
      for (size_t i = 0; i < names.size(); ++i)
        if (names[i].first == p.name) shape.points.push_back(static_cast<int>(i));
    if (shape.points.size() < 2) continue;
    // The two points farthest apart span the body; the others lie on that line (a bar, drawn
    // through them in order along it) or off it (a plate, drawn as the polygon of its points in
    // the order of their angle about the centroid).
    auto p = [&](int i) { return at[static_cast<size_t>(i)]; };
    int a = shape.points[0], c = shape.points[1];
    double longest = -1;
    for (int i : shape.points)
      for (int j : shape.points)
        if (const double d = std::hypot(p(i).x - p(j).x, p(i).y - p(j).y); d > longest) {
          longest = d;
          a = i;
          c = j;
        }
    const double ux = (p(c).x - p(a).x) / std::max(longest, 1e-300);
    const double uy = (p(c).y - p(a).y) / std::max(longest, 1e-300);
    double off_line = 0;
    for (int i : shape.points)
      off_line = std::max(off_line, std::abs((p(i).x - p(a).x) * uy - (p(i).y - p(a).y) * ux));
    shape.polygon = shape.points.size() >= 3 && off_line > 1e-6 * longest;
    if (shape.polygon) {
      double cx = 0, cy = 0;
      for (int i : shape.points) {
        cx += p(i).x / static_cast<double>(shape.points.size());
        cy += p(i).y / static_cast<double>(shape.points.size());
      }
      std::sort(shape.points.begin(), shape.points.end(), [&](int i, int j) {
        return std::atan2(p(i).y - cy, p(i).x - cx) < std::atan2(p(j).y - cy, p(j).x - cx);
      });
    } else {
      std::sort(shape.points.begin(), shape.points.end(), [&](int i, int j) {
        return (p(i).x - p(a).x) * ux + (p(i).y - p(a).y) * uy <
               (p(j).x - p(a).x) * ux + (p(j).y - p(a).y) * uy;
      });
    }
    shapes.push_back(std::move(shape));
  }
  return shapes;
}

std::string draw_mechanism(const Model& model, const MechanismFrames& all,
                           const DrawingOptions& options) {
  if (all.points.empty()) throw std::runtime_error("nothing to draw: no frames");
  // An animation plays evenly spaced frames (SMIL spaces its values evenly in time).
  MechanismFrames frames;
  const size_t count =
      std::min(all.points.size(), static_cast<size_t>(std::max(2, options.max_frames)));
  const double t0 = all.times.front(), t1 = all.times.back();
  for (size_t k = 0; k < count; ++k) {
    const double t = count == 1 ? t0 : t0 + (t1 - t0) * static_cast<double>(k) / (count - 1);
    const auto it = std::lower_bound(all.times.begin(), all.times.end(), t);
    size_t i = static_cast<size_t>(it - all.times.begin());
    if (i >= all.times.size() || (i > 0 && t - all.times[i - 1] < all.times[i] - t)) --i;
    frames.times.push_back(t);
    frames.points.push_back(all.points[i]);
  }
  const double duration = t1 > t0 ? t1 - t0 : 1.0;
  const auto names = model.named_points();
  // Traced points: their indices, and the frames their paths run over (also fitted in the view).
  std::vector<size_t> traced;
  for (const std::string& name : options.trace) {
    size_t i = 0;
    while (i < names.size() && names[i].first != name) ++i;
    if (i == names.size()) {
      std::string known;
      for (const auto& n : names) known += (known.empty() ? "" : ", ") + n.first;
      throw std::runtime_error("--trace: model '" + model.name + "' has no point '" + name +
                               "' (points: " + known + ")");
    }
    traced.push_back(i);
  }
  const MechanismFrames& path = options.trace_path.points.empty() ? all : options.trace_path;
  MechanismFrames fitted = frames;
  if (!traced.empty())
    fitted.points.insert(fitted.points.end(), path.points.begin(), path.points.end());
  const DrawingView view = fit_view(fitted, options.width);
  const std::vector<PointXY>& first = frames.points.front();

  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
                    std::to_string(view.width) + "\" height=\"" + std::to_string(view.height) +
                    "\" viewBox=\"0 0 " + std::to_string(view.width) + " " +
                    std::to_string(view.height) + "\">\n";
  svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  if (!options.title.empty())
    svg += "<text x=\"" + num(view.margin) + "\" y=\"22\" font-family=\"sans-serif\" " +
           "font-size=\"15\">" + xml_escape(options.title) + "</text>\n";

  // The floor under the ground body, hatched below, across the whole drawing.
  const Body& ground = model.bodies[static_cast<size_t>(model.ground)];
  double floor_y = std::numeric_limits<double>::infinity();
  for (const BodyPoint& p : ground.points)
    for (size_t i = 0; i < names.size(); ++i)
      if (names[i].first == p.name) floor_y = std::min(floor_y, first[i].y);
  // A floor when nothing goes below the ground body (a foot standing on it: a walker); else the
  // ground body is a frame with the mechanism around it, hatched under each of its points only.
  bool on_floor = std::isfinite(floor_y);
  const double tolerance = 1.0 / view.scale;  // a pixel: PASIBOT's flying foot grazes 0.03 mm
  for (const std::vector<PointXY>& at : frames.points)
    for (const PointXY& p : at) on_floor = on_floor && !(p.y < floor_y - tolerance);
  auto hatch = [&](double x0, double x1, double y) {
    std::string text = "<line x1=\"" + num(x0) + "\" y1=\"" + num(y) + "\" x2=\"" + num(x1) +
                       "\" y2=\"" + num(y) + "\" stroke-width=\"2\"/>\n";
    for (double x = x0 + 10; x < x1 + 1; x += 12)
      text += "<line x1=\"" + num(x) + "\" y1=\"" + num(y) + "\" x2=\"" + num(x - 8) + "\" y2=\"" +
              num(y + 8) + "\"/>\n";
    return text;
  };
  svg += "<g id=\"ground\" stroke=\"#555\" stroke-width=\"1\">\n";
  if (on_floor) {
    svg += hatch(4.0, view.width - 4.0, view.py(floor_y));
  } else {
    for (const BodyPoint& p : ground.points)
      for (size_t i = 0; i < names.size(); ++i)
        if (names[i].first == p.name)
          svg += hatch(view.px(first[i].x) - 14, view.px(first[i].x) + 14, view.py(first[i].y) + 4);
  }
  svg += "</g>\n";

  // Paths of the traced points, under the bodies.
  for (size_t i : traced) {
    std::string line;
    for (const std::vector<PointXY>& at : path.points)
      line += (line.empty() ? "" : " ") + num(view.px(at[i].x)) + "," + num(view.py(at[i].y));
    svg += "<polyline id=\"trace-" + names[i].first + "\" class=\"trace\" points=\"" + line +
           "\" fill=\"none\" stroke=\"#2ca02c\" stroke-width=\"1.5\" stroke-dasharray=\"5 3\"/>\n";
  }

  // Bodies: the hip-like plates first (underneath), then the bars.
  std::vector<BodyShape> shapes = body_shapes(model, first);
  std::stable_sort(shapes.begin(), shapes.end(),
                   [](const BodyShape& a, const BodyShape& b) { return a.polygon > b.polygon; });
  for (const BodyShape& shape : shapes) {
    const Body& body = model.bodies[static_cast<size_t>(shape.body)];
    const bool mirrored = ends_with(body.name, options.mirror_suffix);
    // Feet (the ground body and its mirror, the other foot of a walker) are drawn thick, in
    // their leg's colour: while walking, either may be the one on the floor.
    const bool foot = body.ground || (!options.mirror_suffix.empty() &&
                                      body.name == ground.name + options.mirror_suffix);
    const std::string colour = mirrored ? "#1f77b4" : "#d95f02";
    std::vector<std::string> values;
    for (const std::vector<PointXY>& at : frames.points)
      values.push_back(point_list(view, at, shape.points));
    svg += std::string("<") + (shape.polygon ? "polygon" : "polyline") + " id=\"body-" + body.name +
           "\" class=\"body\" points=\"" + values.front() + "\" stroke=\"" + colour +
           "\" stroke-width=\"" + (foot ? "5" : "3") +
           "\" stroke-linejoin=\"round\" stroke-linecap=\"round\" fill=\"" +
           (shape.polygon ? "#ccc\" fill-opacity=\"0.6" : "none") + "\">" +
           animate("points", values, duration) + "</" + (shape.polygon ? "polygon" : "polyline") +
           ">\n";
  }

  // Joints: one circle per joint location.
  std::vector<std::string> drawn;
  for (const Joint& joint : model.joints) {
    if (std::find(drawn.begin(), drawn.end(), joint.point) != drawn.end()) continue;
    drawn.push_back(joint.point);
    size_t i = 0;
    while (i < names.size() && names[i].first != joint.point) ++i;
    if (i == names.size()) continue;
    std::vector<std::string> xs, ys;
    for (const std::vector<PointXY>& at : frames.points) {
      xs.push_back(num(view.px(at[i].x)));
      ys.push_back(num(view.py(at[i].y)));
    }
    svg += "<circle id=\"joint-" + joint.point + "\" class=\"joint\" cx=\"" + xs.front() +
           "\" cy=\"" + ys.front() + "\" r=\"3.5\" fill=\"white\" stroke=\"black\" " +
           "stroke-width=\"1.2\">" + animate("cx", xs, duration) + animate("cy", ys, duration) +
           "</circle>\n";
  }

  // A dot on each traced point (it follows the point along its path on an animation).
  for (size_t i : traced) {
    std::vector<std::string> xs, ys;
    for (const std::vector<PointXY>& at : frames.points) {
      xs.push_back(num(view.px(at[i].x)));
      ys.push_back(num(view.py(at[i].y)));
    }
    svg += "<circle id=\"tracer-" + names[i].first + "\" class=\"tracer\" cx=\"" + xs.front() +
           "\" cy=\"" + ys.front() + "\" r=\"3\" fill=\"#2ca02c\">" + animate("cx", xs, duration) +
           animate("cy", ys, duration) + "</circle>\n";
    if (options.labels)
      svg += "<text class=\"label\" x=\"" + num(view.px(first[i].x) + 5) + "\" y=\"" +
             num(view.py(first[i].y) + 12) +
             "\" font-family=\"sans-serif\" font-size=\"11\" fill=\"#2ca02c\">" +
             xml_escape(names[i].first) + "</text>\n";
  }

  if (options.labels)
    for (const BodyShape& shape : shapes) {
      std::vector<std::string> xs, ys;
      for (const std::vector<PointXY>& at : frames.points) {
        double cx = 0, cy = 0;
        for (int i : shape.points) {
          cx += at[static_cast<size_t>(i)].x / static_cast<double>(shape.points.size());
          cy += at[static_cast<size_t>(i)].y / static_cast<double>(shape.points.size());
        }
        xs.push_back(num(view.px(cx) + 4));
        ys.push_back(num(view.py(cy) - 4));
      }
      svg += "<text class=\"label\" x=\"" + xs.front() + "\" y=\"" + ys.front() +
             "\" font-family=\"sans-serif\" font-size=\"11\" fill=\"#222\">" +
             xml_escape(model.bodies[static_cast<size_t>(shape.body)].name) +
             animate("x", xs, duration) + animate("y", ys, duration) + "</text>\n";
    }
  return svg + "</svg>\n";
}

}  // namespace mechgen::report
