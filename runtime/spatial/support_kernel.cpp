// Single-support inverse dynamics through the generated kernel (support_kernel.hpp).
#include "spatial/support_kernel.hpp"

#include <cmath>
#include <cstdio>

#include "model/support_model.hpp"

namespace mechgen::spatial {

namespace {

int column_index(const CompiledKernel& kernel, const std::string& name, const SourceLoc& file) {
  for (int c = 0; c < kernel.column_count; ++c)
    if (name == kernel.column_names[c]) return c;
  throw ModelError(file, "the single-support kernel '" + std::string(kernel.model) +
                             "' has no column '" + name + "' (rebuild to regenerate it)");
}

}  // namespace

SupportKernel::SupportKernel(const SpatialSolver& solver, const SpatialModel& welded, int support,
                             const CompiledKernel& kernel)
    : solver_(solver), kernel_(kernel), support_(support) {
  const SpatialModel& model = solver.model();
  const SourceLoc file{model.common.file, 0, 0};
  const std::string& foot = model.bodies[static_cast<size_t>(support)].name;
  if (welded.common.name != support_model_name(model.common.name, foot) ||
      welded.common.name != kernel.model ||
      kernel.parameter_count != static_cast<int>(welded.common.parameters.size()) ||
      kernel.driver_count != static_cast<int>(welded.drivers.size()))
    throw ModelError(file, "the kernel '" + std::string(kernel.model) +
                               "' is not the single-support kernel of '" + model.common.name +
                               "' on '" + foot + "' (rebuild to regenerate it)");
  const GiNaC::exmap values = model.common.substitutions(solver.parameters());
  for (const PoseDriver& pd : model.pose_drivers)
    if (pd.second == support && pd.first == model.ground)
      at_ = {model.evaluate(pd.at.x, values), model.evaluate(pd.at.y, values),
             model.evaluate(pd.at.z, values)};
  params_ = solver.parameters();
  placement_ = params_.size();
  params_.resize(welded.common.parameters.size(), 0.0);
  for (const SpatialDriver& d : welded.drivers) {
    const int j = model.joint_index(welded.joints[static_cast<size_t>(d.joint)].name);
    joint_.push_back(j);
    column_.push_back(solver.graph().joint_column[static_cast<size_t>(j)] + d.column);
    effort_.push_back(column_index(kernel, d.name + ".effort", file));
  }
  weld_ = column_index(kernel, support_weld_name(foot) + ".fx", file);
}

SupportKernelLoads SupportKernel::loads(const SpatialState& s) const {
  const SpatialModel& model = solver_.model();
  const Pose& D = s.D[static_cast<size_t>(support_)];
  // Flat: the foot's rotation is a turn about z (gravity and the floor normal along z).
  const double tilt = std::hypot(D.R(2, 0), D.R(2, 1), std::hypot(D.R(0, 2), D.R(1, 2)));
  if (!(tilt <= 1e-9)) {
    char text[96];
    std::snprintf(text, sizeof text, "%.3g", tilt);
    throw ModelError({model.common.file, 0, 0},
                     "t = " + std::to_string(s.t) + ": the support foot '" +
                         model.bodies[static_cast<size_t>(support_)].name +
                         "' is not flat on the floor (tilt " + text +
                         "): the single-support kernel stands it on a level floor");
  }
  std::vector<double> params = params_;
  const V3 at = geometry::apply(D, at_);
  for (size_t i = 0; i < 3; ++i) params[placement_ + i] = at[i];
  params[placement_ + 3] = std::atan2(D.R(1, 0), D.R(0, 0));
  std::vector<double> drivers;
  for (const int c : column_) drivers.insert(drivers.end(), {s.q[c], s.qd[c], s.qdd[c]});
  std::vector<double> row(static_cast<size_t>(kernel_.column_count));
  int group = -1;
  const int status =
      kernel_.evaluate_driven_double(params.data(), s.t, drivers.data(), row.data(), &group);
  if (status != 0)
    throw ModelError({model.common.file, 0, 0},
                     "t = " + std::to_string(s.t) + ": the single-support kernel '" +
                         kernel_.model + "' failed" +
                         (group >= 0 && group < kernel_.group_count
                              ? std::string(" in ") + kernel_.group_names[group]
                              : std::string()) +
                         (status == 3 ? " (a non-finite result)" : ""));
  SupportKernelLoads out;
  out.torque.assign(model.joints.size(), 0.0);
  for (size_t k = 0; k < joint_.size(); ++k)
    out.torque[static_cast<size_t>(joint_[k])] = row[static_cast<size_t>(effort_[k])];
  const auto w = static_cast<size_t>(weld_);
  out.floor.f = {row[w], row[w + 1], row[w + 2]};
  // The weld's moment is about its point, the support's `at` point: about the origin instead.
  out.floor.m = V3{row[w + 3], row[w + 4], row[w + 5]} + geometry::cross(at, out.floor.f);
  return out;
}

}  // namespace mechgen::spatial
