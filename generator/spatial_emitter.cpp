// Spatial kernel emission (spatial_emitter.hpp).
#include "spatial_emitter.hpp"

#include <charconv>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "code_block.hpp"
#include "finite_sentinels.hpp"
#include "forward_dynamics_emit.hpp"
#include "kernel_fingerprint.hpp"
#include "model/fingerprint.hpp"
#include "model/spatial_graph.hpp"
#include "model/support_model.hpp"
#include "output_checks.hpp"
#include "spatial/spatial_sweep.hpp"
#include "spatial_primary_inputs.hpp"
#include "spatial_shared_stages.hpp"
#include "template_renderer.hpp"

namespace mechgen::gen {

using GiNaC::ex;

namespace {

// Above this many bytes of entry-point code written as straight lines, the entries share their
// stages (spatial_shared_stages.hpp; README "Performance": the cross-over).
constexpr size_t kSharedStagesAbove = 600 * 1024;
// In a kernel that shares its stages, control() (a controller's cycle) stays its own straight
// line up to this many bytes: it computes no body outputs, so it skips the stages' State and
// workspace stores (the Bioloid's support kernel: 8 232 operations against 9 752 through the
// stages).
constexpr size_t kStraightControlBelow = 256 * 1024;

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read template " + path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// `scalar`(value): T in functions, Real in the structs that hold the model's names.
std::string number_literal(double value, const std::string& scalar = "T") {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  std::string text(buffer, result.ptr);
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  return scalar + "(" + text + ")";
}

std::string lines(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& line : items) text += (text.empty() ? "" : "\n") + line;
  return text;
}

std::string quoted(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "\"" : ", \"") + item + "\"";
  return text;
}

// sin and cos come from the kernels' own branch-free detail:: versions (Cephes polynomials, within
// about 2 ulp), taken from the planar template so that both kernels share one copy: after
// inlining, a coordinate's sin and cos share one range reduction, several times cheaper than
// the C library's sincos.
std::string using_std(const CodeBlock& code) {
  std::string text;
  for (const std::string& f : code.math_functions())
    text += std::string(text.empty() ? "" : "\n") + "  using " +
            (f == "sin" || f == "cos" || f == "branch_sign" ? "detail::" : "std::") + f + ";";
  return text;
}

// The finiteness checks of these outputs (output_checks.hpp), each stage's failure through
// `check_line`; every output in `stage` when one is given (the Newton-Euler system's A and b).
// A value written to several outputs (a screw in every body's Jacobian beyond its joint, a point
// and its Jacobian's entry, up to sign) is checked once, in the earliest stage that writes it:
// its copies are finite exactly when it is, and a failure names the same stage.
// Of those, only each stage's sentinels are summed (finite_sentinels.hpp).
std::string spatial_output_checks(
    const std::vector<SpatialOutput>& outputs, const SymbolDefinitions& definitions,
    const std::function<std::string(OutputStage, const std::string& condition)>& check_line,
    OutputStage stage = OutputStage::none) {
  std::map<ex, CheckedOutput, GiNaC::ex_is_less> first;  // per value (sign aside)
  std::vector<ex> order;
  for (const SpatialOutput& o : outputs) {
    if (GiNaC::is_a<GiNaC::numeric>(o.value)) continue;
    const OutputStage at = stage == OutputStage::none ? spatial_stage_of(o.target) : stage;
    const ex key = first.count(-o.value) ? ex(-o.value) : o.value;
    const auto [it, inserted] = first.emplace(key, CheckedOutput{at, o.target});
    if (inserted)
      order.push_back(key);
    else if (at < it->second.stage)
      it->second = {at, o.target};
  }
  std::vector<CheckedOutput> checked;
  for (int k = static_cast<int>(OutputStage::positions); k < kStageCount; ++k) {
    std::vector<ex> values;
    for (const ex& key : order)
      if (first.at(key).stage == static_cast<OutputStage>(k)) values.push_back(key);
    for (const size_t i : finite_sentinels(values, definitions))
      checked.push_back(first.at(values[i]));
  }
  return output_checks(checked, "  ", check_line);
}

// An output of the second rates: a body's or point's acceleration (ax, alx, ...) or a
// coordinate's (qdd, q1dd, ...).
bool is_acceleration_target(const std::string& target) {
  const std::string field = target.substr(target.rfind('.') + 1);
  return field == "ax" || field == "ay" || field == "az" || field.rfind("al", 0) == 0 ||
         (field.size() > 2 && field.compare(field.size() - 2, 2, "dd") == 0);
}

std::string kernel_math_functions(const std::string& templates_dir) {
  const std::string text = read_text(templates_dir + "/kernel.hpp.in");
  const std::string begin = "namespace detail {\n#if defined(__GNUC__)\n#define MECHGEN_INLINE";
  const std::string end = "#undef MECHGEN_INLINE\n}  // namespace detail\n";
  const auto b = text.find(begin), e = text.find(end);
  if (b == std::string::npos || e == std::string::npos || e < b)
    throw std::runtime_error(
        "templates/kernel.hpp.in: the detail:: math functions block is missing");
  return text.substr(b, e + end.size() - b);
}

class SpatialEmitter {
 public:
  SpatialEmitter(const SpatialModel& model, const SpatialDerivation& d)
      : m_(model), d_(d), inputs_(spatial_primary_inputs(model, build_spatial_graph(model))) {
    for (const auto& [symbol, value] : d.definitions) definition_[symbol] = value;
    for (const auto& [symbol, value] : d.newton_step) definition_[symbol] = value;
  }

