// Spatial Newton-Euler: the power balance (driver power = dT/dt + dV/dt, with dT/dt also checked
// against finite differences of T), the spatial rewrite of the planar Chebyshev four-bar (the
// numeric spatial sweep and the generated kernel's) against the planar reference solver
// (efforts; reactions where unique), and its redundancy.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "model/spatial_model.hpp"
#include "spatial/spatial_drawing.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_kernel_sweep.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"
#include "spatial_test_models.hpp"
#include "sweep/compiled_kernel.hpp"
#include "sweep/sweep.hpp"

namespace mechgen::spatial {
namespace {

TEST(SpatialDynamics, DriverPowerIsTheRateOfKineticPlusPotentialEnergy) {
  std::vector<Case> cases = closed_chains();
  cases.push_back({"leg6", text_of(MECHGEN_SOURCE_DIR "/models/leg6.yaml")});
  for (const auto& [name, text] : cases) {
    SCOPED_TRACE(name);
    const SpatialModel model = read_spatial_model_text(text, name + ".yaml");
    const SpatialSolver solver(model, {});
    const SpatialSweepOptions o = default_spatial_sweep(model);
    SpatialState s;
    double worst = 0, worst_fd = 0, scale = 0;
    const double h = 1e-5;
    for (int i = 0; i <= 20; ++i) {
      const double t = o.t0 + (o.t1 - o.t0) * i / 20;
      solver.solve(t, s);
      const SpatialLoads loads = inverse_dynamics(solver, s);
      Eigen::VectorXd qp, qpd, qpdd;
      solver.primary_motion(t, qp, qpd, qpdd);
      const double power = loads.effort.dot(qpd) + solver.applied_power(s);
      const Energy e = energy(solver, s);
      worst = std::max(worst, std::abs(power - e.kinetic_rate - e.potential_rate));
      scale = std::max(scale, std::abs(power));
      SpatialState plus = s, minus = s;
      solver.solve(t + h, plus);
      solver.solve(t - h, minus);
      const Energy ep = energy(solver, plus), em = energy(solver, minus);
      worst_fd = std::max(
          worst_fd,
          std::abs((ep.kinetic + ep.potential - em.kinetic - em.potential) / (2 * h) - power));
    }
    EXPECT_GT(scale, 1e-4);  // the drivers do work
    EXPECT_LT(worst, 1e-12 * std::max(1.0, scale));
    EXPECT_LT(worst_fd, 1e-7);
    std::cout << name << ": peak driver power " << scale << " W, |P - dE/dt| " << worst
              << " (finite differences of T + V: " << worst_fd << ")\n";
  }
}

// At rest and without gravity, the driver torques balancing a force F at the foot and a couple M
// on it are -(J_foot^T F + J_w^T M): the screw Jacobians' transposes (checked against KDL's
// Jacobian elsewhere) against the Newton-Euler solve.
TEST(SpatialDynamics, FootLoadsMapToTorquesThroughTheJacobianTranspose) {
  std::string text = text_of(MECHGEN_SOURCE_DIR "/models/leg6.yaml");
  text.replace(text.find("gravity: [0, 0, -9.81]"), 23, "gravity: [0, 0, 0]");
  text +=
      "forces:\n  - {name: push, type: force, body: foot_link, point: toe, value: [3, -2, 40]}\n"
      "  - {name: twist, type: torque, body: foot_link, value: [0.1, 0.2, -0.3]}\n";
  const SpatialModel model = read_spatial_model_text(text, "leg6_loaded.yaml");
  const SpatialSolver solver(model, {});
  const int foot = model.body_index("foot_link");
  for (const Eigen::VectorXd& q : {Eigen::VectorXd(Eigen::VectorXd::Zero(6)),
                                   Eigen::VectorXd(Eigen::VectorXd::LinSpaced(6, -0.5, 0.9))}) {
    SpatialState s;
    s.q = q;
    solver.place(s);
    solver.rates(s, Eigen::VectorXd::Zero(6), Eigen::VectorXd::Zero(6));
    const V3 toe =
        solver.point_position(s, foot, solver.instance().points[static_cast<size_t>(foot)][1]);
    const Eigen::VectorXd expected =
        -(solver.point_jacobian(s, foot, toe).transpose() * Eigen::Vector3d(3, -2, 40) +
          solver.body_jacobian(s, foot).topRows(3).transpose() * Eigen::Vector3d(0.1, 0.2, -0.3));
    const SpatialLoads loads = inverse_dynamics(solver, s);
    EXPECT_LT((loads.effort - expected).cwiseAbs().maxCoeff(), 1e-13) << loads.effort.transpose();
    EXPECT_GT(expected.norm(), 1);
  }
}

TEST(SpatialDynamics, SpatialChebyshevEqualsThePlanarSweep) {
  const SpatialModel spatial_model =
      read_spatial_model(MECHGEN_SOURCE_DIR "/models/chebyshev_spatial.yaml");
  const Model planar = read_model(MECHGEN_SOURCE_DIR "/models/chebyshev.yaml");
  SpatialSweepOptions so = default_spatial_sweep(spatial_model);
  so.samples = 73;
  SweepOptions po = default_sweep(planar);
  po.solver = "numeric";
  po.samples = 73;
  // The numeric spatial sweep and the generated kernel's (its planar loop in closed form).
  const CompiledKernel* kernel = find_compiled_kernel("chebyshev_spatial");
  ASSERT_NE(kernel, nullptr);
  const std::vector<SpatialSweepResult> spatial_sweeps{
      run_spatial_sweep(spatial_model, so), run_spatial_kernel_sweep(spatial_model, so, *kernel)};
  const SweepResult pr = run_sweep(planar, po);
  auto column = [](const std::vector<std::string>& cols, const std::string& name) {
    const auto at = std::find(cols.begin(), cols.end(), name);
    EXPECT_NE(at, cols.end()) << name;
    return static_cast<size_t>(at - cols.begin());
  };
  std::vector<std::string> compared{
      "crank_angle.effort", "crank_angle.qd", "crank.vx", "coupler.ax", "rocker.ay", "C.x", "C.y"};
  for (const char* j : {"A_ground_crank", "P_crank_coupler", "M_rocker_coupler", "B_ground_rocker"})
    for (const char* f : {".fx", ".fy"}) compared.push_back(std::string(j) + f);
  double worst = 0;
  for (const SpatialSweepResult& sr : spatial_sweeps) {
    for (const std::string& name : compared) {
      const size_t cs = column(sr.columns, name), cp = column(pr.columns, name);
      for (size_t i = 0; i < sr.rows.size(); ++i) {
        const double d = std::abs(sr.rows[i][cs] - pr.rows[i][cp]);
        worst = std::max(worst, d);
        EXPECT_LT(d, 1e-9 * std::max(1.0, std::abs(pr.rows[i][cp]))) << name << " at row " << i;
      }
    }
    // The driver angle is measured from the reference pose (planar: pi/2 + w t).
    const size_t qs = column(sr.columns, "crank_angle.q"), qp = column(pr.columns, "crank_angle.q");
    for (size_t i = 0; i < sr.rows.size(); ++i)
      EXPECT_NEAR(sr.rows[i][qs] + M_PI / 2, pr.rows[i][qp], 1e-12);
  }
  std::cout << "chebyshev spatial vs planar: largest difference " << worst << "\n";
}

TEST(SpatialDynamics, PlanarLinkageOfSpatialRevolutesIsRedundantByThree) {
  const SpatialModel model =
      read_spatial_model(MECHGEN_SOURCE_DIR "/models/chebyshev_spatial.yaml");
  const SpatialSolver solver(model, {});
  SpatialState s;
  solver.solve(0.3, s);
  const Redundancy r = redundancy(solver, s);
  // 4 x 5 reaction unknowns + 1 effort against 3 x 6 body equations: 21 - 18 = 3.
  EXPECT_EQ(r.degree, 3);
  EXPECT_EQ(inverse_dynamics(solver, s).redundancy, 3);
  EXPECT_TRUE(r.efforts_unique);
  for (size_t j = 0; j < model.joints.size(); ++j) {
    EXPECT_FALSE(r.joint_unique[j]);
    const std::array<bool, 6> expected{true, true, false, false, false, true};
    EXPECT_EQ(r.component_unique[j], expected) << model.joints[j].name;
  }
  // The RSUR and the serial leg are not redundant.
  for (const char* name : {"rsur", "leg6"}) {
    const SpatialModel m =
        read_spatial_model(std::string(MECHGEN_SOURCE_DIR) + "/models/" + name + ".yaml");
    const SpatialSolver sv(m, {});
    SpatialState st;
    sv.solve(0.2, st);
    EXPECT_EQ(redundancy(sv, st).degree, 0) << name;
  }
}

// The two views share one scale and one vertical axis: a joint's pixel height is the same in both,
// and pixel offsets between joints are the world offsets (x in the sagittal, y in the frontal view)
// times that scale.
TEST(SpatialDrawing, SagittalAndFrontalViewsShareOneScale) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/leg6.yaml");
  const SpatialSolver solver(model, {});
  const SpatialFrames frames = spatial_frames(solver, {0.0, 0.2, 0.4});
  ASSERT_EQ(frames.joints[2].size(), 6u);
  SpatialFrames still = frames;
  still.times = {0.4}, still.bodies = {frames.bodies[2]}, still.joints = {frames.joints[2]};
  EXPECT_EQ(spatial_views(still), (std::vector<std::string>{"side", "front"}));
  const std::string svg = draw_spatial(still, SpatialDrawingOptions{});
  std::vector<std::pair<double, double>> circles;  // (cx, cy) in document order: side, then front
  for (size_t at = svg.find("<circle"); at != std::string::npos; at = svg.find("<circle", at + 1))
    circles.emplace_back(std::stod(svg.substr(svg.find("cx=\"", at) + 4)),
                         std::stod(svg.substr(svg.find("cy=\"", at) + 4)));
  ASSERT_EQ(circles.size(), 12u);
  const std::vector<V3>& j = frames.joints[2];
  const double scale = (circles[4].second - circles[3].second) / (j[3][2] - j[4][2]);
  EXPECT_GT(scale, 0);
  for (size_t k = 0; k < 6; ++k) {
    EXPECT_NEAR(circles[k].second, circles[k + 6].second, 0.011);  // same height in both views
    EXPECT_NEAR(circles[k].first - circles[0].first, scale * (j[k][0] - j[0][0]), 0.02);
    EXPECT_NEAR(circles[k + 6].first - circles[6].first, scale * (j[k][1] - j[0][1]), 0.02);
    EXPECT_NEAR(circles[k].second - circles[0].second, -scale * (j[k][2] - j[0][2]), 0.02);
  }
  // Animated: one value per frame.
  const std::string animated = draw_spatial(frames, SpatialDrawingOptions{});
  const auto values = animated.find("values=\"", animated.find("id=\"side-calf\""));
  const std::string list = animated.substr(values, animated.find('"', values + 8) - values);
  EXPECT_EQ(std::count(list.begin(), list.end(), ';'), 2);
}

// The numbers of an SVG attribute list "x1,y1 x2,y2 ..." (polyline points).
std::vector<double> numbers(const std::string& svg, const std::string& id) {
  const size_t at = svg.find("points=\"", svg.find("id=\"" + id + "\""));
  std::string list = svg.substr(at + 8, svg.find('"', at + 8) - at - 8);
  std::replace(list.begin(), list.end(), ',', ' ');
  std::istringstream in(list);
  std::vector<double> out;
  for (double v; in >> v;) out.push_back(v);
  return out;
}

// Bioloid's waist (hips, shoulders, neck) was drawn as a self-crossing zig-zag (issue 24): now an
// outline about its centroid, closed, whose edges cross nowhere in the frontal view.
TEST(SpatialDrawing, ATrunkIsAnOutlineThatDoesNotCrossItself) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/bioloid.yaml");
  const SpatialSolver solver(model, {});
  const SpatialFrames frames = spatial_frames(solver, {0.0});
  const auto waist = std::find(frames.body_names.begin(), frames.body_names.end(), "waist");
  ASSERT_NE(waist, frames.body_names.end());
  const std::vector<V3>& at =
      frames.bodies[0][static_cast<size_t>(waist - frames.body_names.begin())];
  ASSERT_GE(at.size(), 5u);  // four or more locations, closed
  EXPECT_EQ(at.front(), at.back());
  // Proper crossings of two edges that share no end, in the frontal (y, z) projection.
  auto side = [](const V3& a, const V3& b, const V3& c) {
    return (b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]);
  };
  int crossings = 0;
  for (size_t i = 0; i + 1 < at.size(); ++i)
    for (size_t j = i + 2; j + 1 < at.size(); ++j) {
      if (i == 0 && j + 2 == at.size()) continue;  // neighbours across the closing point
      const double d1 = side(at[i], at[i + 1], at[j]), d2 = side(at[i], at[i + 1], at[j + 1]);
      const double d3 = side(at[j], at[j + 1], at[i]), d4 = side(at[j], at[j + 1], at[i + 1]);
      crossings += (d1 * d2 < -1e-12 && d3 * d4 < -1e-12) ? 1 : 0;
    }
  EXPECT_EQ(crossings, 0);
}

