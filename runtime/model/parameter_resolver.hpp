// The `parameters:` block of a description, resolved: units converted to SI, and derived
// parameters (a value that is an expression of other parameters) put in dependency order, with
// cycles and undefined names reported at their location. Read by model_reader.cpp.
#pragma once

#include <ginac/ginac.h>

#include <string>
#include <vector>

#include "model/model.hpp"

namespace mechgen {

// One parameter as the file writes it.
struct ParameterEntry {
  std::string name;
  SourceLoc name_loc;
  std::string text;  // the value: a number or an expression
  SourceLoc value_loc;
  bool has_unit = false;
  std::string unit;
  SourceLoc unit_loc;
  std::string doc;
};

// Fills model.parameters (the base parameters: a number, or an expression of no parameter, such
// as pi/2, converted to SI; file order) and model.derived (dependency order). `table` receives
// each base parameter's symbol and each derived parameter's expression in those symbols, so that
// every later expression naming a derived parameter uses its definition. Throws ModelError.
// "is YAML's infinity: ..." for YAML 1.2's .inf, -.inf, +.inf, .nan (in their three spellings),
// which GiNaC would misread; "" for any other text.
std::string yaml_special_number(std::string text);

void resolve_parameters(const std::vector<ParameterEntry>& entries, Model& model,
                        GiNaC::symtab& table);

}  // namespace mechgen