  // The positions-only entry in two parts: the definitions that read the parameters alone,
  // computed once per parameter set into PositionConstants (a workspace's batch places millions
  // of samples with one parameter set), and what each sample computes from them.
  void hoisted_positions(const std::vector<SpatialOutput>& outputs,
                         std::map<std::string, std::string>& v) const {
    const std::set<ex, GiNaC::ex_is_less> needed = needed_symbols(outputs);
    // A closed form's reach value is checked per sample (after its definition), never hoisted.
    std::set<ex, GiNaC::ex_is_less> varying;
    for (const SpatialDerivation::Guard& g : d_.guards)
      if (needed.count(g.value)) varying.insert(g.value);
    auto reads = [](const ex& e, const std::function<bool(const ex&)>& test) {
      for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it)
        if (GiNaC::is_a<GiNaC::symbol>(*it) && test(*it)) return true;
      return false;
    };
    // Varying: reads a driver input or the State (the warm start), directly or through another.
    for (const auto& [symbol, value] : d_.definitions)
      if (needed.count(symbol) && reads(value, [&](const ex& x) {
            const std::string n = GiNaC::ex_to<GiNaC::symbol>(x).get_name();
            return n.rfind("in.", 0) == 0 || n.rfind("s.", 0) == 0 || varying.count(x) > 0;
          }))
        varying.insert(symbol);
    std::set<ex, GiNaC::ex_is_less> frontier;  // constants a sample reads
    auto constant_read = [&](const ex& e) {
      reads(e, [&](const ex& x) {
        if (needed.count(x) && !varying.count(x) && definition_.count(x)) frontier.insert(x);
        return false;
      });
    };
    for (const auto& [symbol, value] : d_.definitions)
      if (varying.count(symbol)) constant_read(value);
    for (const SpatialOutput& o : outputs) constant_read(o.value);
    CodeBlock constants, sample;
    GiNaC::exmap hoist;
    std::vector<std::string> fields;
    for (const auto& [symbol, value] : d_.definitions) {
      if (!needed.count(symbol) || varying.count(symbol)) continue;
      constants.define(symbol.get_name(), value);
      if (!frontier.count(symbol)) continue;
      constants.assign("k." + symbol.get_name(), symbol);
      hoist[symbol] = GiNaC::symbol("k." + symbol.get_name());
      fields.push_back("  Real " + symbol.get_name() + ";");
    }
    for (const auto& [symbol, value] : d_.definitions) {
      if (!varying.count(symbol)) continue;
      sample.define(symbol.get_name(), value.subs(hoist));
      for (const SpatialDerivation::Guard& g : d_.guards)
        if (g.value == symbol)
          sample.guard(
              symbol, ">=",
              "return detail::failed(s, " + std::to_string(g.group) + ", Status::unreachable);");
    }
    for (const SpatialOutput& o : outputs) sample.assign(o.target, o.value.subs(hoist));
    v["position_constant_fields"] = lines(fields);
    v["position_constants_using"] = using_std(constants);
    v["position_constants_ops"] = std::to_string(constants.op_count());
    v["position_constants_body"] = constants.render("  ");
    v["positions_using"] = using_std(sample);
    v["positions_ops"] = std::to_string(sample.op_count());
    v["positions_body"] = sample.render("  ");
  }

  // Every symbol the outputs read, through the definitions.
  std::set<ex, GiNaC::ex_is_less> needed_symbols(const std::vector<SpatialOutput>& outputs) const {
    std::set<ex, GiNaC::ex_is_less> needed;
    std::vector<ex> pending;
    for (const SpatialOutput& o : outputs) pending.push_back(o.value);
    while (!pending.empty()) {
      const ex e = pending.back();
      pending.pop_back();
      for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it) {
        if (!GiNaC::is_a<GiNaC::symbol>(*it) || needed.count(*it)) continue;
        needed.insert(*it);
        if (auto def = definition_.find(*it); def != definition_.end())
          pending.push_back(def->second);
      }
    }
    return needed;
  }

  // A structurally zero Jacobian entry is zero from the State's construction: never written.
  static std::vector<SpatialOutput> written(const std::vector<SpatialOutput>& outputs) {
    std::vector<SpatialOutput> kept;
    for (const SpatialOutput& o : outputs)
      if (!(o.value.is_zero() && o.target.find("_jacobians.") != std::string::npos))
        kept.push_back(o);
    return kept;
  }

  // Only the definitions the outputs read, in program order, then the outputs.
  // A closed-form group's reach value is checked right after its definition (before any square
  // root of it) in the entry points that have a State.
  CodeBlock block(const std::vector<SpatialOutput>& outputs, bool guards = true) const {
    const std::set<ex, GiNaC::ex_is_less> needed = needed_symbols(outputs);
    CodeBlock code;
    for (const auto& [symbol, value] : d_.definitions) {
      if (!needed.count(symbol)) continue;
      code.define(symbol.get_name(), value);
      for (const SpatialDerivation::Guard& g : d_.guards)
        if (guards && g.value == symbol)
          code.guard(
              symbol, ">=",
              "return detail::failed(s, " + std::to_string(g.group) + ", Status::unreachable);");
    }
    for (const SpatialOutput& o : written(outputs)) code.assign(o.target, o.value);
    const std::vector<std::string> unused = code.unused_definitions();
    if (!unused.empty()) throw std::logic_error("generated code would define unused " + unused[0]);
    return code;
  }

  std::map<std::string, std::string> values(const EmitOptions& options) const {
    std::map<std::string, std::string> v;
    v["math_functions"] = kernel_math_functions(options.templates_dir);
    v["model"] = m_.common.name;
    v["source"] = options.source;
    v["command"] = options.command;
    v["description"] = m_.common.description.empty() ? "(no description)" : m_.common.description;
    v["ground"] = m_.bodies[static_cast<size_t>(m_.ground)].name;
    std::vector<std::string> plan;
    for (const std::string& line : d_.plan) plan.push_back("//   " + line);
    v["plan"] = lines(plan);
    v["primary_count"] = std::to_string(d_.primary_count);
    // The solve groups, then the stages checked after them (output_checks.hpp), as in planar.
    std::vector<std::string> group_names = d_.groups;
    const int inputs_group = static_cast<int>(group_names.size());
    for (const char* stage : kStageNames) group_names.push_back(stage);
    v["group_count"] = std::to_string(group_names.size());
    v["solve_group_count"] = std::to_string(d_.groups.size());
    v["group_names"] = quoted(group_names);
    v["inputs_group"] = std::to_string(inputs_group);
    v["fingerprint"] = hex64(options.fingerprint);
    const auto stage_check = [inputs_group](OutputStage stage, const std::string& condition) {
      return "if (!(" + condition + ")) return detail::failed(s, " +
             std::to_string(inputs_group + static_cast<int>(stage)) + ", Status::non_finite);";
    };

    const std::vector<double> defaults = m_.common.default_parameters();
    std::vector<std::string> params, set_params, names;
    for (size_t i = 0; i < m_.common.parameters.size(); ++i) {
      const Parameter& par = m_.common.parameters[i];
      std::string comment = par.unit;
      if (!par.doc.empty()) comment += (comment.empty() ? "" : ": ") + par.doc;
      params.push_back("  Real " + par.name + " = " + number_literal(defaults[i], "Real") + ";" +
                       (comment.empty() ? "" : "  // " + comment));
      set_params.push_back("  p." + par.name + " = values[" + std::to_string(i) + "];");
      names.push_back(par.name);
    }
    v["param_fields"] = lines(params);
    v["parameter_count"] = std::to_string(names.size());
    v["parameter_names"] = quoted(names);
    v["set_parameters_body"] = lines(set_params);

    std::vector<std::string> inputs, drivers;
    std::string checks;
    CodeBlock motion;
    GiNaC::exmap rename = spatial_parameter_symbols(m_);
    rename[m_.common.t] = GiNaC::symbol("t");
    for (const SpatialPrimaryInput& d : inputs_) {
      inputs.push_back("  Real " + d.name + " = Real(0), " + d.name + "_d = Real(0), " + d.name +
                       "_dd = Real(0);");
      drivers.push_back("    DriverState<Real> " + d.name + ";");
      for (const char* suffix : {"", "_d", "_dd"})
        checks += std::string(" + T(0) * in.") + d.name + suffix;
      motion.assign("in." + d.name, d.value.subs(rename));
      motion.assign("in." + d.name + "_d", d.value_d.subs(rename));
      motion.assign("in." + d.name + "_dd", d.value_dd.subs(rename));
    }
    v["input_fields"] = lines(inputs);
    v["driver_fields"] = lines(drivers);
    v["input_checks"] = checks;
    v["drivers_using"] = using_std(motion);
    v["drivers_body"] = motion.render("  ");

    std::vector<std::string> bodies, body_jacobians, points, point_jacobians, joints;
    for (const SpatialBody& b : m_.bodies) {
      if (b.ground || b.is_virtual) continue;
      bodies.push_back("    BodyState<Real> " + b.name + ";");
      if (m_.emits_jacobian(b.name))
        body_jacobians.push_back("    Real " + b.name + "[6][primary_count] = {};");
    }
    for (const auto& [point, body] : m_.named_points()) {
      points.push_back("    PointState<Real> " + point + ";");
      if (!m_.bodies[static_cast<size_t>(body)].ground && m_.emits_jacobian(point))
        point_jacobians.push_back("    Real " + point + "[3][primary_count] = {};");
    }
    for (const SpatialJoint& j : m_.joints) {
      if (j.is_virtual) continue;
      std::string q;
      for (size_t k = 0; k < j.columns.size(); ++k) {
        const std::string c = j.columns.size() == 1 ? "q" : "q" + std::to_string(k + 1);
        q += std::string(q.empty() ? "Real " : ", ") + c + ", " + c + "d, " + c + "dd";
      }
      joints.push_back("    struct {" + (q.empty() ? "" : "\n      " + q + ";") +
                       "\n      Real fx, fy, fz, mx, my, mz;\n    } " + j.name + ";");
    }
    v["body_fields"] = lines(bodies);
    v["body_jacobian_fields"] = lines(body_jacobians);
    v["point_fields"] = lines(points);
    v["point_jacobian_fields"] = lines(point_jacobians);
    v["joint_fields"] = lines(joints);

    std::vector<SpatialOutput> kinematic = d_.kinematics;
    kinematic.insert(kinematic.end(), d_.jacobians.begin(), d_.jacobians.end());
    std::vector<SpatialOutput> all = kinematic;
    all.insert(all.end(), d_.dynamics.begin(), d_.dynamics.end());
    // What a controller needs each cycle: the named points, their and the bodies' Jacobians and
    // the driver efforts (no body outputs, no reactions).
    std::vector<SpatialOutput> control;
    for (const std::vector<SpatialOutput>* list : {&d_.kinematics, &d_.jacobians, &d_.dynamics})
      for (const SpatialOutput& o : *list)
        if ((o.target.rfind("s.points.", 0) == 0 && o.target.size() > 2 &&
             o.target[o.target.size() - 2] == '.') ||
            o.target.find("_jacobians.") != std::string::npos ||
            (o.target.rfind("s.drivers.", 0) == 0 &&
             o.target.find(".effort") != std::string::npos) ||
            o.target.rfind("s.closure.", 0) == 0)
          control.push_back(o);
    const CodeBlock kin = block(kinematic), full = block(all), lean = block(control);
    // A and b; a closed chain's also close its circuits from the State's warm start, checked as
    // evaluate() checks them.
    std::vector<SpatialOutput> system;
    for (const auto& [index, value] : d_.ne_matrix)
      system.push_back({"A[" + std::to_string(index) + "]", value});
    for (size_t r = 0; r < d_.ne_rhs.size(); ++r)
      if (!d_.ne_rhs[r].is_zero()) system.push_back({"b[" + std::to_string(r) + "]", d_.ne_rhs[r]});
    for (const SpatialOutput& o : d_.kinematics)
      if (o.target.rfind("s.closure.", 0) == 0) system.push_back(o);
    const CodeBlock ne = block(system);
    v["ne_using"] = using_std(ne);
    v["ne_ops"] = std::to_string(ne.op_count());
    v["ne_body"] = ne.render("  ") +
                   spatial_output_checks(system, definition_, stage_check, OutputStage::forces);
    v["ne_rows"] = std::to_string(d_.ne_rows);
    v["ne_size"] = std::to_string(d_.ne_unknowns.size());
    v["ne_unknowns"] = d_.ne_unknowns.empty() ? "nullptr" : quoted(d_.ne_unknowns);
    v["control_using"] = using_std(lean);
    v["control_ops"] = std::to_string(lean.op_count());
    v["control_body"] =
        lean.render("  ") + spatial_output_checks(control, definition_, stage_check);
    // A workspace's sample: the named points' positions alone (no rates, Jacobians or forces),
    // with what closes the circuits' positions checked.
    std::vector<SpatialOutput> placed;
    for (const SpatialOutput& o : d_.kinematics)
      if ((o.target.rfind("s.points.", 0) == 0 && o.target[o.target.size() - 2] == '.') ||
          (!d_.closure_start.empty() && o.target.rfind("s.closure.", 0) == 0 &&
           o.target.rfind("s.closure.wd", 0) != 0 && o.target.rfind("s.closure.rate_", 0) != 0 &&
           o.target.rfind("s.closure.acc_", 0) != 0))
        placed.push_back(o);
    hoisted_positions(placed, v);
    v["positions_body"] += spatial_output_checks(placed, definition_, stage_check);
    // Issue 13's velocity solve: positions and first rates (Davies' velocities, twists, point
    // velocities); no accelerations, Jacobians or forces.
    std::vector<SpatialOutput> velocity;
    for (const SpatialOutput& o : d_.kinematics)
      if (!is_acceleration_target(o.target) && o.target.rfind("s.closure.wddnext", 0) != 0 &&
          o.target.rfind("s.closure.acc_", 0) != 0)
        velocity.push_back(o);
    const CodeBlock vel = block(velocity);
    v["velocities_using"] = using_std(vel);
    v["velocities_ops"] = std::to_string(vel.op_count());
    v["velocities_body"] =
        vel.render("  ") + spatial_output_checks(velocity, definition_, stage_check);
    v["kinematics_using"] = using_std(kin);
    v["kinematics_ops"] = std::to_string(kin.op_count());
    v["kinematics_body"] =
        kin.render("  ") + spatial_output_checks(kinematic, definition_, stage_check);
    v["evaluate_using"] = using_std(full);
    v["evaluate_ops"] = std::to_string(full.op_count());
    v["evaluate_body"] = full.render("  ") + spatial_output_checks(all, definition_, stage_check);
    v["shared_stages"] = "";
    size_t straight = 0;
    for (const char* body :
         {"kinematics_body", "velocities_body", "evaluate_body", "control_body", "ne_body"})
      straight += v[body].size();
    if (straight > kSharedStagesAbove) {
      // What each entry checks stays its own; the code before the checks is shared.
      std::map<std::string, std::vector<SpatialOutput>> checked{{"kinematics", kinematic},
                                                                {"velocities", velocity},
                                                                {"evaluate", all},
                                                                {"control", control}};
      const std::string straight_control[] = {v["control_body"], v["control_using"],
                                              v["control_ops"]};
      shared_stages(velocity, kinematic, control, system, v);
      if (straight_control[0].size() <= kStraightControlBelow) {
        v["control_body"] = straight_control[0];
        v["control_using"] = straight_control[1];
        v["control_ops"] = straight_control[2];
        checked.erase("control");
      }
      for (const auto& [entry, outputs] : checked)
        v[entry + "_body"] += spatial_output_checks(outputs, definition_, stage_check);
      v["ne_body"] += spatial_output_checks(system, definition_, stage_check, OutputStage::forces);
    }
    newton(v);
    closure(v);
    start(v);
    columns(v);
    return v;
  }

  // A large kernel's entry points as calls of shared stages (spatial_shared_stages.hpp): motion
  // (positions and first rates: velocities()), accelerations, jacobians (kinematics()), efforts
  // (control()), then each entry's own tail (evaluate()'s reactions, ne_fill()'s system). Replaces
  // the entries' bodies, using lines and op counts.
  void shared_stages(const std::vector<SpatialOutput>& velocity,
                     const std::vector<SpatialOutput>& kinematic,
                     const std::vector<SpatialOutput>& control,
                     const std::vector<SpatialOutput>& system,
                     std::map<std::string, std::string>& v) const {
    std::set<std::string> in_velocity;
    for (const SpatialOutput& o : velocity) in_velocity.insert(o.target);
    std::vector<SpatialOutput> accelerations;
    for (const SpatialOutput& o : d_.kinematics)
      if (!in_velocity.count(o.target)) accelerations.push_back(o);
    std::set<std::string> staged;
    const auto beyond = [&](const std::vector<SpatialOutput>& outputs) {
      std::vector<SpatialOutput> rest;
      for (const SpatialOutput& o : written(outputs))
        if (!staged.count(o.target)) rest.push_back(o);
      return rest;
    };
    for (const std::vector<SpatialOutput>* list : {&velocity, &kinematic})
      for (const SpatialOutput& o : *list) staged.insert(o.target);
    const std::vector<SpatialOutput> system_rest = beyond(system), efforts = beyond(control);
    for (const SpatialOutput& o : efforts) staged.insert(o.target);
    const std::vector<SpatialOutput> reactions = beyond(d_.dynamics);
    // The bodies' rates of momentum: what the efforts and the Newton-Euler system both read.
    std::vector<ex> momenta;
    {
      const std::set<ex, GiNaC::ex_is_less> motion_read = needed_symbols(velocity),
                                            kinematic_read = needed_symbols(kinematic),
                                            system_read = needed_symbols(system_rest);
      for (const ex& x : needed_symbols(efforts))
        if (system_read.count(x) && !kinematic_read.count(x) && !motion_read.count(x) &&
            definition_.count(x))
          momenta.push_back(x);
    }
    enum : size_t { at_motion, at_accelerations, at_jacobians, at_momenta, at_efforts };
    const std::vector<SharedStage> stages{
        {"motion",
         "Every body's pose and twist, the points, the coordinates and their rates (velocities()).",
         written(velocity),
         {},
         {}},
        {"accelerations",
         "The twist rates, points' and coordinates' accelerations.",
         written(accelerations),
         {},
         {at_motion}},
        {"jacobians",
         "The screw Jacobians of the bodies and points.",
         written(d_.jacobians),
         {},
         {at_motion, at_accelerations}},
        {"momenta",
         "Each body's rate of momentum (the efforts' and the Newton-Euler system's).",
         {},
         momenta,
         {at_motion, at_accelerations}},
        {"efforts",
         "The driver efforts (inverse dynamics).",
         efforts,
         {},
         {at_motion, at_accelerations, at_jacobians, at_momenta}}};
    const std::vector<size_t> all_stages{at_motion, at_accelerations, at_jacobians, at_momenta,
                                         at_efforts};
    const std::vector<StagedEntry> entries{
        {"velocities", {at_motion}, {}},
        {"kinematics", {at_motion, at_accelerations, at_jacobians}, {}},
        {"evaluate", all_stages, reactions},
        {"control", all_stages, {}},
        {"ne", {at_motion, at_accelerations, at_momenta}, system_rest}};
    const StagedProgramView program{
        d_.definitions, [this](const std::vector<SpatialOutput>& o) { return needed_symbols(o); },
        [this](CodeBlock& code, const GiNaC::symbol& symbol) {
          for (const SpatialDerivation::Guard& g : d_.guards)
            if (g.value == symbol)
              code.guard(symbol, ">=",
                         "return detail::failed(s, " + std::to_string(g.group) +
                             ", Status::unreachable);");
        },
        [](const CodeBlock& code) { return using_std(code); }};
    const StagedKernel kernel = emit_shared_stages(program, stages, entries);
    v["shared_stages"] = kernel.functions;
    for (const StagedEntry& e : entries) {
      v[e.name + "_body"] = kernel.body.at(e.name);
      v[e.name + "_using"] = kernel.using_lines.at(e.name);
      v[e.name + "_ops"] = std::to_string(kernel.ops.at(e.name)) + " (with the stages it calls)";
    }
  }

  // The Newton fallback (closed chains with circuits not in closed form): one function that every
  // entry point calls first, running the derived step newton_steps times from the warm start
  // s.closure.q[] into s.closure.next[], which the entries' positions then read. What the step
  // reads from the program (the known bodies' poses) is computed once before the loop.
  void newton(std::map<std::string, std::string>& v) const {
    v["newton_function"] = "";
    if (d_.newton_update.empty()) return;
    std::vector<SpatialOutput> updates;
    for (size_t k = 0; k < d_.newton_update.size(); ++k)
      updates.push_back({"s.closure.next[" + std::to_string(k) + "]", d_.newton_update[k]});
    const std::set<ex, GiNaC::ex_is_less> needed = needed_symbols(updates);
    CodeBlock before("_nb"), step("_ns");
    for (const auto& [symbol, value] : d_.definitions)
      if (needed.count(symbol)) before.define(symbol.get_name(), value);
    for (const auto& [symbol, value] : d_.newton_step)
      if (needed.count(symbol)) step.define(symbol.get_name(), value);
    for (const SpatialOutput& o : updates) step.assign(o.target, o.value);
    std::set<std::string> functions = before.math_functions();
    for (const std::string& f : step.math_functions()) functions.insert(f);
    std::string using_lines;
    for (const std::string& f : functions)
      using_lines +=
          "  using " +
          std::string(f == "sin" || f == "cos" || f == "branch_sign" ? "detail::" : "std::") + f +
          ";\n";
    const std::string n = std::to_string(d_.newton_update.size());
    v["newton_function"] =
        "namespace detail {\n"
        "// The circuits left to Newton-Raphson (the plan above): " +
        std::to_string(d_.newton_steps) +
        " steps from the warm start s.closure.q[] into\n// s.closure.next[], shared by every "
        "entry point; each entry then checks the closure it reached.\n"
        "template <class T>\nvoid close_newton([[maybe_unused]] const Params<T>& p, "
        "[[maybe_unused]] const Inputs<T>& in,\n                  State<T>& s) noexcept {\n" +
        using_lines + "  // Total ops: " + std::to_string(before.op_count()) + " once, then " +
        std::to_string(step.op_count()) + " per step\n" + before.render("  ") +
        "  for (int i = 0; i < " + n + "; ++i) s.closure.next[i] = s.closure.q[i];\n" +
        "  for (int step = 0; step < " + std::to_string(d_.newton_steps) + "; ++step) {\n" +
        step.render("    ") + "  }\n}\n}  // namespace detail\n\n";
    const std::string call = "  detail::close_newton(p, in, s);\n";
    for (const char* body : {"kinematics_body", "velocities_body", "evaluate_body", "control_body",
                             "positions_body", "ne_body"})
      v[body] = call + v[body];
  }

 private:
  // A closed chain's State keeps the secondary coordinates (the Newton-Raphson warm start, the
  // assembly by default); each entry point checks the closure before accepting them. Placed at
  // the start of existing lines of the template: a tree's kernel is unchanged.
  void closure(std::map<std::string, std::string>& v) const {
    v["closure_fields"] = "";
    v["closure_check"] = "";
    v["velocities_closure_check"] = "";
    v["positions_check"] = "";
    v["keep_warm_start"] = "";
    v["entry_state"] = "State<T> s;";
    if (!d_.closed_chain) return;
    std::string start;
    for (const double q : d_.closure_start)
      start += (start.empty() ? "" : ", ") + number_literal(q, "Real");
    const std::string n = std::to_string(d_.closure_start.size());
    // The closure is the last solve group (the stages inputs, positions, ... follow it).
    const std::string closure_group = std::to_string(d_.groups.size() - 1);
    // Warm starts: the Newton coordinates' (none: every circuit in closed form) and the
    // closed-form angles' (unwinding); neither: only the closure's checks.
    const bool newton = !d_.closure_start.empty();
    const bool angles = !d_.angle_start.empty();
    std::string angle_start;
    for (const double q : d_.angle_start)
      angle_start += (angle_start.empty() ? "" : ", ") + number_literal(q, "Real");
    const std::string na = std::to_string(d_.angle_start.size());
    v["keep_warm_start"] =
        newton || angles ? "  cleared.closure = s.closure;  // the warm start survives a failure\n"
                         : "";
    v["closure_fields"] =
        (newton ? "  // The closure: secondary coordinates left to Newton-Raphson (the warm start, "
                  "the assembly at t0\n  // by default, replaced by every call that closes the "
                  "circuits), the last call's result,\n  // squared closure error and the pivots "
                  "of N_s's elimination"
                : "  // The closure: squared closure error and the pivots of N_s's elimination") +
        std::string(angles ? "; the closed-form angles' warm start (the assembly at t0 by "
                             "default,\n  // unwinding: joint angles stay continuous) and the "
                             "last call's angles"
                           : "") +
        ".\n  struct {\n" +
        (newton ? "    Real q[" + n + "] = {" + start + "};\n    Real next[" + n + "];\n" : "") +
        (angles
             ? "    Real w[" + na + "] = {" + angle_start + "};\n    Real wnext[" + na +
                   "];\n    Real wd[" + na + "] = {}, wdd[" + na +
                   "] = {};  // rates and accelerations at time wt\n    Real wdnext[" + na +
                   "], wddnext[" + na +
                   "];\n    Real wt = Real(0);\n"
                   "    // 1 once a call was accepted or the start seeded: the closed forms' roots "
                   "follow\n    // the warm start; 0 (fresh): the assembly's roots.\n"
                   "    Real follow = Real(0);\n"
             : "") +
        "    Real residual, rate_residual, rate_scale, acc_residual, acc_scale, pivot[" +
        std::to_string(d_.closure_pivots.size()) + "];\n  } closure;\n";
    // After a call that closed the circuits: the Newton coordinates and the angles' warm starts
    // carried to the next call, with the rates and accelerations the entry computed (zero where
    // it does not: the velocities' entry has no accelerations, the positions' no rates).
    const auto carried = [&](bool rates, bool accelerations) {
      if (!angles) return std::string();
      return "  for (int i = 0; i < " + na +
             "; ++i) {\n    s.closure.w[i] = s.closure.wnext[i];\n" +
             "    s.closure.wd[i] = " + (rates ? "s.closure.wdnext[i]" : "T(0)") + ";\n" +
             "    s.closure.wdd[i] = " + (accelerations ? "s.closure.wddnext[i]" : "T(0)") +
             ";\n  }\n  s.closure.wt = in.t;\n" + (rates ? "  s.closure.follow = T(1);\n" : "");
    };
    // One determinant check per independent block of N_s: the product of its pivots is the block's
    // determinant whatever the pivot order (a single pivot of a fixed order may pass near zero at
    // a regular pose), and independent circuits do not multiply into one vanishing product.
    std::vector<std::string> block_products;
    std::vector<double> block_dets;
    for (size_t k = 0; k < d_.closure_pivots.size(); ++k) {
      const size_t b = d_.closure_blocks[k];
      if (b >= block_products.size()) block_products.resize(b + 1), block_dets.resize(b + 1, 1.0);
      block_products[b] += (block_products[b].empty() ? "" : " * ") +
                           std::string("s.closure.pivot[") + std::to_string(k) + "]";
      block_dets[b] *= d_.closure_pivots[k];
    }
    // N_s^T N_s's determinant is N_s's squared (a square block's; least squares: the sum of its
    // square minors' squares): the same 1e-9, squared.
    const double singular_ratio = d_.closure_least_squares ? 1e-18 : 1e-9;
    std::string singular_checks;
    for (size_t b = 0; b < block_products.size(); ++b)
      singular_checks += "  if (!(abs(" + block_products[b] + ") > " +
                         number_literal(singular_ratio * std::abs(block_dets[b])) +
                         "))\n    return s.failed_group = " + closure_group +
                         ", Status::singular;\n";
    const std::string checks =
        "  // Unreachable: the Newton-Raphson steps did not close the circuits; singular: N_s is "
        "(nearly)\n  // singular there: the determinant of an independent block (circuits that "
        "share coordinates)\n  // below " +
        std::string(d_.closure_least_squares
                        ? "1e-18 of its value at the assembly (of N_s^T N_s: least squares).\n"
                        : "1e-9 of its value at the assembly.\n") +
        "  using std::abs;\n"
        "  if (!(s.closure.residual <= T(1e8) * std::numeric_limits<T>::epsilon() *\n"
        "                                   std::numeric_limits<T>::epsilon()))\n"
        "    return s.failed_group = " +
        closure_group + ", Status::unreachable;\n" + singular_checks;
    // The rates' and accelerations' solves through N_s in the pivot order fixed at generation:
    // a backward error above 1e5 eps of their terms is a pivot that lost its precision at this
    // pose, refused as singular (the numeric solver pivots at run time).
    const auto backward_check = [&](const std::string& name) {
      return "  // singular also: the " +
             std::string(name == "rate" ? "rates'" : "accelerations'") +
             " solve through N_s lost its precision (backward error above 1e5 eps).\n"
             "  if (!(s.closure." +
             name + "_residual <= T(1e10) * std::numeric_limits<T>::epsilon() *\n" +
             "                                   std::numeric_limits<T>::epsilon() * s.closure." +
             name + "_scale))\n    return s.failed_group = " + closure_group +
             ", Status::singular;\n";
    };
    const std::string newton_next =
        newton ? "  for (int i = 0; i < " + n + "; ++i) s.closure.q[i] = s.closure.next[i];\n" : "";
    v["closure_check"] =
        checks + backward_check("rate") + backward_check("acc") + newton_next + carried(true, true);
    v["velocities_closure_check"] =
        checks + backward_check("rate") + newton_next + carried(true, false);
    // The positions-only entry: the closed forms' reach checked inline; the Newton closure's.
    if (newton) v["positions_check"] = checks + newton_next + carried(false, false);
    if (newton || angles)
      v["entry_state"] =
          "// A closed chain's warm start carries over from one call to the next (per thread and "
          "scalar):\n// from where a sweep starts when time does not advance (a new sweep) or "
          "seed_start()\n// began one, whichever way its time runs then; and after a failed "
          "call, whose State is no\n// assembly to continue from (the next call may lie far from "
          "the last accepted one).\n"
          "Carried<T>& c = carried<T>();\n"
          "if (c.restart || c.s.failed_group >= 0 || (!c.seeded && !(in.t > c.last_t))) c.s = "
          "c.start;\n"
          "c.restart = false;\nc.last_t = in.t;\nState<T>& s = c.s;";
  }

  // The entry's warm start for a new sweep: the State's defaults, or values the runtime seeds
  // (the numeric solver's assembly at the run's parameters), per thread and scalar.
  void start(std::map<std::string, std::string>& v) const {
    v["start_block"] = "";
    v["start_count"] = "0";
    v["start_columns"] = "nullptr";
    v["seed_start"] = "nullptr";
    const size_t nq = d_.closure_start.size(), nw = d_.angle_start.size();
    if (nq + nw == 0) return;
    std::string columns;
    for (const std::vector<int>* list : {&d_.closure_columns, &d_.angle_columns})
      for (const int c : *list) columns += (columns.empty() ? "" : ", ") + std::to_string(c);
    std::string copy;
    if (nq > 0)
      copy += "  for (int i = 0; i < " + std::to_string(nq) +
              "; ++i) c.start.closure.q[i] = static_cast<T>(values[i]);\n";
    if (nw > 0)
      copy += "  for (int i = 0; i < " + std::to_string(nw) +
              "; ++i) c.start.closure.w[i] = static_cast<T>(values[" +
              (nq > 0 ? std::to_string(nq) + " + " : "") + "i]);\n";
    v["start_block"] =
        "// The State carried from call to call (per thread and scalar) and where a sweep starts: "
        "the\n// State's defaults (the assembly at the default parameters, t0), or the values "
        "seed_start()\n// was given for the warm start's entries, which are these columns of the "
        "spatial graph (the\n// Newton coordinates, then the closed-form angles).\n"
        "template <class T>\nstruct Carried {\n  State<T> start, s;\n"
        "  T last_t = std::numeric_limits<T>::infinity();\n"
        "  bool restart = false;  // the next call starts from `start`\n"
        "  bool seeded = false;   // a seeded sweep: carried whichever way its time runs\n};\n"
        "template <class T>\nstatic Carried<T>& carried() {\n"
        "  static thread_local Carried<T> c;\n  return c;\n}\n"
        "static const int start_columns[] = {" +
        columns +
        "};\n\n"
        "template <class T>\nstatic void seed(const double* values) {\n"
        "  Carried<T>& c = carried<T>();\n  c.start = State<T>{};\n  c.restart = true;\n"
        "  c.seeded = values != nullptr;\n  if (values == nullptr) return;\n" +
        copy + (nw > 0 ? "  c.start.closure.follow = T(1);\n" : "") +
        "}\n\n// Null: the defaults again.\n"
        "static void seed_start(const double* values) {\n  seed<double>(values);\n"
        "  seed<float>(values);\n}\n";
    v["start_count"] = std::to_string(nq + nw);
    v["start_columns"] = "start_columns";
    v["seed_start"] = "&seed_start";
  }

  // to_columns in DESIGN.md's spatial column order, checked against the sweep's own names.
  void columns(std::map<std::string, std::string>& v) const {
    std::vector<std::string> names{"t"}, body{"  row[0] = in.t;"};
    auto column = [&](const std::string& name, const std::string& source) {
      body.push_back("  row[" + std::to_string(names.size()) + "] = " + source + ";");
      names.push_back(name);
    };
    for (const SpatialPrimaryInput& d : inputs_)
      for (const char* f : {"q", "qd", "qdd", "effort"})
        column(d.column + "." + f, "s.drivers." + d.name + "." + f);
    for (const SpatialBody& b : m_.bodies) {
      if (b.ground || b.is_virtual) continue;
      const std::string s = "s.bodies." + b.name + ".";
      for (const char* f : {"x", "y", "z"}) column(b.name + "." + f, s + f);
      body.push_back("  " + s + "quaternion(q);");
      for (int k = 0; k < 4; ++k) column(b.name + ".q" + "wxyz"[k], "q[" + std::to_string(k) + "]");
      for (const char* f :
           {"vx", "vy", "vz", "ax", "ay", "az", "wx", "wy", "wz", "alx", "aly", "alz"})
        column(b.name + "." + f, s + f);
    }
    for (const auto& [point, body_index] : m_.named_points())
      for (const char* f : {"x", "y", "z"}) column(point + "." + f, "s.points." + point + "." + f);
    for (const SpatialJoint& j : m_.joints) {
      if (j.is_virtual) continue;
      for (size_t k = 0; k < j.columns.size(); ++k) {
        const std::string q = j.columns.size() == 1 ? "q" : "q" + std::to_string(k + 1);
        for (const char* f : {"", "d", "dd"})
          column(j.name + "." + q + f, "s.joints." + j.name + "." + q + f);
      }
      for (const char* f : {"fx", "fy", "fz", "mx", "my", "mz"})
        column(j.name + "." + f, "s.joints." + j.name + "." + f);
    }
    for (const auto& [point, body_index] : m_.named_points())
      for (const char* f : {"vx", "vy", "vz", "ax", "ay", "az"})
        column(point + "." + f, "s.points." + point + "." + f);
    if (names != spatial::spatial_column_names(m_))
      throw std::logic_error("spatial kernel columns differ from the sweep's");
    v["column_count"] = std::to_string(names.size());
    v["column_names"] = quoted(names);
    v["to_columns_body"] = lines(body);
  }

  const SpatialModel& m_;
  const SpatialDerivation& d_;
  std::vector<SpatialPrimaryInput> inputs_;  // joint drivers, then prescribed pose coordinates
  std::map<ex, ex, GiNaC::ex_is_less> definition_;
};

}  // namespace

