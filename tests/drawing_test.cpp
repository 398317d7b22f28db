// Mechanism drawings (runtime/report/mechanism_drawing.hpp): one element per body, drawn at the
// numeric reference solver's coordinates; joints at the joint points; an animation whose first
// frame is the still and whose frames are the sweep's.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <sstream>

#include "report/mechanism_drawing.hpp"
#include "sweep/sweep.hpp"

namespace {

using mechgen::Model;
namespace report = mechgen::report;

const Model& pasibot() {
  static const Model model = mechgen::read_model(MECHGEN_SOURCE_DIR "/models/pasibot.yaml");
  return model;
}

mechgen::SweepResult numeric_sweep(int samples) {
  mechgen::SweepOptions options = mechgen::default_sweep(pasibot());
  options.solver = "numeric";
  options.samples = samples;
  return mechgen::run_sweep(pasibot(), options);
}

// The value of attribute `name` in the element with id `id` (its opening tag).
std::string attribute(const std::string& svg, const std::string& id, const std::string& name) {
  const size_t at = svg.find("id=\"" + id + "\"");
  if (at == std::string::npos) return "";
  const size_t end = svg.find('>', at);
  const size_t a = svg.find(" " + name + "=\"", at);
  if (a == std::string::npos || a > end) return "";
  const size_t from = a + name.size() + 3;
  return svg.substr(from, svg.find('"', from) - from);
}

std::vector<double> numbers(const std::string& text) {
  std::vector<double> values;
  std::string cleaned = text;
  for (char& c : cleaned)
    if (c == ',') c = ' ';
  std::istringstream in(cleaned);
  for (double v; in >> v;) values.push_back(v);
  return values;
}

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(MechanismDrawing, EveryBodyOnceAtTheSolversCoordinates) {
  const mechgen::SweepResult sweep = numeric_sweep(61);
  const auto& row = sweep.rows[37];  // somewhere inside the step
  const report::MechanismFrames frames = report::frames_from_table(pasibot(), sweep.columns, {row});
  const std::string svg = report::draw_mechanism(pasibot(), frames, {});
  const report::DrawingView view = report::fit_view(frames, 900);
  EXPECT_EQ(count(svg, "class=\"body\""), pasibot().bodies.size());  // 24, the ground included
  EXPECT_EQ(count(svg, "<animate"), 0u);                             // a still
  auto column = [&](const std::string& name) {
    return row[static_cast<size_t>(std::find(sweep.columns.begin(), sweep.columns.end(), name) -
                                   sweep.columns.begin())];
  };
  for (const mechgen::Body& body : pasibot().bodies) {
    SCOPED_TRACE(body.name);
    EXPECT_EQ(count(svg, "id=\"body-" + body.name + "\""), 1u);
    const std::vector<double> xy = numbers(attribute(svg, "body-" + body.name, "points"));
    ASSERT_EQ(xy.size(), 2 * body.points.size());
    // Every drawn vertex is one of the body's points at the solver's position, and every point
    // of the body is drawn.
    for (const mechgen::BodyPoint& p : body.points) {
      const double px = view.px(column(p.name + ".x")), py = view.py(column(p.name + ".y"));
      bool found = false;
      for (size_t i = 0; i + 1 < xy.size(); i += 2)
        found = found || (std::abs(xy[i] - px) < 1e-3 && std::abs(xy[i + 1] - py) < 1e-3);
      EXPECT_TRUE(found) << p.name << " at " << px << "," << py;
    }
  }
  // The bars are drawn through their points in order: the coupler l7 as C, M, P (or reversed).
  const std::vector<double> l7 = numbers(attribute(svg, "body-l7", "points"));
  EXPECT_NEAR(l7[2], view.px(column("M.x")), 1e-3);
  // The hip plate (A, B, D not on one line) is a polygon; the joints are circles at their points.
  EXPECT_NE(svg.find("<polygon id=\"body-l13\""), std::string::npos);
  EXPECT_NEAR(std::stod(attribute(svg, "joint-K", "cx")), view.px(column("K.x")), 1e-3);
  EXPECT_NEAR(std::stod(attribute(svg, "joint-K", "cy")), view.py(column("K.y")), 1e-3);
  EXPECT_NE(svg.find("id=\"ground\""), std::string::npos);
}

TEST(MechanismDrawing, AnimationStartsAtTheStillAndPlaysTheSweepsFrames) {
  const mechgen::SweepResult sweep = numeric_sweep(31);
  const report::MechanismFrames frames =
      report::frames_from_table(pasibot(), sweep.columns, sweep.rows);
  report::DrawingOptions options;
  options.labels = true;
  const std::string svg = report::draw_mechanism(pasibot(), frames, options);
  const report::DrawingView view = report::fit_view(frames, options.width);
  // The static attribute is the first frame; the animation's values are all 31 frames.
  const size_t tag = svg.find("id=\"body-l2\"");
  const size_t values_at = svg.find("values=\"", tag) + 8;
  const std::string values = svg.substr(values_at, svg.find('"', values_at) - values_at);
  EXPECT_EQ(count(values, ";") + 1, 31u);
  EXPECT_EQ(values.substr(0, values.find(';')), attribute(svg, "body-l2", "points"));
  // The last frame holds the tibia's end E where the solver has it at the end of the step.
  const std::vector<double> last = numbers(values.substr(values.rfind(';') + 1));
  const auto& end = sweep.rows.back();
  auto column = [&](const std::string& name) {
    return end[static_cast<size_t>(std::find(sweep.columns.begin(), sweep.columns.end(), name) -
                                   sweep.columns.begin())];
  };
  bool found = false;
  for (size_t i = 0; i + 1 < last.size(); i += 2)
    found = found ||
            (std::abs(last[i] - view.px(column("Jp.x"))) < 1e-3 &&
             std::abs(last[i + 1] - view.py(column("Jp.y"))) < 1e-3) ||
            (std::abs(last[i] - view.px(column("J.x"))) < 1e-3 &&
             std::abs(last[i + 1] - view.py(column("J.y"))) < 1e-3);
  EXPECT_TRUE(found);
  // Duration: the step's time, real time.
  const size_t dur = svg.find("dur=\"");
  ASSERT_NE(dur, std::string::npos);
  EXPECT_NEAR(std::stod(svg.substr(dur + 5)), sweep.rows.back()[0] - sweep.rows.front()[0], 1e-3);
  EXPECT_EQ(count(svg, "class=\"label\""), pasibot().bodies.size());
}

TEST(MechanismDrawing, ShapesFollowTheGeometry) {
  const mechgen::SweepResult sweep = numeric_sweep(3);
  const report::MechanismFrames frames =
      report::frames_from_table(pasibot(), sweep.columns, {sweep.rows.front()});
  const auto shapes = report::body_shapes(pasibot(), frames.points.front());
  int polygons = 0;
  for (const auto& shape : shapes) polygons += shape.polygon;
  EXPECT_EQ(polygons, 1);  // the hip; every other body is a bar
  EXPECT_THROW(report::frames_from_table(pasibot(), {"t", "A.x"}, {{0, 0}}), std::runtime_error);
}

// --trace: the path of chebyshev's coupler point C, on a still (over the model's step) and on an
// animation (over its frames): every vertex at the solver's C, through the view's mapping; on the
// still a dot sits on C at the drawn time.
TEST(MechanismDrawing, TracedPointPathsOnStillAndAnimation) {
  const Model model = mechgen::read_model(MECHGEN_SOURCE_DIR "/models/chebyshev.yaml");
  mechgen::SweepOptions options = mechgen::default_sweep(model);
  options.solver = "numeric";
  options.samples = 73;
  const mechgen::SweepResult sweep = mechgen::run_sweep(model, options);
  const report::MechanismFrames path = report::frames_from_table(model, sweep.columns, sweep.rows);
  size_t cx = 0;
  while (sweep.columns[cx] != "C.x") ++cx;
  for (const bool animated : {false, true}) {
    SCOPED_TRACE(animated ? "animation" : "still");
    report::DrawingOptions drawing;
    drawing.trace = {"C"};
    drawing.max_frames = 200;  // keep every frame
    report::MechanismFrames frames = path;
    if (!animated) {
      frames = report::frames_from_table(model, sweep.columns, {sweep.rows[20]});
      drawing.trace_path = path;
    }
    const std::string svg = report::draw_mechanism(model, frames, drawing);
    EXPECT_EQ(count(svg, "class=\"trace\""), 1u);
    EXPECT_EQ(count(svg, "class=\"tracer\""), 1u);
    // The view is fitted to the mechanism's frames and the whole path.
    report::MechanismFrames fitted = frames;
    if (!animated)
      fitted.points.insert(fitted.points.end(), path.points.begin(), path.points.end());
    const report::DrawingView view = report::fit_view(fitted, drawing.width);
    const std::vector<double> xy = numbers(attribute(svg, "trace-C", "points"));
    ASSERT_EQ(xy.size(), 2 * sweep.rows.size());
    for (size_t i = 0; i < sweep.rows.size(); ++i) {
      EXPECT_NEAR(xy[2 * i], view.px(sweep.rows[i][cx]), 0.01);
      EXPECT_NEAR(xy[2 * i + 1], view.py(sweep.rows[i][cx + 1]), 0.01);
    }
    const size_t drawn = animated ? 0 : 20;
    EXPECT_NEAR(numbers(attribute(svg, "tracer-C", "cx")).at(0), view.px(sweep.rows[drawn][cx]),
                0.01);
    EXPECT_EQ(svg.find("<animate") != std::string::npos, animated);
  }
  // The straight stroke of the lambda linkage shows in the trace: the first half of the step
  // (crank from pi/2 to 3 pi/2) keeps C within 0.0098 l of y = -4 l.
  const double l = 0.03;
  for (size_t i = 0; i <= 36; ++i) EXPECT_NEAR(sweep.rows[i][cx + 1], -4 * l, 0.0098 * l + 1e-12);
  report::DrawingOptions bad;
  bad.trace = {"Q"};
  try {
    report::draw_mechanism(model, path, bad);
    FAIL() << "traced a point that does not exist";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "--trace: model 'chebyshev' has no point 'Q' (points: A, B, P, C, M)");
  }
}

}  // namespace
