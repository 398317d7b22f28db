// Shared stages of a large spatial kernel (spatial_shared_stages.hpp).
#include "spatial_shared_stages.hpp"

#include <algorithm>
#include <set>
#include <stdexcept>

namespace mechgen::gen {

using GiNaC::ex;
using SymbolSet = std::set<ex, GiNaC::ex_is_less>;

namespace {

// The symbols an expression reads directly (not through their definitions).
void read_symbols(const ex& e, SymbolSet& into) {
  for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (GiNaC::is_a<GiNaC::symbol>(*it)) into.insert(*it);
}

// One block of the program: the definitions `own` in program order, each reading what earlier
// stages computed from the workspace, then the outputs, then (a stage) what later code reads.
CodeBlock block(const StagedProgramView& program, const SymbolSet& own,
                const GiNaC::exmap& from_shared, const std::vector<SpatialOutput>& outputs,
                const SymbolSet& exported) {
  CodeBlock code;
  for (const auto& [symbol, value] : program.definitions) {
    if (!own.count(symbol)) continue;
    code.define(symbol.get_name(), value.subs(from_shared, GiNaC::subs_options::no_pattern));
    program.after_define(code, symbol);
  }
  for (const SpatialOutput& o : outputs)
    code.assign(o.target, o.value.subs(from_shared, GiNaC::subs_options::no_pattern));
  for (const auto& [symbol, value] : program.definitions)
    if (own.count(symbol) && exported.count(symbol)) code.assign("w." + symbol.get_name(), symbol);
  const std::vector<std::string> unused = code.unused_definitions();
  if (!unused.empty()) throw std::logic_error("shared stage would define unused " + unused[0]);
  return code;
}

}  // namespace

StagedKernel emit_shared_stages(const StagedProgramView& program,
                                const std::vector<SharedStage>& stages,
                                const std::vector<StagedEntry>& entries) {
  SymbolSet defined;
  for (const auto& [symbol, value] : program.definitions) {
    // `w` is the workspace's name in the emitted code.
    if (symbol.get_name() == "w") throw std::logic_error("a definition is named w");
    defined.insert(symbol);
  }
  const auto own_definitions = [&](std::vector<SpatialOutput> outputs,
                                   const std::vector<GiNaC::ex>& quantities,
                                   const SymbolSet& before) {
    for (const ex& q : quantities) outputs.push_back({"", q});
    SymbolSet own;
    for (const ex& x : program.needed(outputs))
      if (defined.count(x) && !before.count(x)) own.insert(x);
    return own;
  };
  // What each stage defines, and what the stages it follows defined (a name two stages that do
  // not follow one another both need is defined by both).
  std::vector<SymbolSet> stage_own, stage_before;
  const auto union_of = [&](const std::vector<size_t>& list) {
    SymbolSet all;
    for (const size_t k : list) {
      if (k >= stage_own.size()) throw std::logic_error("shared stage used before it is defined");
      all.insert(stage_own[k].begin(), stage_own[k].end());
    }
    return all;
  };
  // Every stage a list runs must have the stages it follows in the list before it.
  const auto check_order = [&](const std::vector<size_t>& list, const std::string& who) {
    for (size_t i = 0; i < list.size(); ++i)
      for (const size_t k : stages.at(list[i]).after)
        if (std::find(list.begin(), list.begin() + static_cast<long>(i), k) ==
            list.begin() + static_cast<long>(i))
          throw std::logic_error(who + " runs " + stages[list[i]].name + " before " +
                                 stages[k].name);
  };
  for (size_t k = 0; k < stages.size(); ++k) {
    check_order(stages[k].after, stages[k].name);
    stage_before.push_back(union_of(stages[k].after));
    stage_own.push_back(own_definitions(stages[k].outputs, stages[k].quantities, stage_before[k]));
  }
  std::vector<SymbolSet> entry_before, entry_own;
  for (const StagedEntry& e : entries) {
    check_order(e.stages, e.name);
    entry_before.push_back(union_of(e.stages));
    entry_own.push_back(own_definitions(e.outputs, {}, entry_before.back()));
  }

  // The workspace: every quantity a stage defines that a later stage or an entry's tail reads.
  SymbolSet shared;
  const auto collect = [&](const SymbolSet& own, const std::vector<SpatialOutput>& outputs,
                           const SymbolSet& before) {
    SymbolSet reads;
    for (const auto& [symbol, value] : program.definitions)
      if (own.count(symbol)) read_symbols(value, reads);
    for (const SpatialOutput& o : outputs) read_symbols(o.value, reads);
    for (const ex& x : reads)
      if (before.count(x)) shared.insert(x);
  };
  for (size_t k = 0; k < stages.size(); ++k)
    collect(stage_own[k], stages[k].outputs, stage_before[k]);
  for (size_t e = 0; e < entries.size(); ++e)
    collect(entry_own[e], entries[e].outputs, entry_before[e]);
  const auto from_shared = [&](const SymbolSet& before) {
    GiNaC::exmap map;
    for (const ex& x : shared)
      if (before.count(x)) map[x] = GiNaC::symbol("w." + GiNaC::ex_to<GiNaC::symbol>(x).get_name());
    return map;
  };

  StagedKernel kernel;
  // struct Shared: its fields in program order, grouped by the stage that writes them.
  std::string fields;
  SymbolSet declared;
  for (size_t k = 0; k < stages.size(); ++k) {
    std::string line, group;
    for (const auto& [symbol, value] : program.definitions) {
      if (!stage_own[k].count(symbol) || !shared.count(symbol) || !declared.insert(symbol).second)
        continue;
      const std::string name = symbol.get_name();
      if (!line.empty() && line.size() + name.size() + 2 > 96) {
        group += line + ";\n";
        line.clear();
      }
      line += (line.empty() ? "  T " : ", ") + name;
    }
    if (!line.empty()) fields += "  // from " + stages[k].name + "()\n" + group + line + ";\n";
  }
  kernel.functions =
      "namespace detail {\n"
      "// What a stage below computes and a later stage or an entry point reads: the workspace "
      "`w`, one\n// per call, on the entry point's stack.\n"
      "template <class T>\nstruct Shared {\n" +
      fields + "};\n\n";
  std::vector<int> stage_ops;
  for (size_t k = 0; k < stages.size(); ++k) {
    const CodeBlock code =
        block(program, stage_own[k], from_shared(stage_before[k]), stages[k].outputs, shared);
    stage_ops.push_back(code.op_count());
    const std::string using_lines = program.using_lines(code);
    kernel.functions += "// " + stages[k].doc + "\ntemplate <class T>\nStatus " + stages[k].name +
                        "([[maybe_unused]] const Params<T>& p, [[maybe_unused]] const "
                        "Inputs<T>& in,\n" +
                        std::string(stages[k].name.size() + 8, ' ') +
                        "[[maybe_unused]] State<T>& s, [[maybe_unused]] Shared<T>& w) "
                        "noexcept {\n" +
                        (using_lines.empty() ? "" : using_lines + "\n") +
                        "  // Total ops: " + std::to_string(code.op_count()) + "\n" +
                        code.render("  ") + "  return Status::ok;\n}\n\n";
  }
  kernel.functions += "}  // namespace detail\n\n";

  for (size_t e = 0; e < entries.size(); ++e) {
    const StagedEntry& entry = entries[e];
    const CodeBlock code =
        block(program, entry_own[e], from_shared(entry_before[e]), entry.outputs, SymbolSet{});
    std::string calls = "  detail::Shared<T> w;\n";
    int ops = code.op_count();
    for (const size_t k : entry.stages) {
      calls += "  if (const Status status = detail::" + stages[k].name +
               "(p, in, s, w); status != Status::ok) return status;\n";
      ops += stage_ops[k];
    }
    kernel.body[entry.name] = calls + code.render("  ");
    kernel.using_lines[entry.name] = program.using_lines(code);
    kernel.ops[entry.name] = ops;
  }
  return kernel;
}

}  // namespace mechgen::gen