std::vector<EmittedFile> emit_spatial_kernel(const SpatialModel& model,
                                             const SpatialDerivation& derivation,
                                             const EmitOptions& options) {
  if (derivation.primary_count == 0)
    throw std::runtime_error(model.common.file + ": error: no driver: nothing to generate");
  const std::map<std::string, std::string> values =
      SpatialEmitter(model, derivation).values(options);
  std::vector<EmittedFile> files;
  std::string driven;
  std::vector<std::string> coordinates;
  const std::vector<SpatialPrimaryInput> inputs =
      spatial_primary_inputs(model, build_spatial_graph(model));
  for (size_t i = 0; i < inputs.size(); ++i) {
    coordinates.push_back(inputs[i].name);
    for (size_t k = 0; k < 3; ++k)
      driven += std::string(driven.empty() ? "" : "\n") + "in." + inputs[i].name +
                (k == 0   ? ""
                 : k == 1 ? "_d"
                          : "_dd") +
                " = static_cast<T>(drivers[" + std::to_string(3 * i + k) + "]);";
  }
  // A closed chain's forward dynamics starts from the warm start the last row left on this
  // thread (a copy: it neither moves nor restarts the sweep's).
  const ForwardDynamicsText dynamics = emit_forward_dynamics(
      options.templates_dir, coordinates, driven,
      values.at("start_count") == "0"
          ? "State<T> s;"
          : "State<T> s = carried<T>().s;  // the last row's warm start, copied");
  std::map<std::string, std::string> header = values;
  for (const char* key :
       {"entry_state", "start_block", "start_count", "start_columns", "seed_start"})
    header.erase(key);  // the entry's
  header["forward_dynamics"] = dynamics.header;
  files.push_back({model.common.name + ".hpp",
                   render_template(read_text(options.templates_dir + "/spatial_kernel.hpp.in"),
                                   header, "spatial_kernel.hpp.in")});
  // The positions-only batch: driver k's coordinate of sample i at q[k * n + i]; point c's axis
  // a to out[(3 c + a) n + i].
  std::string batch_inputs, batch_points, point_names;
  for (size_t i = 0; i < inputs.size(); ++i)
    batch_inputs += std::string(batch_inputs.empty() ? "" : "\n    ") + "in." + inputs[i].name +
                    " = q[" + std::to_string(i) + " * n + i];";
  size_t point_count = 0;
  for (const auto& [point, body] : model.named_points()) {
    for (size_t a = 0; a < 3; ++a)
      batch_points += std::string(batch_points.empty() ? "" : "\n    ") + "out[" +
                      std::to_string(3 * point_count + a) + " * n + i] = s.points." + point + "." +
                      "xyz"[a] + ";";
    point_names += std::string(point_names.empty() ? "" : ", ") + "\"" + point + "\"";
    ++point_count;
  }
  // The Jacobians entry: the State's body_jacobians then point_jacobians fields, in order.
  std::string jacobian_names, jacobian_rows, jacobian_copy;
  size_t jacobian_count = 0;
  const auto add_jacobian = [&](const std::string& field, const std::string& name, int rows) {
    jacobian_names += std::string(jacobian_names.empty() ? "" : ", ") + "\"" + name + "\"";
    jacobian_rows += std::string(jacobian_rows.empty() ? "" : ", ") + std::to_string(rows);
    jacobian_copy += std::string(jacobian_copy.empty() ? "" : "\n") + "J = copy_jacobian(&s." +
                     field + "." + name + "[0][0], " + std::to_string(rows) + ", J);";
    ++jacobian_count;
  };
  for (const SpatialBody& b : model.bodies)
    if (!b.ground && !b.is_virtual && model.emits_jacobian(b.name))
      add_jacobian("body_jacobians", b.name, 6);
  for (const auto& [point, body] : model.named_points())
    if (!model.bodies[static_cast<size_t>(body)].ground && model.emits_jacobian(point))
      add_jacobian("point_jacobians", point, 3);
  const std::map<std::string, std::string> entry{
      {"model", values.at("model")},
      {"source", values.at("source")},
      {"command", values.at("command")},
      {"driver_count", std::to_string(inputs.size())},
      {"driven_inputs", driven},
      {"forward_dynamics_entry", dynamics.entry},
      {"entry_state", values.at("entry_state")},
      {"start_block", values.at("start_block")},
      {"start_count", values.at("start_count")},
      {"start_columns", values.at("start_columns")},
      {"seed_start", values.at("seed_start")},
      {"batch_inputs", batch_inputs},
      {"batch_points", batch_points},
      {"point_count", std::to_string(point_count)},
      {"point_names", point_names.empty() ? "nullptr" : point_names},
      {"jacobian_count", std::to_string(jacobian_count)},
      {"jacobian_names", jacobian_names.empty() ? "nullptr" : jacobian_names},
      {"jacobian_rows", jacobian_rows.empty() ? "0" : jacobian_rows},
      {"jacobian_copy", jacobian_copy}};
  files.push_back(
      {model.common.name + "_entry.cpp",
       render_template(read_text(options.templates_dir + "/spatial_kernel_entry.cpp.in"), entry,
                       "spatial_kernel_entry.cpp.in")});
  return files;
}

