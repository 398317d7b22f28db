// The spatial sweep: one row of DESIGN.md's spatial columns per sample (spatial_sweep.hpp).
#include "spatial/spatial_sweep.hpp"

#include <algorithm>
#include <sstream>

#include "numeric/mass_bias.hpp"
#include "spatial/spatial_mass_matrix.hpp"

#include "model/spatial_graph.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {

std::vector<std::string> spatial_column_names(const SpatialModel& model) {
  std::vector<std::string> cols{"t"};
  for (const SpatialDriver& d : model.drivers)
    for (const char* s : {".q", ".qd", ".qdd", ".effort"}) cols.push_back(d.name + s);
  for (const PoseDriver& pd : model.pose_drivers)
    for (const PoseCoordinate& c : pd.coordinates)
      if (c.value)
        for (const char* s : {".q", ".qd", ".qdd", ".effort"})
          cols.push_back(pd.name + "." + c.name + s);
  for (const SpatialBody& b : model.bodies) {
    if (b.ground || b.is_virtual) continue;
    for (const char* s : {".x", ".y", ".z", ".qw", ".qx", ".qy", ".qz", ".vx", ".vy", ".vz", ".ax",
                          ".ay", ".az", ".wx", ".wy", ".wz", ".alx", ".aly", ".alz"})
      cols.push_back(b.name + s);
  }
  for (const auto& [point, body] : model.named_points())
    for (const char* s : {".x", ".y", ".z"}) cols.push_back(point + s);
  for (const SpatialJoint& j : model.joints) {
    if (j.is_virtual) continue;
    for (size_t k = 0; k < j.columns.size(); ++k) {
      const std::string q = j.columns.size() == 1 ? ".q" : ".q" + std::to_string(k + 1);
      for (const char* s : {"", "d", "dd"}) cols.push_back(j.name + q + s);
    }
    for (const char* s : {".fx", ".fy", ".fz", ".mx", ".my", ".mz"}) cols.push_back(j.name + s);
  }
  // Appended after the original columns, so a script reading them by position reads the same.
  for (const auto& [point, body] : model.named_points())
    for (const char* s : {".vx", ".vy", ".vz", ".ax", ".ay", ".az"}) cols.push_back(point + s);
  return cols;
}

SpatialSweepOptions default_spatial_sweep(const SpatialModel& model,
                                          const std::vector<double>& parameters) {
  SpatialSweepOptions o;
  o.parameters = parameters.empty() ? model.common.default_parameters() : parameters;
  const GiNaC::exmap subs = model.common.substitutions(o.parameters);
  o.t0 = model.evaluate(model.common.step.t0, subs);
  o.t1 = model.evaluate(model.common.step.t1, subs);
  o.samples = model.common.step.samples;
  return o;
}

std::vector<SpatialDriverGroup> spatial_driver_groups(const SpatialSolver& solver) {
  const SpatialModel& model = solver.model();
  const SpatialGraph& graph = solver.graph();
  const GiNaC::exmap subs = model.common.substitutions(solver.parameters());
  std::vector<int> primary_index(static_cast<size_t>(graph.cols()), -1);
  for (size_t k = 0; k < graph.primary.size(); ++k)
    primary_index[static_cast<size_t>(graph.primary[k])] = static_cast<int>(k);
  std::vector<SpatialDriverGroup> out;
  auto add = [&](const std::string& name, int column, double offset) {
    out.push_back({name, column, primary_index[static_cast<size_t>(column)], offset});
  };
  for (const SpatialDriver& d : model.drivers)
    add(d.name, graph.joint_column[static_cast<size_t>(d.joint)] + d.column, 0);
  for (const PoseDriver& pd : model.pose_drivers)
    for (const PoseCoordinate& c : pd.coordinates)
      if (c.value)
        add(pd.name + "." + c.name, graph.joint_column[static_cast<size_t>(c.joint)],
            model.evaluate({c.reference, "reference", pd.loc}, subs));
  return out;
}

