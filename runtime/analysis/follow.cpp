// A twin with joint drivers following a pose-driven spatial model (follow.hpp).
#include "analysis/follow.hpp"

#include <algorithm>
#include <cmath>

#include "spatial/driven_solve.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_solver.hpp"

namespace mechgen::analysis {

FollowResult follow(const SpatialModel& driven, const SpatialModel& twin,
                    const FollowOptions& options) {
  const spatial::SpatialSolver ik(driven, options.parameters);
  const spatial::SpatialSolver fk(twin, options.twin_parameters);
  const SpatialGraph& g = fk.graph();
  // Per twin primary: its column in the pose-driven model.
  std::vector<int> source;
  FollowResult r;
  r.columns.push_back("t");
  for (const int c : g.primary) {
    const SpatialColumn& col = g.columns[static_cast<size_t>(c)];
    if (col.driver < 0)
      throw ModelError(twin.pose_drivers.front().loc, "the twin must have joint drivers only");
    const SpatialDriver& d = twin.drivers[static_cast<size_t>(col.driver)];
    const std::string& joint = twin.joints[static_cast<size_t>(d.joint)].name;
    const int j = driven.joint_index(joint);
    if (j < 0)
      throw ModelError(
          d.loc, "driver '" + d.name + "': joint '" + joint + "' is not in " + driven.common.file);
    source.push_back(ik.graph().joint_column[static_cast<size_t>(j)] + col.index);
    for (const char* s : {".q", ".qd", ".qdd", ".effort"}) r.columns.push_back(d.name + s);
  }
  const GiNaC::exmap subs = driven.common.substitutions(ik.parameters());
  const double t0 = driven.evaluate(driven.common.step.t0, subs);
  const double t1 = driven.evaluate(driven.common.step.t1, subs);
  spatial::SpatialState s, twin_state;
  fk.solve(twin.evaluate(twin.common.step.t0, twin.common.substitutions(fk.parameters())),
           twin_state);
  const auto n = static_cast<Eigen::Index>(source.size());
  Eigen::VectorXd q(n), qd(n), qdd(n);
  // The pose-driven model is followed in steps of at most 1/256 of the step's duration whatever
  // the samples asked for: from a sample far back its Newton-Raphson may land on another
  // assembly branch (seen with 5 samples of the quadruped swing, depending on round-off).
  const double max_dt = (t1 - t0) / 256;
  double t_prev = t0;
  for (int k = 0; k < options.samples; ++k) {
    const double t = options.samples == 1 ? t0 : t0 + (t1 - t0) * k / (options.samples - 1);
    const int substeps =
        k == 0 ? 1 : std::max(1, static_cast<int>(std::ceil((t - t_prev) / max_dt)));
    for (int i = 1; i < substeps; ++i) ik.solve(t_prev + (t - t_prev) * i / substeps, s);
    ik.solve(t, s);
    t_prev = t;
    for (Eigen::Index i = 0; i < n; ++i) {
      const int c = source[static_cast<size_t>(i)];
      q[i] = s.q[c], qd[i] = s.qd[c], qdd[i] = s.qdd[c];
    }
    // Short continuation steps keep the twin on the pose-driven model's branch.
    spatial::solve_at(fk, q, qd, qdd, twin_state, 0.01);
    twin_state.t = t;
    const spatial::SpatialLoads loads = spatial::inverse_dynamics(fk, twin_state);
    std::vector<double> row{t};
    for (Eigen::Index i = 0; i < n; ++i)
      row.insert(row.end(), {q[i], qd[i], qdd[i], loads.effort[i]});
    r.rows.push_back(row);
  }
  return r;
}

}  // namespace mechgen::analysis
