#include "kernel_emitter.hpp"

#include <charconv>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "code_block.hpp"
#include "forward_dynamics_emit.hpp"
#include "latency_schedule.hpp"
#include "model/columns.hpp"
#include "model/fingerprint.hpp"
#include "output_checks.hpp"
#include "template_renderer.hpp"

namespace mechgen::gen {

using GiNaC::ex;

namespace {

// `scalar`(value): T in functions, Real in the structs that hold the model's names.
std::string literal(double value, const std::string& scalar = "T") {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  std::string text(buffer, result.ptr);
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  return scalar + "(" + text + ")";
}

std::string quoted_list(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "\"" : ", \"") + item + "\"";
  return text;
}

bool ends_with(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += (text.empty() ? "" : "\n") + line;
  return text;
}

// The outputs whose finiteness a kernel checks: every State field it writes, except constants
// (finite by construction) and the warm start.
std::vector<CheckedOutput> checked_outputs(const std::vector<Output>& outputs) {
  std::vector<CheckedOutput> checked;
  for (const Output& o : outputs)
    if (!GiNaC::is_a<GiNaC::numeric>(o.value) && stage_of(o.target) != OutputStage::none)
      checked.push_back({stage_of(o.target), o.target});
  return checked;
}

class Emitter {
 public:
  Emitter(const Model& model, const Derivation& derivation, const StagedProgram& program,
          const EmitOptions& options)
      : model_(model), d_(derivation), program_(program), options_(options) {
    const std::vector<double> defaults = model.default_parameters();
    for (size_t i = 0; i < model.parameters.size(); ++i) {
      const Parameter& par = model.parameters[i];
      rename_[par.symbol] = options.bake ? ex(defaults[i]) : ex(GiNaC::symbol("p." + par.name));
    }
    rename_[model.t] = GiNaC::symbol("in.t");
    for (const Statement& st : program.statements())
      if (st.kind == Statement::Kind::define) definition_[st.symbol] = st.value;
  }

  // Straight-line code for `outputs` (target, value): only the statements they need, with the
  // checks on the way, in emission_order (each value computed right before its first use, each
  // output written as soon as it is known; a warm start for the next call only after every
  // check); `fail` maps a status and group to the statement run when a check fails.
  CodeBlock block(const std::vector<Output>& outputs,
                  const std::function<std::string(const std::string& status, int group)>& fail,
                  Readiness readiness = Readiness::latency) const {
    std::set<ex, GiNaC::ex_is_less> needed;
    std::vector<ex> pending;
    for (const Output& o : outputs) pending.push_back(o.value);
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
    // A kept check (an iterative group's convergence test) comes along with what it reads.
    for (const Statement& st : program_.statements()) {
      if (!st.keep || needed.count(st.symbol)) continue;
      const ex& def = definition_.at(st.symbol);
      bool inputs_computed = true;
      for (auto it = def.preorder_begin(); it != def.preorder_end(); ++it)
        if (GiNaC::is_a<GiNaC::symbol>(*it) && definition_.count(*it) && !needed.count(*it))
          inputs_computed = false;
      if (!inputs_computed) continue;
      needed.insert(st.symbol);
      for (auto it = def.preorder_begin(); it != def.preorder_end(); ++it)
        if (GiNaC::is_a<GiNaC::symbol>(*it)) needed.insert(*it);
    }
    CodeBlock code;
    code.invert_every_denominator();
    std::vector<ex> values;
    std::vector<bool> after_checks;
    for (const Output& o : outputs) {
      values.push_back(o.value);
      after_checks.push_back(o.target.rfind("s.warm.", 0) == 0);
    }
    for (const Step step :
         emission_order(program_.statements(), needed, values, after_checks, readiness)) {
      if (step.output) {
        const Output& o = outputs[step.index];
        code.assign(o.target, o.value.subs(rename_));
        continue;
      }
      const Statement& st = program_.statements()[step.index];
      switch (st.kind) {
        case Statement::Kind::define:
          code.define(st.symbol.get_name(), st.value.subs(rename_));
          break;
        case Statement::Kind::check_positive:
          code.guard(st.symbol, ">", fail(st.failure, st.group));
          break;
        case Statement::Kind::check_nonzero:
          code.guard(st.symbol, "!=", fail(st.failure, st.group));
          break;
      }
    }
    const std::vector<std::string> unused = code.unused_definitions();
    if (!unused.empty()) throw std::logic_error("generated code would define unused " + unused[0]);
    return code;
  }

