// SVG plots and CSV tables (runtime/report).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "report/column_plot.hpp"
#include "report/csv_table.hpp"
#include "report/svg_plot.hpp"

namespace mechgen::report {
namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + 1)) ++n;
  return n;
}

// The "d" attribute of the path drawing series k.
std::string path_of(const std::string& svg, int k) {
  const std::string tag = "<path class=\"series-" + std::to_string(k) + "\"";
  const auto start = svg.find(tag);
  if (start == std::string::npos) return "";
  const auto d = svg.find(" d=\"", start) + 4;
  return svg.substr(d, svg.find('"', d) - d);
}

// The points of a path "Mx,y Lx,y ...".
std::vector<std::pair<double, double>> path_points(const std::string& d) {
  std::vector<std::pair<double, double>> pts;
  for (std::size_t i = d.find_first_of("ML"); i != std::string::npos;
       i = d.find_first_of("ML", i + 1)) {
    const std::size_t comma = d.find(',', i);
    pts.emplace_back(std::stod(d.substr(i + 1, comma - i - 1)), std::stod(d.substr(comma + 1)));
  }
  return pts;
}

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("mechgen_report_test_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

TEST(NiceTicks, ExactDecimalValues) {
  EXPECT_EQ(nice_ticks(0, 0.87, 5), (std::vector<double>{0, 0.2, 0.4, 0.6, 0.8}));
  EXPECT_EQ(nice_ticks(0, 1, 5), (std::vector<double>{0, 0.2, 0.4, 0.6, 0.8, 1.0}));
  EXPECT_EQ(nice_ticks(-0.35, 0.35, 7), (std::vector<double>{-0.3, -0.2, -0.1, 0, 0.1, 0.2, 0.3}));
  EXPECT_EQ(nice_ticks(-3, 12, 5), (std::vector<double>{0, 5, 10}));
  EXPECT_EQ(nice_ticks(0.0012, 0.0049, 4), (std::vector<double>{0.002, 0.003, 0.004}));
  EXPECT_EQ(nice_ticks(120, 980, 5), (std::vector<double>{200, 400, 600, 800}));
  EXPECT_EQ(nice_ticks(0, 2 * M_PI, 8), (std::vector<double>{0, 1, 2, 3, 4, 5, 6}));
}

TEST(NiceTicks, StepsAreOneTwoFive) {
  EXPECT_EQ(nice_step(0.87, 5), 0.2);
  EXPECT_EQ(nice_step(1.0, 10), 0.1);
  EXPECT_EQ(nice_step(15, 5), 5);
  EXPECT_EQ(nice_step(7, 1), 10);
  EXPECT_EQ(nice_step(3e-6, 3), 1e-6);
}

TEST(NiceTicks, DegenerateInputs) {
  EXPECT_TRUE(nice_ticks(1, 0, 5).empty());
  EXPECT_TRUE(nice_ticks(kNaN, 1, 5).empty());
  EXPECT_EQ(nice_ticks(2.5, 2.5, 5), (std::vector<double>{2.5}));
}

TEST(TickLabels, CommonDecimalsAndNoNegativeZero) {
  EXPECT_EQ(tick_labels({0, 0.2, 0.4}), (std::vector<std::string>{"0.0", "0.2", "0.4"}));
  EXPECT_EQ(tick_labels({-10, -5, 0, 5}), (std::vector<std::string>{"-10", "-5", "0", "5"}));
  EXPECT_EQ(tick_labels({-0.05, 0, 0.05}), (std::vector<std::string>{"-0.05", "0.00", "0.05"}));
  EXPECT_EQ(tick_labels({0, 2e6, 4e6}), (std::vector<std::string>{"0", "2000000", "4000000"}));
  EXPECT_EQ(tick_labels({0, 2e7, 4e7}), (std::vector<std::string>{"0", "2e+07", "4e+07"}));
  EXPECT_EQ(tick_labels({1e-7, 2e-7}), (std::vector<std::string>{"1e-07", "2e-07"}));
}

TEST(Layout, DataMapsToPixelsLinearly) {
  PlotSpec spec;
  spec.title = "torque";
  spec.x_label = "time t [s]";
  spec.y_label = "torque [N m]";
  spec.series.push_back({"theta8.effort", {0, 0.5, 1.0}, {-1, 3, 1}});
  const PlotLayout L = compute_layout(spec);
  ASSERT_TRUE(L.has_data);
  EXPECT_LT(L.left, L.right);
  EXPECT_LT(L.top, L.bottom);
  // x: the data's extent exactly; y: the extent plus 5 % each side.
  EXPECT_EQ(L.x.lo, 0);
  EXPECT_EQ(L.x.hi, 1);
  EXPECT_DOUBLE_EQ(L.y.lo, -1.2);
  EXPECT_DOUBLE_EQ(L.y.hi, 3.2);
  EXPECT_DOUBLE_EQ(L.x.to_px(0), L.left);
  EXPECT_DOUBLE_EQ(L.x.to_px(1), L.right);
  EXPECT_DOUBLE_EQ(L.x.to_px(0.5), 0.5 * (L.left + L.right));
  EXPECT_DOUBLE_EQ(L.y.to_px(-1.2), L.bottom);
  EXPECT_DOUBLE_EQ(L.y.to_px(3.2), L.top);
  EXPECT_DOUBLE_EQ(L.y.to_px(1.0), L.bottom - (2.2 / 4.4) * (L.bottom - L.top));

  // The drawn path goes through exactly those pixels (to 0.01 px, the SVG's precision).
  const std::string svg = render_svg(spec);
  const auto pts = path_points(path_of(svg, 0));
  ASSERT_EQ(pts.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(pts[i].first, L.x.to_px(spec.series[0].x[i]), 0.0051);
    EXPECT_NEAR(pts[i].second, L.y.to_px(spec.series[0].y[i]), 0.0051);
  }
  EXPECT_EQ(path_of(svg, 0).substr(0, 1), "M");
}

TEST(Layout, TicksLieInsideTheAxes) {
  PlotSpec spec;
  spec.series.push_back({"s", {0, 0.87}, {10, 20}});
  const PlotLayout L = compute_layout(spec);
  ASSERT_GE(L.x_ticks.size(), 3u);
  ASSERT_GE(L.y_ticks.size(), 3u);
  for (double t : L.x_ticks) {
    EXPECT_GE(t, L.x.lo);
    EXPECT_LE(t, L.x.hi);
  }
  for (double t : L.y_ticks) {
    EXPECT_GE(t, L.y.lo);
    EXPECT_LE(t, L.y.hi);
  }
}

TEST(Layout, ExplicitRangeIsKept) {
  PlotSpec spec;
  spec.series.push_back({"s", {0, 1, 2}, {0, 100, 0}});
  spec.y_min = -1;
  spec.y_max = 1;
  const PlotLayout L = compute_layout(spec);
  EXPECT_EQ(L.y.lo, -1);
  EXPECT_EQ(L.y.hi, 1);
  // Out-of-range data is clipped to the plot area, not dropped.
  const std::string svg = render_svg(spec);
  EXPECT_NE(svg.find("<clipPath id=\"plot-area\">"), std::string::npos);
  EXPECT_NE(svg.find("clip-path=\"url(#plot-area)\""), std::string::npos);
  EXPECT_EQ(path_points(path_of(svg, 0)).size(), 3u);
}

TEST(Render, LegendTitleAndLabels) {
  PlotSpec spec;
  spec.title = "PASIBOT <step> & torque";
  spec.x_label = "time t [s]";
  spec.y_label = "effort [N m]";
  spec.series.push_back({"theta8.effort", {0, 1}, {0, 1}});
  spec.series.push_back({"jA.fx", {0, 1}, {1, 0}});
  const std::string svg = render_svg(spec);
  EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\"", 0), 0u);
  EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
  EXPECT_NE(svg.find(">theta8.effort</text>"), std::string::npos);
  EXPECT_NE(svg.find(">jA.fx</text>"), std::string::npos);
  EXPECT_EQ(count(svg, "class=\"legend-entry\""), 2);
  EXPECT_NE(svg.find("PASIBOT &lt;step&gt; &amp; torque"), std::string::npos);
  EXPECT_EQ(svg.find("<step>"), std::string::npos);
  EXPECT_NE(svg.find(">time t [s]</text>"), std::string::npos);
  EXPECT_NE(svg.find(">effort [N m]</text>"), std::string::npos);
  // Distinct colours.
  const auto colour = [&](int k) {
    const auto p = svg.find("<path class=\"series-" + std::to_string(k) + "\" stroke=\"");
    return svg.substr(p + 31, 7);
  };
  EXPECT_NE(colour(0), colour(1));
  // Equal numbers of opening and closing tags of each kind used.
  EXPECT_EQ(count(svg, "<text"), count(svg, "</text>"));
  EXPECT_EQ(count(svg, "<g"), count(svg, "</g>"));
}

