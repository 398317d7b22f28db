// The derivation's definitions and outputs evaluated numerically (GiNaC, 17 digits), for tests
// that compare a derivation with the numeric solver.
#pragma once

#include <ginac/ginac.h>

#include <Eigen/Dense>
#include <map>
#include <string>
#include <vector>

#include "model/spatial_graph.hpp"
#include "model/spatial_model.hpp"

namespace mechgen::gen {

using Values = std::map<std::string, double>;

inline double evaluate(const GiNaC::ex& e, const Values& values) {
  GiNaC::exmap subs;
  for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (GiNaC::is_a<GiNaC::symbol>(*it))
      subs[*it] = values.at(GiNaC::ex_to<GiNaC::symbol>(*it).get_name());
  return GiNaC::ex_to<GiNaC::numeric>(GiNaC::evalf(e.subs(subs))).to_double();
}

// The kernel's inputs: parameters as `p.<name>`, each driver's coordinate and rates as `in.<d>`,
// the time as `in.t` (applied loads read it).
inline Values input_values(const SpatialModel& model, const SpatialGraph& graph,
                           const std::vector<double>& parameters, const Eigen::VectorXd& q,
                           const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd, double t = 0) {
  Values values{{"in.t", t}};
  for (size_t i = 0; i < parameters.size(); ++i)
    values["p." + model.common.parameters[i].name] = parameters[i];
  for (const SpatialDriver& dr : model.drivers) {
    const int c = graph.joint_column[static_cast<size_t>(dr.joint)] + dr.column;
    values["in." + dr.name] = q[c];
    values["in." + dr.name + "_d"] = qd[c];
    values["in." + dr.name + "_dd"] = qdd[c];
  }
  return values;
}

}  // namespace mechgen::gen
