// The derivation's definitions and outputs evaluated numerically (GiNaC, 17 digits), for tests
// that compare a derivation with the numeric solver.
#pragma once

#include <ginac/ginac.h>

#include <Eigen/Dense>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "model/spatial_graph.hpp"
#include "model/spatial_model.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial_derivation.hpp"

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

// Every definition of `d` evaluated at a state the numeric solver solved: the inputs, the Newton
// coordinates' and the closed-form angles' warm starts at the solved coordinates (no rates: the
// prediction is the warm start itself), so every root taken is the solver's.
inline Values derivation_values(const SpatialModel& model, const SpatialGraph& graph,
                                const SpatialDerivation& d, const std::vector<double>& parameters,
                                const spatial::SpatialState& st) {
  Values values = input_values(model, graph, parameters, st.q, st.qd, st.qdd, st.t);
  for (size_t k = 0; k < graph.secondary.size(); ++k)
    values["s.closure.q[" + std::to_string(k) + "]"] = st.q[graph.secondary[k]];
  values["s.closure.wt"] = st.t;
  values["s.closure.follow"] = 1;
  for (size_t k = 0; k < d.angle_columns.size(); ++k) {
    const std::string index = "[" + std::to_string(k) + "]";
    values["s.closure.w" + index] = st.q[d.angle_columns[k]];
    values["s.closure.wd" + index] = values["s.closure.wdd" + index] = 0;
  }
  for (const auto& [symbol, value] : d.definitions)
    values[symbol.get_name()] = evaluate(value, values);
  return values;
}

// A shipped model's description text (tests edit it before reading).
inline std::string model_text(const std::string& name) {
  std::ifstream in(std::string(MECHGEN_SOURCE_DIR "/models/") + name + ".yaml");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace mechgen::gen