std::vector<double> spatial_sweep_row(const SpatialSolver& solver,
                                      const std::vector<SpatialDriverGroup>& groups,
                                      const SpatialState& state, const SpatialLoads& loads) {
  const SpatialModel& model = solver.model();
  const SpatialGraph& graph = solver.graph();
  const SpatialInstance& in = solver.instance();
  std::vector<double> row{state.t};
  for (const SpatialDriverGroup& d : groups) {
    const auto c = static_cast<Eigen::Index>(d.column);
    row.insert(row.end(),
               {state.q[c] + d.offset, state.qd[c], state.qdd[c], loads.effort[d.primary]});
  }
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    if (model.bodies[b].ground || model.bodies[b].is_virtual) continue;
    const int bi = static_cast<int>(b);
    const Pose frame = solver.body_pose(state, bi);
    const V3 c = geometry::apply(frame, in.com[b]);
    const std::array<double, 4> q = quaternion(frame.R);
    const V3 v = solver.point_velocity(state, bi, in.com[b]);
    const V3 a = solver.point_acceleration(state, bi, in.com[b]);
    const V3 w = state.V[b].w, al = state.A[b].w;
    row.insert(row.end(), {c[0], c[1], c[2], q[0], q[1], q[2], q[3], v[0], v[1], v[2], a[0], a[1],
                           a[2], w[0], w[1], w[2], al[0], al[1], al[2]});
  }
  // Named point i's body and its position in that body's frame.
  std::vector<std::pair<int, const V3*>> points;
  for (const auto& [point, body] : model.named_points()) {
    const SpatialBody& sb = model.bodies[static_cast<size_t>(body)];
    size_t k = 0;
    while (sb.points[k].name != point) ++k;
    points.emplace_back(body, &in.points[static_cast<size_t>(body)][k]);
  }
  for (const auto& [body, local] : points) {
    const V3 x = solver.point_position(state, body, *local);
    row.insert(row.end(), {x[0], x[1], x[2]});
  }
  for (size_t j = 0; j < model.joints.size(); ++j) {
    if (model.joints[j].is_virtual) continue;
    for (size_t k = 0; k < model.joints[j].columns.size(); ++k) {
      const auto c = static_cast<Eigen::Index>(graph.joint_column[j] + static_cast<int>(k));
      row.insert(row.end(), {state.q[c], state.qd[c], state.qdd[c]});
    }
    const Wrench& r = loads.reaction[j];
    row.insert(row.end(), {r.f[0], r.f[1], r.f[2], r.m[0], r.m[1], r.m[2]});
  }
  for (const auto& [body, local] : points) {
    const V3 v = solver.point_velocity(state, body, *local);
    const V3 a = solver.point_acceleration(state, body, *local);
    row.insert(row.end(), {v[0], v[1], v[2], a[0], a[1], a[2]});
  }
  return row;
}

void check_table_times(const SpatialModel& model, const SpatialSweepOptions& options) {
  const double lo = std::min(options.t0, options.t1), hi = std::max(options.t0, options.t1);
  for (const SpatialDriver& d : model.drivers) {
    if (!d.table) continue;
    const CubicSpline& s = *d.table->spline;
    const double slack = 1e-12 * (s.back() - s.front());
    if (lo >= s.front() - slack && hi <= s.back() + slack) continue;
    std::ostringstream m;
    m.precision(17);
    m << "driver '" << d.name << "': the sweep's time range [" << lo << ", " << hi
      << "] s is not within its table's [" << s.front() << ", " << s.back() << "] s ('"
      << d.table->file << "'; a table is not extrapolated: choose t0 and t1 within it)";
    throw ModelError(d.value.loc, m.str());
  }
}

SpatialSweepResult run_spatial_sweep(const SpatialModel& model,
                                     const SpatialSweepOptions& options) {
  check_table_times(model, options);
  const SpatialSolver solver(model, options.parameters);
  const std::vector<SpatialDriverGroup> groups = spatial_driver_groups(solver);
  SpatialSweepResult result;
  result.columns = spatial_column_names(model);
  if (options.mass_matrix) {
    std::vector<std::string> names;
    for (const SpatialDriverGroup& d : groups) names.push_back(d.name);
    for (std::string& c : numeric::mass_bias_columns(names)) result.columns.push_back(c);
  }
  SpatialState state;
  for (int i = 0; i < options.samples; ++i) {
    const double t = options.samples == 1 ? options.t0
                     : i == options.samples - 1
                         ? options.t1
                         : options.t0 + (options.t1 - options.t0) * i / (options.samples - 1);
    solver.solve(t, state);
    std::vector<double> row =
        spatial_sweep_row(solver, groups, state, inverse_dynamics(solver, state));
    if (options.mass_matrix) {
      // In graph().primary order, reordered to the groups' (column) order.
      Eigen::VectorXd qpd(static_cast<Eigen::Index>(groups.size()));
      for (const SpatialDriverGroup& d : groups) qpd[d.primary] = state.qd[d.column];
      const MassBias primary = mass_matrix_bias(solver, state, qpd);
      MassBias mb{Eigen::MatrixXd(qpd.size(), qpd.size()), Eigen::VectorXd(qpd.size())};
      for (size_t a = 0; a < groups.size(); ++a) {
        mb.h[static_cast<Eigen::Index>(a)] = primary.h[groups[a].primary];
        for (size_t b = 0; b < groups.size(); ++b)
          mb.M(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) =
              primary.M(groups[a].primary, groups[b].primary);
      }
      numeric::append_mass_bias(mb, row);
    }
    result.rows.push_back(std::move(row));
  }
  return result;
}

}  // namespace mechgen::spatial