  // sin, cos and atan2 come from the kernel's own branch-free detail:: versions, in the scalar
  // entries as in evaluate_batch: the two then agree to the last bit, and atan2 costs a fraction
  // of the C library's (about 140 instructions a call there; 23 calls a PASIBOT sample in the
  // batch, none in evaluate(), whose State keeps each orientation as its cosine and sine).
  static bool has_kernel_version(const std::string& f) {
    return f == "sin" || f == "cos" || f == "atan2";
  }
  static std::string using_lines(const CodeBlock& code) {
    std::string text;
    for (const std::string& f : code.math_functions())
      text += std::string(text.empty() ? "" : "\n") + "  using " +
              (has_kernel_version(f) ? "detail::" : "std::") + f + ";";
    return text;
  }

  std::map<std::string, std::string> values(const SolvePlan& plan) const {
    std::map<std::string, std::string> v;
    const std::vector<double> defaults = model_.default_parameters();
    v["model"] = model_.name;
    v["source"] = options_.source;
    v["command"] = options_.command;
    v["fingerprint"] = hex64(options_.fingerprint);
    v["description"] = model_.description.empty() ? "(no description)" : model_.description;
    v["ground"] = model_.bodies[static_cast<size_t>(model_.ground)].name;
    v["reference"] = model_.bodies[static_cast<size_t>(plan.reference)].name;
    std::vector<std::string> plan_lines;
    for (size_t g = 0; g < plan.groups.size(); ++g) {
      std::string line = "//   " + describe(model_, plan.groups[g]);
      for (const std::string& note : d_.notes)
        if (note.rfind(plan.groups[g].name + ":", 0) == 0)
          line += ";" + note.substr(plan.groups[g].name.size() + 1);
      plan_lines.push_back(line);
    }
    v["plan"] = joined(plan_lines);

    std::vector<std::string> params, set_params, names;
    for (size_t i = 0; i < model_.parameters.size(); ++i) {
      const Parameter& par = model_.parameters[i];
      std::string comment = par.unit.empty() ? "" : par.unit;
      if (!par.written.empty()) comment += " (" + par.written + " in the model)";
      if (!par.doc.empty()) comment += (comment.empty() ? "" : ": ") + par.doc;
      params.push_back("  Real " + par.name + " = " + literal(defaults[i], "Real") + ";" +
                       (comment.empty() ? "" : "  // " + comment));
      set_params.push_back("  p." + par.name + " = values[" + std::to_string(i) + "];");
      names.push_back(par.name);
    }
    if (!model_.derived.empty())
      params.push_back(
          "\n  // Derived parameters: not fields but computed from the fields above (the kernel "
          "uses\n"
          "  // the same expressions inline), so setting a field moves them too.");
    // Inside a derived function T is the scalar type: a parameter named T is read first.
    GiNaC::exmap member_named_T;
    for (const Parameter& par : model_.parameters)
      if (par.name == "T") member_named_T[par.symbol] = GiNaC::symbol("T_member_");
    for (const DerivedParameter& d : model_.derived) {
      CodeBlock block("_" + d.name + "_");
      // The code is the kernels' (scalar T); a parameter itself named T is the member.
      block.assign("const T value", d.value.ex.subs(member_named_T));
      bool reads_T = false;
      for (const auto& [symbol, member] : member_named_T)
        reads_T = reads_T || d.value.ex.has(symbol);
      std::string function =
          "  Real " + d.name + "() const noexcept {  // " + d.value.text +
          (d.unit.empty() ? "" : " [" + d.unit + "]") + (d.doc.empty() ? "" : ": " + d.doc) + "\n" +
          (reads_T ? "    const Real T_member_ = this->T;\n" : "") + "    using T = Real;\n";
      for (const std::string& f : block.math_functions()) function += "    using std::" + f + ";\n";
      function += block.render("    ") + "    return value;\n  }";
      params.push_back(function);
    }
    v["param_fields"] = joined(params);
    v["set_parameters_body"] = joined(set_params);
    v["parameter_count"] = std::to_string(model_.parameters.size());
    v["parameter_names"] = quoted_list(names);

    std::vector<std::string> inputs, bodies, points, joints, drivers;
    for (const Driver& dr : model_.drivers)
      inputs.push_back("  Real " + dr.name + " = Real(0), " + dr.name + "_d = Real(0), " + dr.name +
                       "_dd = Real(0);  // " + (dr.kind == DriverKind::angle ? "rad" : "m"));
    for (const Body& b : model_.bodies)
      if (!b.ground) bodies.push_back("    BodyState<Real> " + b.name + ";");
    for (const auto& [point, locator] : model_.named_points())
      points.push_back("    PointState<Real> " + point + ";");
    for (const Joint& j : model_.joints)
      joints.push_back(std::string(j.type == JointType::prismatic ? "    JointForceMoment<Real> "
                                                                  : "    JointForce<Real> ") +
                       j.name + ";  // " + to_string(j.type));
    for (const Driver& dr : model_.drivers)
      drivers.push_back("    DriverState<Real> " + dr.name + ";");
    v["input_fields"] = joined(inputs);
    std::string checks;
    for (const Driver& dr : model_.drivers)
      for (const char* suffix : {"", "_d", "_dd"})
        checks += " && isfinite(in." + dr.name + suffix + ")";
    v["input_checks"] = checks;
    v["body_fields"] = joined(bodies);
    // Start values of the iterative groups: the last solution, so a state reused along a sweep
    // warm-starts Newton-Raphson; a new state starts from the assembly.
    std::string warm;
    if (!d_.warm_start.empty()) {
      warm = "  struct Warm {  // iterative groups' start angles (reference frame)\n";
      for (const auto& [field, value] : d_.warm_start)
        warm += "    Real " + field + " = " + literal(value, "Real") + ";\n";
      warm += "  } warm;\n";
    }
    v["warm_fields"] = warm;
    v["failed_note"] = warm.empty() ? "" : "; the iterative groups' warm start is kept";
    v["failed_body"] = warm.empty() ? "  s = State<T>{};\n"
                                      "  s.failed_group = group;\n"
                                      "  return status;"
                                    : "  const auto warm = s.warm;\n"
                                      "  s = State<T>{};\n"
                                      "  s.warm = warm;\n"
                                      "  s.failed_group = group;\n"
                                      "  return status;";
    v["ne_state"] =
        warm.empty() ? "" : "  State<T> s;  // iterative groups start from the assembly\n";
    // Samples of a batch are independent: each starts its iterative groups from the assembly.
    v["batch_state"] =
        warm.empty() ? "" : "    State<T> s;  // iterative groups start from the assembly\n";
    v["point_fields"] = joined(points);
    v["joint_fields"] = joined(joints);
    v["driver_fields"] = joined(drivers);
    // The solve groups, then the stages whose checks follow them (output_checks.hpp).
    std::vector<std::string> group_names = d_.group_names;
    const int inputs_group = static_cast<int>(group_names.size());
    for (const char* stage : kStageNames) group_names.push_back(stage);
    v["group_count"] = std::to_string(group_names.size());
    v["solve_group_count"] = std::to_string(d_.group_names.size());
    v["group_names"] = quoted_list(group_names);
    v["inputs_group"] = std::to_string(inputs_group);
    auto stage_check = [inputs_group](OutputStage stage, const std::string& condition) {
      return "if (!(" + condition + ")) return detail::failed(s, " +
             std::to_string(inputs_group + static_cast<int>(stage)) + ", Status::non_finite);";
    };

    // A Newton-Euler pivot belongs to no solve group: it names the "forces" stage.
    const int forces_group = inputs_group + static_cast<int>(OutputStage::forces);
    auto state_fail = [forces_group](const std::string& status, int group) {
      return "return detail::failed(s, " + std::to_string(group < 0 ? forces_group : group) +
             ", Status::" + status + ");";
    };
    auto plain_fail = [](const std::string& status, int) {
      return "return Status::" + status + ";";
    };
    const CodeBlock kin = block(d_.kinematics, state_fail);
    std::vector<Output> all = d_.kinematics;
    all.insert(all.end(), d_.dynamics.begin(), d_.dynamics.end());
    const CodeBlock full = block(all, state_fail);
    const size_t n = d_.ne_unknowns.size();
    std::vector<Output> ne;
    for (size_t r = 0; r < n; ++r) {
      for (size_t c = 0; c < n; ++c) {
        const ex& a = d_.ne_matrix[r * n + c];
        if (!a.is_zero()) ne.push_back({"A[" + std::to_string(r * n + c) + "]", a});
      }
      ne.push_back({"b[" + std::to_string(r) + "]", d_.ne_rhs[r]});
    }
    const CodeBlock system = block(ne, plain_fail);
    v["kinematics_using"] = using_lines(kin);
    v["kinematics_ops"] = std::to_string(kin.op_count());
    v["kinematics_body"] =
        kin.render("  ") + output_checks(checked_outputs(d_.kinematics), "  ", stage_check);
    v["evaluate_using"] = using_lines(full);
    v["evaluate_ops"] = std::to_string(full.op_count());
    v["evaluate_body"] = full.render("  ") + output_checks(checked_outputs(all), "  ", stage_check);
    v["ne_using"] = using_lines(system);
    v["ne_ops"] = std::to_string(system.op_count());
    std::vector<CheckedOutput> system_outputs;
    for (const Output& o : ne)
      if (!GiNaC::is_a<GiNaC::numeric>(o.value))
        system_outputs.push_back({OutputStage::forces, o.target});
    v["ne_body"] = system.render("  ") +
                   output_checks(system_outputs, "  ", [](OutputStage, const std::string& c) {
                     return "if (!(" + c + ")) return Status::non_finite;";
                   });
    v["ne_size"] = std::to_string(n);
    v["ne_unknowns"] = quoted_list(d_.ne_unknowns);

    // The model's driver motion: q(t) and its exact derivatives.
    CodeBlock motion;
    GiNaC::exmap rename = rename_;
    rename[model_.t] = GiNaC::symbol("t");
    for (const Driver& dr : model_.drivers) {
      motion.assign("in." + dr.name, dr.value.ex.subs(rename));
      motion.assign("in." + dr.name + "_d", dr.value_d.subs(rename));
      motion.assign("in." + dr.name + "_dd", dr.value_dd.subs(rename));
    }
    v["drivers_using"] = using_lines(motion);
    v["drivers_body"] = motion.render("  ");

    const std::vector<std::string> columns = column_names(model_);
    std::vector<std::string> to_columns, sources;
    for (size_t i = 0; i < columns.size(); ++i) {
      const std::string& c = columns[i];
      std::string source;
      const auto dot = c.find('.');
      if (c == "t") {
        source = "in.t";
      } else {
        const std::string owner = c.substr(0, dot), field = c.substr(dot + 1);
        std::string group = "points";
        if (model_.body_index(owner) >= 0) group = "bodies";
        for (const Joint& j : model_.joints)
          if (j.name == owner) group = "joints";
        for (const Driver& dr : model_.drivers)
          if (dr.name == owner) group = "drivers";
        source = "s." + group + "." + owner + "." + field;
        if (group == "bodies" && field == "th") source += "()";  // from cos_th and sin_th
      }
      to_columns.push_back("  row[" + std::to_string(i) + "] = " + source + ";");
      sources.push_back(source);
    }
    v["column_count"] = std::to_string(columns.size());
    batch_values(columns, sources, all, inputs_group, v);
    v["column_names"] = quoted_list(columns);
    v["to_columns_body"] = joined(to_columns);
    return v;
  }

