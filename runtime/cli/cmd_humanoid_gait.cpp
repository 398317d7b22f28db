// mechgen humanoid-gait: the seed-001 humanoid walking (runtime/spatial/humanoid_gait.hpp) on the
// numeric solver: the leg joints' angles and velocities (seed Figs. 7 and 8), the joint torques
// the servos must give in single support against their stall torque (from the generated
// single-support kernels, spatial/support_kernel.hpp, or numerically), and the ZMP two ways
// (LIP-3D from the centre of mass, exact from the floor wrench) with the margin to the support
// polygon.
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iostream>

#include "cli/command.hpp"
#include "model/spatial_value_checks.hpp"
#include "model/support_model.hpp"
#include "ondemand/kernel_resolver.hpp"
#include "report/atomic_output.hpp"
#include "report/csv_table.hpp"
#include "report/svg_plot.hpp"
#include "spatial/floating_base.hpp"
#include "spatial/humanoid_gait.hpp"
#include "spatial/support_kernel.hpp"

namespace mechgen::cli {

namespace {

using spatial::V3;

const char* const kHumanoidGaitHelp =
    R"(usage: mechgen humanoid-gait MODEL.yaml --out DIR [--samples-per-step N] [--stall-torque T]
                              [--set NAME=VALUE]... [--waist NAME] [--right-foot NAME] [--left-foot NAME]
                              [--solver generated|numeric]

A walking gait of a humanoid modelled as seed 001 does (models/bioloid.yaml): Kajita's 3D linear
inverted pendulum walk (ZMP on the support foot's centre, support switching each step_time),
the waist and both feet planned in the inertial frame and fed to their 3P3R virtual chains, the
other pose drivers (hands) carried with the waist; Davies' method (numeric reference solver)
gives every real joint. The joint torques and the floor wrench come from the generated
single-support kernels (`mechgen generate MODEL.yaml --support FOOT`, one per foot, compiled in
or built on first use), or with --solver numeric from the numeric tree dynamics. The model
supplies the parameters step_length, step_time, swing_height and steps. Writes into DIR:
  gait.csv                 t, step, support (0 right, 1 left), per real joint J: J.q, J.qd,
                           J.torque (single support, support foot as ground); per real body B:
                           B.x/y/z (centre of mass), B.qw/qx/qy/qz (orientation), the
                           poses `mechgen view` animates; com.x/y/z,
                           floor.fx/fy/fz/mx/my/mz (on the support foot, about the origin),
                           zmp_planned.x/y, zmp_lip.x/y, zmp_exact.x/y, zmp_difference,
                           margin_lip, margin_exact (to the support polygon's edge, + inside)
  fig7_leg_angles.svg      leg joint angles (seed Fig. 7)
  fig8_leg_velocities.svg  leg joint velocities (seed Fig. 8)
  leg_torques.svg, arm_torques.svg   joint torques with the stall torque
  zmp_x.svg, zmp_y.svg     planned, LIP-3D and exact ZMP over time
  zmp_difference.svg       exact minus LIP-3D, per axis
  zmp_path.svg             top view: both ZMPs and the footprints
  walk.svg                 animated stick figure, side and front views (10 frames per step):
                           limbs coloured by side, joints marked, centre of mass and exact ZMP
options:
  --samples-per-step N     samples in each step (default 50)
  --stall-torque T         servo stall torque in N m (default 1.5: Robotis AX-12)
  --set NAME=VALUE         override a model parameter (e.g. step_length, step_time, steps)
  --waist, --right-foot, --left-foot   pose driver names (default vFB, vRL, vLL)
  --solver S               generated (default: the single-support kernels) or numeric
)";

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw std::runtime_error(path + ": error: cannot write");
}

report::Series series(const std::string& label, const std::vector<double>& x,
                      const std::vector<double>& y) {
  return {label, x, y};
}

// The stick figure of one solved state: per real body, lines from the joint point that carries it
// (or, for the waist, its first named point) to the points of the joints it carries and to its own
// named points. Each line as x1 y1 z1 x2 y2 z2; `body_of_line` gets the body of each.
std::vector<std::array<double, 6>> stick_figure(const spatial::SpatialSolver& solver,
                                                const spatial::SpatialState& s,
                                                std::vector<int>& body_of_line) {
  const SpatialModel& m = solver.model();
  const spatial::SpatialInstance& in = solver.instance();
  std::vector<std::array<double, 6>> lines;
  for (size_t b = 0; b < m.bodies.size(); ++b) {
    if (m.bodies[b].ground || m.bodies[b].is_virtual) continue;
    const int bi = static_cast<int>(b);
    std::vector<V3> ends;
    V3 from{0, 0, 0};
    bool have_from = false;
    for (size_t j = 0; j < m.joints.size(); ++j) {
      if (m.joints[j].is_virtual) continue;
      const V3 p = geometry::apply(s.D[b], in.joint_point[j]);
      if (m.joints[j].second == bi) from = p, have_from = true;
      if (m.joints[j].first == bi) ends.push_back(p);
    }
    for (size_t k = 0; k < m.bodies[b].points.size(); ++k) {
      const V3 p = solver.point_position(s, bi, in.points[b][k]);
      if (!have_from) {
        from = p, have_from = true;
        continue;
      }
      ends.push_back(p);
    }
    for (const V3& e : ends)
      if (std::hypot(e[0] - from[0], e[1] - from[1], e[2] - from[2]) > 1e-6)
        lines.push_back({from[0], from[1], from[2], e[0], e[1], e[2]}), body_of_line.push_back(bi);
  }
  return lines;
}

// The colour of each line of a stick figure, from the body it belongs to: a body named r_... red,
// l_... green, any other (the trunk) blue.
std::vector<std::string> line_colours(const SpatialModel& m, const std::vector<int>& body_of_line) {
  std::vector<std::string> colours;
  for (const int b : body_of_line) {
    const std::string& name = m.bodies[static_cast<size_t>(b)].name;
    colours.push_back(name.rfind("r_", 0) == 0   ? "#c0392b"
                      : name.rfind("l_", 0) == 0 ? "#27ae60"
                                                 : "#1f4e99");
  }
  return colours;
}

// One frame of walk.svg: the stick figure's lines (x1 y1 z1 x2 y2 z2), the centre of mass and the
// exact ZMP on the floor.
struct StickFrame {
  std::vector<std::array<double, 6>> lines;
  std::vector<int> bodies;  // the body each line belongs to
  V3 com, zmp;
};

// An SVG element whose attributes `names` take one value a frame, looping over `duration`; the
// first frame's values are its own attributes (a viewer without SMIL shows the start pose).
std::string animated_element(const std::string& tag, const std::string& style,
                             const std::vector<std::string>& names,
                             const std::vector<std::vector<double>>& values, double duration) {
  std::string out = "<" + tag;
  for (size_t i = 0; i < names.size(); ++i)
    out += " " + names[i] + "=\"" + fixed(values[i].front(), 5) + "\"";
  out += " " + style + ">";
  for (size_t i = 0; i < names.size(); ++i) {
    std::string list;
    for (const double v : values[i]) list += (list.empty() ? "" : ";") + fixed(v, 5);
    out += "<animate attributeName=\"" + names[i] + "\" dur=\"" + fixed(duration, 6) +
           "s\" repeatCount=\"indefinite\" values=\"" + list + "\"/>";
  }
  return out + "</" + tag + ">\n";
}

// Two orthographic views side by side (side: x right, z up; front: y to the viewer's right),
// animated over the frames with SMIL, looping: the bodies (each limb in its colour: the lines of
// a body whose name starts with r_ or l_ in the right or left colour), the joints as small
// circles, the centre of mass and the exact ZMP (on the floor).
std::string animated_drawing(const std::string& title, const std::vector<StickFrame>& frames,
                             const std::vector<std::string>& colours, double duration) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (const StickFrame& f : frames)
    for (const auto& l : f.lines)
      for (int i = 0; i < 6; ++i)
        lo[i % 3] = std::min(lo[i % 3], l[static_cast<size_t>(i)]),
               hi[i % 3] = std::max(hi[i % 3], l[static_cast<size_t>(i)]);
  const double scale = 1500, pad = 20;  // px per m
  const double side_w = (hi[0] - lo[0]) * scale + 2 * pad,
               front_w = (hi[1] - lo[1]) * scale + 2 * pad;
  const double h = (hi[2] - lo[2]) * scale + 2 * pad + 50;
  const std::string key =
      "right limbs red, left limbs green; orange disc: centre of mass; black dot: exact ZMP on "
      "the floor";
  const std::string w = fixed(std::max(side_w + front_w, 2 * pad + 6.5 * key.size()), 6);
  std::string out = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + w + "\" height=\"" +
                    fixed(h, 6) + "\" viewBox=\"0 0 " + w + " " + fixed(h, 6) + "\">\n<title>" +
                    report::xml_escape(title) +
                    "</title>\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  out += "<text x=\"" + fixed(pad, 4) + "\" y=\"18\" font-size=\"14\">" +
         report::xml_escape(title) + " (side view | front view)</text>\n";
  out += "<text x=\"" + fixed(pad, 4) + "\" y=\"" + fixed(h - 8, 6) +
         "\" font-size=\"12\" fill=\"#555\">" + key + "</text>\n";
  const double floor_y = 30 + pad + hi[2] * scale;
  out += "<line x1=\"0\" y1=\"" + fixed(floor_y, 6) + "\" x2=\"" + w + "\" y2=\"" +
         fixed(floor_y, 6) + "\" stroke=\"#999\"/>\n";
  const size_t nl = frames.front().lines.size();
  for (int view = 0; view < 2; ++view) {
    const size_t axis = view == 0 ? 0 : 1;
    const double x0 = view == 0 ? pad - lo[0] * scale : side_w + pad - lo[1] * scale;
    auto across = [&](double v) { return x0 + v * scale; };
    auto up = [&](double z) { return floor_y - z * scale; };
    for (size_t k = 0; k < nl; ++k) {
      std::vector<std::vector<double>> v(4);
      for (const StickFrame& f : frames) {
        const auto& l = f.lines[k];
        v[0].push_back(across(l[axis])), v[1].push_back(up(l[2]));
        v[2].push_back(across(l[3 + axis])), v[3].push_back(up(l[5]));
      }
      out += animated_element(
          "line", "stroke=\"" + colours[k] + "\" stroke-width=\"3\" stroke-linecap=\"round\"",
          {"x1", "y1", "x2", "y2"}, v, duration);
      out += animated_element("circle",
                              "class=\"joint\" r=\"2.5\" fill=\"white\" stroke=\"#333\" "
                              "stroke-width=\"1\"",
                              {"cx", "cy"}, {v[2], v[3]}, duration);
    }
    std::vector<std::vector<double>> com(2), zmp(2);
    for (const StickFrame& f : frames) {
      com[0].push_back(across(f.com[axis])), com[1].push_back(up(f.com[2]));
      zmp[0].push_back(across(f.zmp[axis])), zmp[1].push_back(floor_y);
    }
    out += animated_element("circle",
                            "class=\"com\" r=\"6\" fill=\"#e67e22\" stroke=\"black\" "
                            "stroke-width=\"1\"",
                            {"cx", "cy"}, com, duration);
    out += animated_element("circle", "class=\"zmp\" r=\"4\" fill=\"black\"", {"cx", "cy"}, zmp,
                            duration);
  }
  return out + "</svg>\n";
}

spatial::SupportKernelLoads numeric_loads(const spatial::FloatingBaseLoads& loads) {
  return {loads.torque, loads.floor};
}

int run_humanoid_gait(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  if (!args.has("--out")) throw UsageError("missing --out DIR");
  const std::string dir = args.get("--out");
  // The folder exists and can be written, checked before the minutes of computing.
  report::check_output_path(dir + "/gait.csv");
  const int per_step = args.integer("--samples-per-step", 50);
  if (per_step < 2) throw UsageError("--samples-per-step must be at least 2");
  const double stall = args.number("--stall-torque", 1.5);
  const std::string solver_name = args.get("--solver", "generated");
  if (solver_name != "generated" && solver_name != "numeric")
    throw UsageError("--solver must be generated or numeric");
  g_current_file = path;
  const SpatialModel model = read_spatial_model(path);
  std::vector<double> parameters = model.common.default_parameters();
  apply_overrides(model, args.all("--set"), parameters);
  const spatial::SpatialSolver solver(model, parameters);
  const spatial::HumanoidGait gait(solver, spatial::gait_settings(solver),
                                   args.get("--waist", "vFB"), args.get("--right-foot", "vRL"),
                                   args.get("--left-foot", "vLL"));
  const SpatialGraph& g = solver.graph();
  const double gravity = -solver.instance().gravity[2];
  // Per support side: the generated single-support kernel (--solver generated).
  std::vector<SpatialModel> welded;
  std::vector<spatial::SupportKernel> kernels;
  if (solver_name == "generated") {
    for (int side = 0; side < 2; ++side) {
      const int foot = model.pose_drivers[static_cast<size_t>(gait.foot_driver(side))].second;
      const std::string& name = model.bodies[static_cast<size_t>(foot)].name;
      welded.push_back(weld_support(model, name));
      kernels.emplace_back(solver, welded.back(), foot, ondemand::kernel_for(welded.back(), name));
    }
  }
  std::vector<int> real;
  for (size_t j = 0; j < model.joints.size(); ++j)
    if (!model.joints[j].is_virtual) real.push_back(static_cast<int>(j));

  report::CsvTable table;
  table.header = {"t", "step", "support"};
  for (const int j : real)
    for (const char* k : {".q", ".qd", ".torque"})
      table.header.push_back(model.joints[static_cast<size_t>(j)].name + k);
  // Every real body's pose (centre of mass and frame orientation, as a spatial sweep's), so that
  // `mechgen view MODEL.yaml --csv gait.csv` animates the gait from this file.
  std::vector<int> posed;
  for (size_t b = 0; b < model.bodies.size(); ++b)
    if (!model.bodies[b].ground && !model.bodies[b].is_virtual)
      posed.push_back(static_cast<int>(b));
  for (const int b : posed)
    for (const char* k : {".x", ".y", ".z", ".qw", ".qx", ".qy", ".qz"})
      table.header.push_back(model.bodies[static_cast<size_t>(b)].name + k);
  for (const char* k :
       {"com.x", "com.y", "com.z", "floor.fx", "floor.fy", "floor.fz", "floor.mx", "floor.my",
        "floor.mz", "zmp_planned.x", "zmp_planned.y", "zmp_lip.x", "zmp_lip.y", "zmp_exact.x",
        "zmp_exact.y", "zmp_difference", "margin_lip", "margin_exact"})
    table.header.push_back(k);

  const double T = gait.settings().step_time;
  const int n = gait.settings().steps * per_step;
  spatial::SpatialState s;
  std::vector<double> peak(model.joints.size(), 0.0), peak_t(model.joints.size(), 0.0);
  double worst_diff = 0, worst_diff_t = 0, min_lip = INFINITY, min_exact = INFINITY;
  double min_lip_t = 0, min_exact_t = 0, worst_closure = 0;
  std::vector<std::vector<V3>> prints;
  std::vector<StickFrame> frames;
  for (int i = 0; i < n; ++i) {
    // Inside each step (a support switch is an instant with both feet down).
    const double t = T * (i / per_step) + T * ((i % per_step) + 0.5) / per_step;
    gait.solve(t, s);
    worst_closure = std::max(worst_closure, (solver.network(s) * s.qd).cwiseAbs().maxCoeff());
    const int side = gait.support(t);
    const int foot = model.pose_drivers[static_cast<size_t>(gait.foot_driver(side))].second;
    const spatial::SupportKernelLoads loads =
        kernels.empty() ? numeric_loads(spatial::single_support_dynamics(solver, s, foot))
                        : kernels[static_cast<size_t>(side)].loads(s);
    const spatial::CentreOfMass c = spatial::centre_of_mass(solver, s);
    std::vector<V3> sole;
    for (const V3& p : solver.instance().points[static_cast<size_t>(foot)])
      sole.push_back(solver.point_position(s, foot, p));
    const std::vector<V3> polygon = spatial::convex_hull_xy(sole);
    if (i % per_step == 0) prints.push_back(polygon);
    const double floor_z = sole.empty() ? 0 : sole[0][2];
    const V3 lip = spatial::lip_zmp(c.p, c.a, gravity, floor_z);
    const V3 exact = spatial::zmp_of(loads.floor, floor_z);
    if (i % std::max(1, per_step / 10) == 0) {
      StickFrame frame{{}, {}, c.p, exact};
      frame.lines = stick_figure(solver, s, frame.bodies);
      frames.push_back(frame);
    }
    const V3 planned = gait.planned_zmp(t);
    const double diff = std::hypot(exact[0] - lip[0], exact[1] - lip[1]);
    const double m_lip = spatial::polygon_margin(polygon, lip);
    const double m_exact = spatial::polygon_margin(polygon, exact);
    if (diff > worst_diff) worst_diff = diff, worst_diff_t = t;
    if (m_lip < min_lip) min_lip = m_lip, min_lip_t = t;
    if (m_exact < min_exact) min_exact = m_exact, min_exact_t = t;
    std::vector<double> row{t, static_cast<double>(gait.step_index(t)), static_cast<double>(side)};
    for (const int j : real) {
      const int col = g.joint_column[static_cast<size_t>(j)];
      const double tau = loads.torque[static_cast<size_t>(j)];
      row.insert(row.end(), {s.q[col], s.qd[col], tau});
      if (std::abs(tau) > peak[static_cast<size_t>(j)])
        peak[static_cast<size_t>(j)] = std::abs(tau), peak_t[static_cast<size_t>(j)] = t;
    }
    for (const int b : posed) {
      const geometry::Pose<double> frame = solver.body_pose(s, b);
      const V3 at = geometry::apply(frame, solver.instance().com[static_cast<size_t>(b)]);
      const std::array<double, 4> q = spatial::quaternion(frame.R);
      row.insert(row.end(), {at[0], at[1], at[2], q[0], q[1], q[2], q[3]});
    }
    row.insert(row.end(),
               {c.p[0], c.p[1], c.p[2], loads.floor.f[0], loads.floor.f[1], loads.floor.f[2],
                loads.floor.m[0], loads.floor.m[1], loads.floor.m[2], planned[0], planned[1],
                lip[0], lip[1], exact[0], exact[1], diff, m_lip, m_exact});
    table.rows.push_back(row);
  }
  g_current_file = dir + "/gait.csv";
  report::write_csv(table, dir + "/gait.csv");

  auto column = [&](const std::string& name) { return table.values(table.require_column(name)); };
  const std::vector<double> time = column("t");
  auto joint_plot = [&](const std::string& file, const std::string& title,
                        const std::string& suffix, const std::string& unit,
                        const std::vector<std::string>& prefixes, bool stall_lines) {
    report::PlotSpec spec;
    spec.title = title;
    spec.x_label = "time t [s]";
    spec.y_label = unit;
    spec.width = 1000;
    for (const int j : real) {
      const std::string& name = model.joints[static_cast<size_t>(j)].name;
      for (const std::string& p : prefixes)
        if (name.rfind(p, 0) == 0) spec.series.push_back(series(name, time, column(name + suffix)));
    }
    if (stall_lines) {
      spec.series.push_back(series("+stall", {time.front(), time.back()}, {stall, stall}));
      spec.series.push_back(series("-stall", {time.front(), time.back()}, {-stall, -stall}));
    }
    write_text(dir + "/" + file, report::render_svg(spec));
  };
  joint_plot("fig7_leg_angles.svg", model.common.name + ": leg joint angles (seed Fig. 7)", ".q",
             "angle [rad]", {"RL", "LL"}, false);
  joint_plot("fig8_leg_velocities.svg",
             model.common.name + ": leg joint velocities, Davies' method (seed Fig. 8)", ".qd",
             "angular velocity [rad/s]", {"RL", "LL"}, false);
  joint_plot("leg_torques.svg", model.common.name + ": leg joint torques, single support",
             ".torque", "torque [N m]", {"RL", "LL"}, true);
  joint_plot("arm_torques.svg", model.common.name + ": arm joint torques", ".torque",
             "torque [N m]", {"RA", "LA"}, false);
  for (const char* axis : {"x", "y"}) {
    report::PlotSpec spec;
    spec.title = model.common.name + ": ZMP " + axis +
                 ": planned, LIP-3D (whole-body CoM), exact (floor wrench)";
    spec.x_label = "time t [s]";
    spec.y_label = std::string("ZMP ") + axis + " [m]";
    spec.width = 1000;
    for (const char* k : {"zmp_planned.", "zmp_lip.", "zmp_exact."})
      spec.series.push_back(series(std::string(k) + axis, time, column(std::string(k) + axis)));
    spec.series.push_back(
        series(std::string("com.") + axis, time, column(std::string("com.") + axis)));
    write_text(dir + "/zmp_" + axis + ".svg", report::render_svg(spec));
  }
  {
    report::PlotSpec spec;
    spec.title = model.common.name + ": exact ZMP minus LIP-3D ZMP";
    spec.x_label = "time t [s]";
    spec.y_label = "difference [m]";
    spec.width = 1000;
    for (const char* axis : {"x", "y"}) {
      std::vector<double> d = column(std::string("zmp_exact.") + axis);
      const std::vector<double> l = column(std::string("zmp_lip.") + axis);
      for (size_t k = 0; k < d.size(); ++k) d[k] -= l[k];
      spec.series.push_back(series(std::string("exact - LIP, ") + axis, time, d));
    }
    write_text(dir + "/zmp_difference.svg", report::render_svg(spec));
  }
  {
    report::PlotSpec spec;
    spec.title = model.common.name + ": ZMP paths and footprints (top view)";
    spec.x_label = "x [m]";
    spec.y_label = "y [m]";
    spec.width = 1000;
    spec.height = 450;
    for (size_t k = 0; k < prints.size(); ++k) {
      report::Series p{"step " + std::to_string(k), {}, {}};
      for (size_t i = 0; i <= prints[k].size(); ++i) {
        p.x.push_back(prints[k][i % prints[k].size()][0]);
        p.y.push_back(prints[k][i % prints[k].size()][1]);
      }
      spec.series.push_back(p);
    }
    spec.series.push_back(series("LIP-3D", column("zmp_lip.x"), column("zmp_lip.y")));
    spec.series.push_back(series("exact", column("zmp_exact.x"), column("zmp_exact.y")));
    write_text(dir + "/zmp_path.svg", report::render_svg(spec));
  }

  write_text(
      dir + "/walk.svg",
      animated_drawing(model.common.name + ": " + std::to_string(gait.settings().steps) + " steps",
                       frames, line_colours(model, frames.front().bodies), gait.duration()));
  std::cout << "humanoid-gait " << model.common.name << ": " << gait.settings().steps
            << " steps of " << fixed(gait.settings().step_length, 4) << " m in " << fixed(T, 3)
            << " s (LIP: z_c " << fixed(gait.com_height(), 4) << " m, omega "
            << fixed(gait.omega(), 4) << " 1/s), " << n
            << " samples, numeric solver; single-support dynamics: "
            << (kernels.empty()
                    ? "numeric"
                    : "generated kernels " + welded[0].common.name + ", " + welded[1].common.name)
            << "\n";
  std::cout << "  closure: max |N q'| " << fixed(worst_closure, 3) << "\n";
  std::vector<int> order = real;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return peak[static_cast<size_t>(a)] > peak[static_cast<size_t>(b)];
  });
  std::vector<std::vector<std::string>> rows{
      {"joint", "peak |torque| [N m]", "at t [s]", "of stall"}};
  for (const int j : order)
    rows.push_back({model.joints[static_cast<size_t>(j)].name,
                    fixed(peak[static_cast<size_t>(j)], 4),
                    fixed(peak_t[static_cast<size_t>(j)], 4),
                    fixed(100 * peak[static_cast<size_t>(j)] / stall, 3) + " %"});
  std::cout << "  joint torques in single support (stall " << fixed(stall, 3) << " N m):\n"
            << cli::table(rows, "    ");
  std::cout << "  ZMP: largest |exact - LIP-3D| " << fixed(worst_diff, 4)
            << " m at t = " << fixed(worst_diff_t, 4) << " s (step "
            << gait.step_index(worst_diff_t) << ", phase "
            << fixed(std::fmod(worst_diff_t, T) / T, 3) << ")\n";
  std::cout << "  margin to the support polygon: LIP-3D " << fixed(min_lip, 4)
            << " m (t = " << fixed(min_lip_t, 4) << " s), exact " << fixed(min_exact, 4)
            << " m (t = " << fixed(min_exact_t, 4) << " s)"
            << (min_exact < 0 ? "  (exact ZMP leaves the foot)" : "") << "\n";
  std::cout << "wrote " << dir << "/gait.csv, 8 figures and the animated drawing walk.svg\n";
  return 0;
}

}  // namespace

Command humanoid_gait_command() {
  return {"humanoid-gait",
          "seed-001 humanoid walk: leg angles, velocities (Figs. 7-8), torques, ZMP two ways",
          kHumanoidGaitHelp,
          {{"--out", "-o", true},
           {"--samples-per-step", "", true},
           {"--stall-torque", "", true},
           {"--set", "", true, true},
           {"--waist", "", true},
           {"--right-foot", "", true},
           {"--left-foot", "", true},
           {"--solver", "", true}},
          &run_humanoid_gait,
          /*out_is_folder=*/true};
}

}  // namespace mechgen::cli