// Issue 24: a series exactly under another stayed invisible; 20 series on one axis were
// unreadable.
TEST(Render, ASeriesOverAnotherIsDashed) {
  PlotSpec spec;
  spec.series.push_back({"a", {0, 1, 2}, {0, 1, 0}});
  spec.series.push_back({"b", {0, 1, 2}, {0, 1, 0}});  // the same values
  spec.series.push_back({"c", {0, 1, 2}, {1, 0, 1}});
  const std::string svg = render_svg(spec);
  ASSERT_EQ(path_of(svg, 0), path_of(svg, 1));
  const auto dash = [&](int k) {
    const auto p = svg.find("<path class=\"series-" + std::to_string(k) + "\"");
    const auto end = svg.find(" d=\"", p);
    const auto at = svg.find("stroke-dasharray=\"", p);
    return at < end ? svg.substr(at + 18, svg.find('"', at + 18) - at - 18) : std::string();
  };
  EXPECT_EQ(dash(0), "");
  EXPECT_EQ(dash(1), "5 7");
  EXPECT_EQ(dash(2), "");
  EXPECT_EQ(count(svg, "stroke-dasharray=\"5 7\""), 2);  // the path and its legend entry
}

TEST(Render, MoreThanEightSeriesAreSplitIntoPanels) {
  PlotSpec spec;
  spec.title = "twenty";
  for (int k = 0; k < 20; ++k)
    spec.series.push_back({"s" + std::to_string(k), {0, 1, 2}, {0, 1.0 * k, 2.0 * k}});
  const std::string svg = render_svg(spec);
  EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"800\" height=\"1500\" "
                      "viewBox=\"0 0 800 1500\">",
                      0),
            0u);
  EXPECT_EQ(count(svg, "<svg class=\"panel\""), 3);
  EXPECT_EQ(count(svg, "class=\"legend-entry\""), 20);
  // At most 8 series a panel (7, 7, 6), each panel clipped to its own plot area.
  std::vector<int> per_panel;
  for (auto at = svg.find("<svg class=\"panel\""); at != std::string::npos;
       at = svg.find("<svg class=\"panel\"", at + 1))
    per_panel.push_back(
        count(svg.substr(at, svg.find("</svg>", at) - at), "class=\"legend-entry\""));
  EXPECT_EQ(per_panel, (std::vector<int>{7, 7, 6}));
  for (const char* id : {"plot-area-1", "plot-area-2", "plot-area-3"})
    EXPECT_EQ(count(svg, id), 2) << id;  // defined once, used once
  EXPECT_NE(svg.find("twenty (2 of 3)"), std::string::npos);
  EXPECT_NE(svg.find("y=\"1000\""), std::string::npos);
  EXPECT_EQ(count(svg, "<svg"), count(svg, "</svg>"));
}