// lecture_leg lies in the x-y plane: its sagittal and frontal views would be lines (issue 24), so
// the drawing shows the top view alone and says why; the canvas keeps a sane shape, with a
// viewBox. A named point's path is drawn (one vertex a time), labels name the bodies, and an
// unknown point is an error naming the points there are.
TEST(SpatialDrawing, ViewsFromTheExtentTracesAndLabels) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/lecture_leg.yaml");
  const SpatialSolver solver(model, {});
  const auto points = model.named_points();
  ASSERT_FALSE(points.empty());
  const std::string point = points.back().first;
  const SpatialFrames frames = spatial_frames(solver, {0.0, 0.1, 0.2, 0.3}, {point});
  ASSERT_EQ(frames.traces.size(), 1u);
  ASSERT_EQ(frames.traces[0].size(), 4u);
  EXPECT_EQ(spatial_views(frames), std::vector<std::string>{"top"});
  SpatialDrawingOptions options;
  options.labels = true;
  const std::string svg = draw_spatial(frames, options);
  EXPECT_EQ(svg.find("id=\"side-"), std::string::npos);
  EXPECT_EQ(svg.find("id=\"front-"), std::string::npos);
  EXPECT_NE(svg.find("sagittal and frontal view left out: the mechanism is edge-on"),
            std::string::npos);
  const double width = std::stod(svg.substr(svg.find("width=\"") + 7));
  const double height = std::stod(svg.substr(svg.find("height=\"") + 8));
  EXPECT_GT(width, 300);
  EXPECT_GT(height, 100);
  EXPECT_NE(svg.find("viewBox=\"0 0 "), std::string::npos);
  const std::vector<double> path = numbers(svg, "top-trace-" + point);
  ASSERT_EQ(path.size(), 8u);
  // The path in pixels follows the point: x right, y up, one scale.
  const double dx = frames.traces[0][3][0] - frames.traces[0][0][0];
  const double dy = frames.traces[0][3][1] - frames.traces[0][0][1];
  ASSERT_GT(std::abs(dx), 1e-3);
  ASSERT_GT(std::abs(dy), 1e-3);
  const double scale = (path[6] - path[0]) / dx;
  EXPECT_GT(scale, 0);
  EXPECT_NEAR(-(path[7] - path[1]) / dy, scale, 0.01 * scale);
  EXPECT_NE(svg.find("id=\"top-tracer-" + point + "\""), std::string::npos);  // animated
  EXPECT_NE(svg.find("class=\"label\""), std::string::npos);
  for (const std::string& body : frames.body_names)
    EXPECT_NE(svg.find(">" + body + "</text>"), std::string::npos) << body;
  try {
    spatial_frames(solver, {0.0}, {"NOSUCH"});
    ADD_FAILURE() << "no error for an unknown point";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("has no point 'NOSUCH' (points: "), std::string::npos);
    EXPECT_NE(std::string(error.what()).find(point), std::string::npos);
  }
}

}  // namespace
}  // namespace mechgen::spatial