  // Result encoding of evaluate_batch's checks (see batch_values); the template decodes with
  // batch_code_range.
  static constexpr int kFirstCheckRank = 2000;  // weights below 2^24: exact in float too
  static constexpr int kCodeRange = 4096;

  // evaluate_batch: the evaluate() block with every output written to its column and every check
  // folded into the sample's result code instead of returning.
  void batch_values(const std::vector<std::string>& columns,
                    const std::vector<std::string>& sources, const std::vector<Output>& all,
                    int inputs_group, std::map<std::string, std::string>& v) const {
    std::map<std::string, size_t> column_of;
    for (size_t c = 0; c < sources.size(); ++c) column_of[sources[c]] = c;
    auto target = [&](const std::string& source) {
      const auto it = column_of.find(source);
      if (it == column_of.end()) throw std::logic_error("output " + source + " is not a column");
      return "out[" + std::to_string(it->second) + " * stride + i]";
    };
    std::vector<Output> outputs{{target("in.t"), model_.t}};
    std::vector<CheckedOutput> checked;
    std::map<std::string, ex> value_of;
    for (const Output& o : all) value_of[o.target] = o.value;
    for (const Output& o : all) {
      // The warm start kept for a next call has no column; a body's orientation is its angle.
      if (o.target.rfind("s.warm.", 0) == 0 || ends_with(o.target, ".sin_th")) continue;
      if (ends_with(o.target, ".cos_th")) {
        const std::string body = o.target.substr(0, o.target.size() - 6);
        outputs.push_back(
            {target(body + "th()"), GiNaC::atan2(value_of.at(body + "sin_th"), o.value)});
      } else {
        outputs.push_back({target(o.target), o.value});
      }
      if (!GiNaC::is_a<GiNaC::numeric>(o.value))
        checked.push_back({stage_of(o.target), outputs.back().target});
    }
    if (outputs.size() != columns.size())
      throw std::logic_error("evaluate_batch would leave columns unwritten");
    const int forces_group = inputs_group + static_cast<int>(OutputStage::forces);
    auto code = [forces_group](const std::string& status, int group) {
      return std::to_string((status == "unreachable" ? 1
                             : status == "singular"  ? 2
                                                     : 3) +
                            4 * ((group < 0 ? forces_group : group) + 1));
    };
    // Roots ready in program order: in the vectorised loop that order's placement measured faster
    // (about 5 %) than latency order's, which keeps more vectors alive.
    const CodeBlock batch = block(outputs, code, Readiness::program);
    // Functions without a detail:: version (acos, ...) stay library calls: the batch is then
    // correct but not vectorised.
    const std::string using_text = using_lines(batch);
    std::vector<std::string> fields, inputs, locals;
    std::string checks;
    for (const Driver& dr : model_.drivers)
      for (const char* suffix : {"", "_d", "_dd"}) {
        const std::string name = dr.name + suffix;
        fields.push_back("  const Real* " + name + " = nullptr;");
        inputs.push_back("    in." + name + " = batch_" + name + "[i];");
        locals.push_back("  const T* const batch_" + name + " = inputs." + name + ";");
        checks += " + (in." + name + " - in." + name + ")";
      }
    std::vector<std::string> pointers, stores;
    int slot = 0;
    for (const Driver& dr : model_.drivers)
      for (const char* suffix : {"", "_d", "_dd"}) {
        const std::string name = dr.name + suffix;
        pointers.push_back("  batch." + name + " = storage + " + std::to_string(slot) + " * n;");
        stores.push_back("    storage[" + std::to_string(slot) + " * n + i] = in." + name + ";");
        ++slot;
      }
    v["batch_storage_per_sample"] = std::to_string(slot);
    v["batch_pointers"] = joined(pointers);
    v["batch_stores"] = joined(stores);
    v["batch_input_fields"] = joined(fields);
    v["batch_code_range"] = std::to_string(kCodeRange);
    v["batch_input_weight"] = std::to_string(static_cast<long>(kFirstCheckRank + 1) * kCodeRange +
                                             1 + 4 * (inputs_group + 1));
    v["batch_inputs"] = joined(inputs);
    v["batch_pointers_local"] = joined(locals);
    v["batch_input_checks"] = checks;
    v["batch_using"] = using_text;
    v["batch_ops"] = std::to_string(batch.op_count());
    // The first failing check wins: check k (in program order) contributes
    // (kFirstCheckRank - k) * kCodeRange + code when it fails, and a running maximum keeps the
    // earliest; no branch, and no boolean logic that GCC 12 cannot vectorise.
    int rank = kFirstCheckRank;
    std::string body =
        batch.render("    ", [&rank](const std::string& condition, const std::string& c) {
          const long weight = static_cast<long>(rank--) * kCodeRange + std::stol(c);
          return "failed = max(failed, (" + condition + ") ? T(0) : T(" + std::to_string(weight) +
                 "));";
        });
    // Then the outputs' finiteness, stage by stage, after every other check.
    body += output_checks(checked, "    ",
                          [&rank, inputs_group](OutputStage stage, const std::string& condition) {
                            const long weight = static_cast<long>(rank--) * kCodeRange + 3 +
                                                4 * (inputs_group + static_cast<int>(stage) + 1);
                            return "failed = max(failed, (" + condition + ") ? T(0) : T(" +
                                   std::to_string(weight) + "));";
                          });
    if (rank <= 0) throw std::logic_error("evaluate_batch: too many checks");
    if (!body.empty() && body.back() == '\n') body.pop_back();
    v["batch_body"] = body;
  }