// Issue 24: a walking plot did not show where the support foot changes.
TEST(ColumnPlot, SupportChangesOfAWalkAreMarked) {
  CsvTable table;
  table.header = {"t", "step", "support", "theta8.effort"};
  table.rows = {{0, 0, 0, 1},   {0.5, 0, 0, 2}, {1, 0, 0, 3}, {1, 1, 1, 3},
                {1.5, 1, 1, 2}, {2, 1, 1, 1},   {2, 2, 0, 1}, {2.5, 2, 0, 0}};
  ColumnPlotOptions options;
  options.x = "t";
  options.y = {"theta8.effort"};
  const PlotSpec spec = column_plot(table, options);
  EXPECT_EQ(spec.x_marks, (std::vector<double>{1, 2}));
  const std::string svg = render_svg(spec);
  EXPECT_EQ(count(svg, "class=\"x-mark\""), 2);
  EXPECT_NE(svg.find(">support change</text>"), std::string::npos);
  const PlotLayout L = compute_layout(spec);
  const size_t at = svg.find("class=\"x-mark\"");
  const size_t x1 = svg.rfind("x1=\"", at) + 4;
  EXPECT_NEAR(std::stod(svg.substr(x1)), L.x.to_px(1.0), 0.01);
  // Against another column, or without a support column: no marks.
  options.x = "theta8.effort";
  options.y = {"t"};
  EXPECT_TRUE(column_plot(table, options).x_marks.empty());
}