std::vector<EmittedFile> emit_spatial_files(const SpatialModel& model,
                                            const SpatialDerivation& derivation,
                                            const GenerateOptions& options) {
  EmitOptions emit;
  emit.templates_dir = options.templates_dir;
  emit.source = display_path(options.model_path);
  emit.command = "build/mechgen generate " + emit.source +
                 (options.support.empty() ? "" : " --support " + options.support);
  emit.fingerprint =
      kernel_fingerprint(model.common, options.templates_dir, false, KernelKind::spatial);
  return emit_spatial_kernel(model, derivation, emit);
}

GenerateResult generate_spatial(const GenerateOptions& options) {
  const SpatialModel model =
      options.support.empty()
          ? read_spatial_model(options.model_path)
          : weld_support(read_spatial_model(options.model_path), options.support);
  const SpatialGraph graph = build_spatial_graph(model);
  const SpatialDerivation derivation = derive_spatial(model, graph);
  GenerateResult result{model.common.name, {}, derivation.plan};
  std::filesystem::create_directories(options.output_dir);
  for (const EmittedFile& file : emit_spatial_files(model, derivation, options)) {
    const std::string path = (std::filesystem::path(options.output_dir) / file.name).string();
    std::ofstream out(path, std::ios::binary);
    out << file.text;
    if (!out) throw std::runtime_error("cannot write " + path);
    result.written.push_back(path);
  }
  return result;
}

}  // namespace mechgen::gen