 private:
  const Model& model_;
  const Derivation& d_;
  const StagedProgram& program_;
  const EmitOptions& options_;
  GiNaC::exmap rename_;
  std::map<ex, ex, GiNaC::ex_is_less> definition_;
};

}  // namespace

std::vector<EmittedFile> emit_kernel(const Model& model, const SolvePlan& plan,
                                     const Derivation& derivation, const StagedProgram& program,
                                     const EmitOptions& options) {
  Emitter emitter(model, derivation, program, options);
  std::map<std::string, std::string> values = emitter.values(plan);
  // Driven evaluation (a motion other than the model's own, e.g. a start from rest): the driver
  // inputs are read from a flat array, (q, qd, qdd) per driver in model order.
  std::string driven_inputs;
  std::vector<std::string> coordinates;
  for (size_t i = 0; i < model.drivers.size(); ++i) {
    coordinates.push_back(model.drivers[i].name);
    for (size_t k = 0; k < 3; ++k)
      driven_inputs += std::string(driven_inputs.empty() ? "" : "\n") + "in." +
                       model.drivers[i].name +
                       (k == 0   ? ""
                        : k == 1 ? "_d"
                                 : "_dd") +
                       " = static_cast<T>(drivers[" + std::to_string(3 * i + k) + "]);";
  }
  // The driven batch: evaluate_batch's inputs read from the drivers' arrays (its storage layout).
  std::string driven_batch;
  for (size_t i = 0; i < model.drivers.size(); ++i)
    for (size_t k = 0; k < 3; ++k)
      driven_batch += std::string(driven_batch.empty() ? "" : "\n") + "  batch." +
                      model.drivers[i].name +
                      (k == 0   ? ""
                       : k == 1 ? "_d"
                                : "_dd") +
                      " = drivers + " + std::to_string(3 * i + k) + " * n;";
  const ForwardDynamicsText dynamics =
      emit_forward_dynamics(options.templates_dir, coordinates, driven_inputs, "State<T> s;");
  values["forward_dynamics"] = dynamics.header;
  std::vector<EmittedFile> files;
  const std::string kernel = options.templates_dir + "/kernel.hpp.in";
  files.push_back(
      {model.name + ".hpp", render_template(read_template(kernel), values, "kernel.hpp.in")});
  std::map<std::string, std::string> entry_values{
      {"model", values["model"]},
      {"source", values["source"]},
      {"command", values["command"]},
      {"driver_count", std::to_string(model.drivers.size())},
      {"driven_inputs", driven_inputs},
      {"forward_dynamics_entry", dynamics.entry},
      {"driven_batch_pointers", driven_batch}};
  const std::string entry = options.templates_dir + "/kernel_entry.cpp.in";
  files.push_back({model.name + "_entry.cpp",
                   render_template(read_template(entry), entry_values, "kernel_entry.cpp.in")});
  return files;
}

}  // namespace mechgen::gen