// Issue 24: the stress plot was in Pa while loads prints MPa, and its yield was nowhere.
TEST(ColumnPlot, StressesInMegapascalsWithTheYieldAsALimit) {
  EXPECT_EQ(column_unit("l7.sigma"), "[Pa]");
  const CsvTable t = parse_csv("t,l7.sigma,l2.sigma\n0,1e6,2e6\n1,3.5e7,4e6\n", "loads.csv");
  ColumnPlotOptions options{"t", {"l7.sigma", "l2.sigma"}, "", "", ""};
  options.limits = {{276, "yield 276 MPa", PlotSpec::Limit::Side::max},
                    {10, "a line", PlotSpec::Limit::Side::line}};
  const PlotSpec spec = column_plot(t, options);
  EXPECT_EQ(spec.y_label, "l7.sigma, l2.sigma [MPa]");
  EXPECT_EQ(spec.series[0].y, (std::vector<double>{1, 35}));
  const PlotLayout L = compute_layout(spec);
  EXPECT_GE(L.y.hi, 276);  // the limit is inside the range
  const std::string svg = render_svg(spec);
  ASSERT_EQ(count(svg, "class=\"limit\""), 2);
  EXPECT_EQ(count(svg, "class=\"beyond-limit\""), 1);  // a line limit shades nothing
  const size_t at = svg.find("class=\"limit\"");
  const size_t y1 = svg.rfind("y1=\"", at) + 4;
  EXPECT_NEAR(std::stod(svg.substr(y1)), L.y.to_px(276), 0.01);
  EXPECT_NE(svg.find(">yield 276 MPa</text>"), std::string::npos);
  // Above the data: the band from the line up to the top of the plot is shaded.
  const size_t band = svg.find("class=\"beyond-limit\"");
  ASSERT_NE(band, std::string::npos);
  EXPECT_NEAR(std::stod(svg.substr(svg.find("y=\"", band) + 3)), L.top, 0.01);
  EXPECT_NEAR(std::stod(svg.substr(svg.find("height=\"", band) + 8)), L.y.to_px(276) - L.top, 0.01);
}

TEST(Render, LongLegendLabelsAreShortenedNotSqueezingThePlot) {
  PlotSpec spec;
  const std::string long_label(60, 'a');
  spec.series.push_back({long_label, {0, 1}, {0, 1}});
  const PlotLayout L = compute_layout(spec);
  EXPECT_GT(L.right - L.left, 0.6 * spec.width);
  const std::string svg = render_svg(spec);
  EXPECT_EQ(svg.find(long_label), std::string::npos);
  EXPECT_NE(svg.find(">" + long_label.substr(0, 10)), std::string::npos);
  EXPECT_NE(svg.find("...</text>"), std::string::npos);
}

TEST(Render, NonFiniteValuesBreakTheLine) {
  PlotSpec spec;
  spec.series.push_back({"s", {0, 1, 2, 3, 4, 5}, {0, 1, kNaN, 3, INFINITY, 5}});
  const std::string svg = render_svg(spec);
  const std::string d = path_of(svg, 0);
  EXPECT_EQ(count(d, "M"), 3);  // 0-1, then 3 alone, then 5 alone
  EXPECT_EQ(count(d, "L"), 1);
  EXPECT_EQ(count(svg, "<circle"), 2);  // isolated points are dots
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(svg.find("inf"), std::string::npos);
}

TEST(Render, EmptyAndConstantData) {
  const std::string empty = render_svg(PlotSpec{});
  EXPECT_NE(empty.find("no data"), std::string::npos);
  EXPECT_EQ(empty.find("nan"), std::string::npos);

  PlotSpec all_nan;
  all_nan.series.push_back({"s", {kNaN, kNaN}, {kNaN, kNaN}});
  EXPECT_NE(render_svg(all_nan).find("no data"), std::string::npos);

  PlotSpec constant;
  constant.series.push_back({"c", {0, 1, 2}, {3, 3, 3}});
  const PlotLayout L = compute_layout(constant);
  EXPECT_LT(L.y.lo, 3);
  EXPECT_GT(L.y.hi, 3);
  EXPECT_NEAR(L.y.to_px(3), 0.5 * (L.top + L.bottom), 1e-9);
  EXPECT_GE(L.y_ticks.size(), 2u);

  PlotSpec zero_point;
  zero_point.series.push_back({"p", {0}, {0}});
  const PlotLayout Z = compute_layout(zero_point);
  EXPECT_LT(Z.x.lo, 0);
  EXPECT_GT(Z.x.hi, 0);
  EXPECT_EQ(count(render_svg(zero_point), "<circle"), 1);
}

