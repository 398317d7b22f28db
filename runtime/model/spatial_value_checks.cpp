#include "model/spatial_value_checks.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>

namespace mechgen {

namespace {

std::string number_text(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

void check_body(const SpatialModel& model, const SpatialBody& b, const GiNaC::exmap& subs) {
  const SpatialMass& m = b.mass;
  const double mass = model.evaluate(m.mass, subs);
  if (!(mass >= 0))
    throw ModelError(m.loc,
                     "body '" + b.name + "' has a negative mass (" + number_text(mass) + " kg)");
  Eigen::Matrix3d inertia;
  for (int k = 0; k < 9; ++k)
    inertia(k / 3, k % 3) =
        model.evaluate({m.inertia[static_cast<size_t>(k)], "inertia", m.loc}, subs);
  const double scale = inertia.cwiseAbs().maxCoeff();
  // A massless body (a link only there to carry joints, as the Bioloid's wrists) has no inertia.
  if (mass == 0) {
    if (scale != 0)
      throw ModelError(m.loc, "body '" + b.name + "' has no mass but an inertia tensor");
    return;
  }
  if (!((inertia - inertia.transpose()).cwiseAbs().maxCoeff() <= 1e-12 * scale))
    throw ModelError(m.loc, "body '" + b.name + "': the inertia tensor is not symmetric");
  // Principal moments in increasing order.
  const Eigen::Vector3d moments =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(inertia, Eigen::EigenvaluesOnly).eigenvalues();
  // Positive semi-definite: a point mass (all moments 0) and a thin rod (one moment 0) are
  // rigid bodies too, and models of statics use them.
  if (!(moments[0] >= -1e-12 * scale))
    throw ModelError(m.loc, "body '" + b.name +
                                "': the inertia tensor has a negative principal moment (" +
                                number_text(moments[0]) + " kg m^2)");
  if (!(moments[0] + moments[1] >= moments[2] * (1 - 1e-9)))
    throw ModelError(m.loc, "body '" + b.name + "': principal moments " + number_text(moments[0]) +
                                ", " + number_text(moments[1]) + ", " + number_text(moments[2]) +
                                " kg m^2 violate the triangle inequality (I1 + I2 >= I3)");
}

}  // namespace

void check_spatial_values(const SpatialModel& model, const std::vector<double>& parameters) {
  const Model& common = model.common;
  try {
    const GiNaC::exmap subs = common.substitutions(parameters);
    for (const SpatialBody& b : model.bodies)
      if (!b.ground && !b.is_virtual) check_body(model, b, subs);
  } catch (const ModelError& error) {
    std::string changed;
    for (size_t i = 0; i < parameters.size() && i < common.parameters.size(); ++i)
      if (!(parameters[i] == common.parameters[i].value))
        changed += (changed.empty() ? " (with " : ", ") + common.parameters[i].name + " = " +
                   number_text(parameters[i]);
    if (changed.empty()) throw;
    const std::string what = error.what();
    const auto split = what.find(": error: ");
    throw ModelError(error.where(),
                     (split == what.npos ? what : what.substr(split + 9)) + changed + ")");
  }
}

void apply_overrides(const SpatialModel& model, const std::vector<std::string>& overrides,
                     std::vector<double>& values) {
  apply_overrides(model.common, overrides, values);
  if (!overrides.empty()) check_spatial_values(model, values);
}

}  // namespace mechgen
