// The spatial sweep: one row of DESIGN.md's spatial columns per sample (spatial_sweep.hpp).
#include "spatial/spatial_sweep.hpp"

#include "model/spatial_graph.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {

namespace {

// The driver groups in output order: joint drivers, then each pose driver's prescribed
// coordinates; each is one primary column.
struct DriverGroup {
  std::string name;
  int column = -1;
  double offset = 0;  // added to the column's q (a pose coordinate's reference value)
};

std::vector<DriverGroup> driver_groups(const SpatialModel& model, const SpatialGraph& graph,
                                       const GiNaC::exmap& subs) {
  std::vector<DriverGroup> out;
  for (const SpatialDriver& d : model.drivers)
    out.push_back({d.name, graph.joint_column[static_cast<size_t>(d.joint)] + d.column, 0});
  for (const PoseDriver& pd : model.pose_drivers)
    for (const PoseCoordinate& c : pd.coordinates)
      if (c.value)
        out.push_back({pd.name + "." + c.name, graph.joint_column[static_cast<size_t>(c.joint)],
                       model.evaluate({c.reference, "reference", pd.loc}, subs)});
  return out;
}

}  // namespace

std::vector<std::string> spatial_column_names(const SpatialModel& model) {
  const SpatialGraph graph = build_spatial_graph(model);
  std::vector<std::string> cols{"t"};
  for (const DriverGroup& d :
       driver_groups(model, graph, model.common.substitutions(model.common.default_parameters())))
    for (const char* s : {".q", ".qd", ".qdd", ".effort"}) cols.push_back(d.name + s);
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

SpatialSweepResult run_spatial_sweep(const SpatialModel& model,
                                     const SpatialSweepOptions& options) {
  const SpatialSolver solver(model, options.parameters);
  const SpatialGraph& graph = solver.graph();
  const std::vector<DriverGroup> groups =
      driver_groups(model, graph, model.common.substitutions(solver.parameters()));
  std::vector<int> primary_index(static_cast<size_t>(graph.cols()), -1);
  for (size_t k = 0; k < graph.primary.size(); ++k)
    primary_index[static_cast<size_t>(graph.primary[k])] = static_cast<int>(k);
  SpatialSweepResult result;
  result.columns = spatial_column_names(model);
  SpatialState state;
  const SpatialInstance& in = solver.instance();
  for (int i = 0; i < options.samples; ++i) {
    const double t = options.samples == 1 ? options.t0
                     : i == options.samples - 1
                         ? options.t1
                         : options.t0 + (options.t1 - options.t0) * i / (options.samples - 1);
    solver.solve(t, state);
    const SpatialLoads loads = inverse_dynamics(solver, state);
    std::vector<double> row{t};
    for (const DriverGroup& d : groups) {
      const auto c = static_cast<Eigen::Index>(d.column);
      row.insert(row.end(), {state.q[c] + d.offset, state.qd[c], state.qdd[c],
                             loads.effort[primary_index[static_cast<size_t>(d.column)]]});
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
    for (const auto& [point, body] : model.named_points()) {
      const SpatialBody& sb = model.bodies[static_cast<size_t>(body)];
      size_t k = 0;
      while (sb.points[k].name != point) ++k;
      const V3 x = solver.point_position(state, body, in.points[static_cast<size_t>(body)][k]);
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
    result.rows.push_back(std::move(row));
  }
  return result;
}

}  // namespace mechgen::spatial