TEST(Render, MismatchedSeriesIsAnError) {
  PlotSpec spec;
  spec.series.push_back({"bad", {0, 1, 2}, {0, 1}});
  EXPECT_THROW(render_svg(spec), std::invalid_argument);
}

TEST(Csv, ParsesNumbersHeaderAndSpecialValues) {
  const CsvTable t = parse_csv("t, a.x ,b\r\n0,1.5,-2e-3\n\n0.1,nan,+inf\n", "mem.csv", Cells::any);
  EXPECT_EQ(t.header, (std::vector<std::string>{"t", "a.x", "b"}));
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0], (std::vector<double>{0, 1.5, -2e-3}));
  EXPECT_TRUE(std::isnan(t.rows[1][1]));
  EXPECT_EQ(t.rows[1][2], INFINITY);
  EXPECT_EQ(t.column("a.x"), 1);
  EXPECT_EQ(t.column("missing"), -1);
  EXPECT_EQ(t.values(0), (std::vector<double>{0, 0.1}));
}

void expect_error(const std::string& text, const std::string& message) {
  try {
    parse_csv(text, "run.csv");
    ADD_FAILURE() << "no error for: " << text;
  } catch (const CsvError& e) {
    EXPECT_EQ(std::string(e.what()), message);
  }
}

TEST(Csv, ErrorsNameFileAndLine) {
  expect_error("t,x\n0,1\n0.1,abc\n", "run.csv:3: column 'x': 'abc' is not a number");
  expect_error("t,x\n0,1\n0.1\n", "run.csv:3: expected 2 values, found 1");
  expect_error("t,x\n0,1,2\n", "run.csv:2: expected 2 values, found 3");
  expect_error("t,x\n0,\n", "run.csv:2: column 'x': '' is not a number");
  expect_error("t,x\n0,1.5.2\n", "run.csv:2: column 'x': '1.5.2' is not a number");
  expect_error("t,x\n0,1e999\n", "run.csv:2: column 'x': '1e999' is out of range");
  expect_error("t,,x\n", "run.csv:1: empty name for column 2");
  // Non-finite cells: an analysis would compute with them (summary printed nan, issue 16).
  expect_error("t,x\n0,1\n0.1,nan\n", "run.csv:3: column 'x': 'nan' is not finite");
  expect_error("t,x\n0,-inf\n", "run.csv:2: column 'x': '-inf' is not finite");
  expect_error("t,x\n0,+INF\n", "run.csv:2: column 'x': '+INF' is not finite");
  expect_error("t,x,t\n", "run.csv:1: column 't' appears twice");
  expect_error("", "run.csv:1: no header row (the file is empty)");
  try {
    read_csv("/nonexistent/dir/file.csv");
    ADD_FAILURE();
  } catch (const CsvError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/dir/file.csv:0: cannot open for reading");
  }
  const CsvTable t = parse_csv("t,x\n", "run.csv");
  try {
    t.require_column("y");
    ADD_FAILURE();
  } catch (const CsvError& e) {
    EXPECT_EQ(std::string(e.what()), "run.csv: no column 'y' (columns: t, x)");
  }
}

TEST(Csv, RoundTripKeepsEveryBit) {
  CsvTable t;
  t.header = {"t", "theta8.effort", "C.x"};
  t.rows = {{0, 0.1, 1.0 / 3.0},
            {1e-300, -2.5e10, M_PI},
            {0.30000000000000004, std::nextafter(1.0, 2.0), -0.0},
            {5e-324, std::numeric_limits<double>::max(), INFINITY}};
  const std::string path = temp_path("roundtrip.csv");
  write_csv(t, path);
  const CsvTable back = read_csv(path, Cells::any);
  std::filesystem::remove(path);
  EXPECT_EQ(back.path, path);
  EXPECT_EQ(back.header, t.header);
  ASSERT_EQ(back.rows.size(), t.rows.size());
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    for (std::size_t j = 0; j < t.header.size(); ++j) {
      EXPECT_EQ(back.rows[i][j], t.rows[i][j]) << i << "," << j;
      EXPECT_EQ(std::signbit(back.rows[i][j]), std::signbit(t.rows[i][j]));
    }
  }
}

