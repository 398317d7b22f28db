#include "model/parameter_resolver.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "model/units.hpp"

namespace mechgen {

namespace {

std::string first_line(const std::string& message) {
  std::string line = message.substr(0, message.find('\n'));  // drop GiNaC's source trailer
  const std::string position = "parse error at line 0, column 0: ";
  const auto at = line.find(position);
  return at == std::string::npos ? line : line.substr(at + position.size());
}

}  // namespace

std::string yaml_special_number(std::string text) {
  if (!text.empty() && (text[0] == '+' || text[0] == '-')) text.erase(0, 1);
  for (const char* special : {".inf", ".Inf", ".INF", ".nan", ".NaN", ".NAN"})
    if (text == special)
      return std::string("is YAML's ") +
             (text[1] == 'i' || text[1] == 'I' ? "infinity" : "not-a-number") +
             ": mechgen takes finite numbers only";
  return "";
}

namespace {

// The names an expression uses, found by parsing it without a table of known names.
std::set<std::string> names_used(const ParameterEntry& e, const GiNaC::ex& t) {
  GiNaC::symtab open{{"pi", GiNaC::Pi}, {"t", t}};
  GiNaC::ex parsed;
  if (const std::string why = yaml_special_number(e.text); !why.empty())
    throw ModelError(e.value_loc, "parameter '" + e.name + "' value '" + e.text + "' " + why);
  try {
    GiNaC::parser parse(open, false);
    parsed = parse(e.text);
  } catch (const GiNaC::pole_error& error) {
    throw ModelError(e.value_loc, "parameter '" + e.name + "' value '" + e.text +
                                      "' cannot be evaluated (" + first_line(error.what()) + ")");
  } catch (const std::exception& error) {
    throw ModelError(e.value_loc, "parameter '" + e.name + "' value '" + e.text +
                                      "': syntax error (" + first_line(error.what()) + ")");
  }
  if (parsed.has(t))
    throw ModelError(e.value_loc,
                     "parameter '" + e.name + "' value '" + e.text + "' may not depend on time t");
  std::set<std::string> names;
  for (GiNaC::const_preorder_iterator i = parsed.preorder_begin(); i != parsed.preorder_end(); ++i)
    if (GiNaC::is_a<GiNaC::symbol>(*i)) names.insert(GiNaC::ex_to<GiNaC::symbol>(*i).get_name());
  return names;
}

bool plain_number(const std::string& text, double& value) {
  size_t used = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    return false;
  }
  return used == text.size() && std::isfinite(value);
}

std::string number_text(double value) {
  std::ostringstream out;
  out.precision(12);
  out << value;
  return out.str();
}

class Resolver {
 public:
  Resolver(const std::vector<ParameterEntry>& entries, Model& model, GiNaC::symtab& table)
      : entries_(entries), model_(model), table_(table) {}

  void run() {
    for (size_t i = 0; i < entries_.size(); ++i) index_[entries_[i].name] = i;
    uses_.resize(entries_.size());
    std::vector<double> constant(entries_.size(), 0);
    std::vector<bool> derived(entries_.size(), false);
    for (size_t i = 0; i < entries_.size(); ++i) {
      const ParameterEntry& e = entries_[i];
      if (plain_number(e.text, constant[i])) continue;
      for (const std::string& name : names_used(e, model_.t)) {
        if (!index_.count(name)) {
          std::string known;
          for (const ParameterEntry& p : entries_) known += (known.empty() ? "" : ", ") + p.name;
          throw ModelError(e.value_loc, "parameter '" + e.name + "' value '" + e.text +
                                            "': undefined name '" + name +
                                            "' (parameters: " + known + ")");
        }
        uses_[i].push_back(name);
      }
      if (uses_[i].empty())
        constant[i] = model_.evaluate(Expr{parse_strict(e), e.text, e.value_loc}, {});
      else
        derived[i] = true;
    }
    for (size_t i = 0; i < entries_.size(); ++i)
      if (!derived[i]) add_base(entries_[i], constant[i]);
    state_.assign(entries_.size(), 0);
    for (size_t i = 0; i < entries_.size(); ++i)
      if (derived[i]) visit(i);
  }