TEST(ColumnPlot, LabelsAndUnitsFromColumnNames) {
  EXPECT_EQ(column_unit("t"), "[s]");
  EXPECT_EQ(column_unit("l3.vx"), "[m/s]");
  EXPECT_EQ(column_unit("l3.al"), "[rad/s²]");
  EXPECT_EQ(column_unit("jA.fy"), "[N]");
  EXPECT_EQ(column_unit("slide.m"), "[N m]");
  EXPECT_EQ(column_unit("theta8.effort"), "");  // torque or force: the kind is not in the name

  const CsvTable t = parse_csv("t,C.x,C.y,theta8.effort\n0,1,2,3\n0.5,1.5,2.5,-3\n", "s.csv");
  const PlotSpec xy = column_plot(t, {"t", {"C.x", "C.y"}, "", "", ""});
  EXPECT_EQ(xy.x_label, "time t [s]");
  EXPECT_EQ(xy.y_label, "C.x, C.y [m]");
  ASSERT_EQ(xy.series.size(), 2u);
  EXPECT_EQ(xy.series[1].label, "C.y");
  EXPECT_EQ(xy.series[1].x, (std::vector<double>{0, 0.5}));
  EXPECT_EQ(xy.series[1].y, (std::vector<double>{2, 2.5}));

  const PlotSpec e = column_plot(t, {"t", {"theta8.effort"}, "", "", "torque [N m]"});
  EXPECT_EQ(e.y_label, "torque [N m]");
  EXPECT_EQ(e.title, "theta8.effort over t");
  EXPECT_THROW(column_plot(t, {"t", {"nope"}, "", "", ""}), CsvError);
}

// --equal: one scale on both axes, so a circle is drawn round (in a 800 x 500 plot whose free
// layout stretches it), centred, and the data stays inside the axes.
TEST(Layout, EqualScaleKeepsACircleRound) {
  PlotSpec spec;
  spec.title = "coupler point";
  spec.x_label = "C.x [m]";
  spec.y_label = "C.y [m]";
  std::vector<double> x, y;
  for (int i = 0; i <= 360; ++i) {
    x.push_back(3 + 0.5 * std::cos(i * M_PI / 180));
    y.push_back(-2 + 0.5 * std::sin(i * M_PI / 180));
  }
  spec.series.push_back({"C", x, y});
  auto radii = [&](const PlotLayout& L) {
    const double cx = L.x.to_px(3), cy = L.y.to_px(-2);
    double lo = INFINITY, hi = 0;
    for (size_t i = 0; i < x.size(); ++i) {
      const double r = std::hypot(L.x.to_px(x[i]) - cx, L.y.to_px(y[i]) - cy);
      lo = std::min(lo, r);
      hi = std::max(hi, r);
    }
    return std::pair<double, double>{lo, hi};
  };
  const auto [free_lo, free_hi] = radii(compute_layout(spec));
  EXPECT_GT(free_hi / free_lo, 1.2);  // the free layout makes an ellipse
  spec.equal_scale = true;
  const PlotLayout L = compute_layout(spec);
  const auto [lo, hi] = radii(L);
  EXPECT_NEAR(hi / lo, 1.0, 1e-9);
  EXPECT_NEAR(std::abs(L.x.px_hi - L.x.px_lo) / (L.x.hi - L.x.lo),
              std::abs(L.y.px_hi - L.y.px_lo) / (L.y.hi - L.y.lo), 1e-9);
  EXPECT_NEAR((L.x.lo + L.x.hi) / 2, 3, 1e-12);  // the widened axis stays centred
  EXPECT_LE(L.x.lo, 2.5);
  EXPECT_GE(L.x.hi, 3.5);
  EXPECT_LE(L.y.lo, -2.5);
  EXPECT_GE(L.y.hi, -1.5);
  EXPECT_NE(render_svg(spec).find("<svg"), std::string::npos);
}

}  // namespace
}  // namespace mechgen::report