 private:
  GiNaC::ex parse_strict(const ParameterEntry& e) const {
    try {
      GiNaC::parser parse(table_, true);
      return parse(e.text);
    } catch (const std::exception& error) {
      throw ModelError(e.value_loc, "parameter '" + e.name + "' value '" + e.text +
                                        "': " + first_line(error.what()));
    }
  }

  UnitConversion unit_of(const ParameterEntry& e) const {
    const std::optional<UnitConversion> unit = find_unit(e.unit);
    if (!unit)
      throw ModelError(e.unit_loc, "parameter '" + e.name + "': unknown unit '" + e.unit +
                                       "' (known units: " + known_units() + ")");
    return *unit;
  }

  void add_base(const ParameterEntry& e, double written) {
    Parameter p;
    p.name = e.name;
    p.loc = e.name_loc;
    p.doc = e.doc;
    p.value = written;
    if (e.has_unit) {
      const UnitConversion unit = unit_of(e);
      p.unit = unit.si;
      if (unit.factor != 1) {
        p.value = written * unit.factor;
        p.written = number_text(written) + " " + e.unit;
      }
    }
    p.symbol = GiNaC::symbol(p.name);
    table_[p.name] = p.symbol;
    model_.parameters.push_back(p);
  }

  // Depth first: a derived parameter after everything it uses; a name met again while its own
  // definition is being resolved closes a cycle.
  void visit(size_t i) {
    if (state_[i] == 2) return;
    const ParameterEntry& e = entries_[i];
    path_.push_back(e.name);
    if (state_[i] == 1) {
      std::string cycle;
      for (auto at = std::find(path_.begin(), path_.end(), e.name); at != path_.end(); ++at)
        cycle += (cycle.empty() ? "" : " -> ") + *at;
      const ParameterEntry& closing = entries_[index_.at(path_[path_.size() - 2])];
      throw ModelError(closing.value_loc, "parameters defined in a cycle: " + cycle +
                                              " (a derived parameter may not depend on itself)");
    }
    state_[i] = 1;
    for (const std::string& name : uses_[i]) visit(index_.at(name));
    path_.pop_back();
    state_[i] = 2;
    if (uses_[i].empty()) return;  // a base parameter
    DerivedParameter d;
    d.name = e.name;
    d.loc = e.name_loc;
    d.doc = e.doc;
    d.uses = uses_[i];
    d.value = Expr{parse_strict(e), e.text, e.value_loc};
    if (e.has_unit) {
      const UnitConversion unit = unit_of(e);
      if (unit.factor != 1)
        throw ModelError(e.unit_loc, "parameter '" + e.name + "' is derived, so computed in SI " +
                                         "from the SI values of " + list(d.uses) +
                                         ": its unit must be '" + unit.si + "', not '" + e.unit +
                                         "'");
      d.unit = unit.si;
    }
    model_.evaluate(d.value, model_.substitutions(model_.default_parameters()));
    table_[d.name] = d.value.ex;
    model_.derived.push_back(d);
  }

  static std::string list(const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& n : names) text += (text.empty() ? "" : ", ") + n;
    return text;
  }

  const std::vector<ParameterEntry>& entries_;
  Model& model_;
  GiNaC::symtab& table_;
  std::map<std::string, size_t> index_;
  std::vector<std::vector<std::string>> uses_;
  std::vector<int> state_;  // 0 unvisited, 1 being resolved, 2 done
  std::vector<std::string> path_;
};

}  // namespace

void resolve_parameters(const std::vector<ParameterEntry>& entries, Model& model,
                        GiNaC::symtab& table) {
  Resolver(entries, model, table).run();
}

}  // namespace mechgen
