// The YAML and expression reading that planar and spatial descriptions share. The planar reader
// (model_reader.cpp) implements it, so a spatial description gets the same parameters, names,
// expressions and messages; spatial_reader.cpp reads the spatial elements through it.
#pragma once

#include <yaml-cpp/yaml.h>

#include <set>
#include <string>

#include "model/model.hpp"

namespace mechgen {

struct SpatialModel;

class DescriptionSyntax {
 public:
  virtual ~DescriptionSyntax() = default;
  virtual SourceLoc loc(const YAML::Node& node) const = 0;
  virtual void expect_keys(const YAML::Node& node, const std::string& what,
                           const std::set<std::string>& allowed) const = 0;
  virtual YAML::Node required(const YAML::Node& parent, const std::string& key,
                              const std::string& what) const = 0;
  virtual std::string scalar(const YAML::Node& node, const std::string& what) const = 0;
  virtual std::string identifier(const YAML::Node& node, const std::string& what) const = 0;
  // `true` or `false` (`what` names the key in the message otherwise).
  virtual bool flag(const YAML::Node& node, const std::string& what) const = 0;
  // An expression of the parameters (and of t when time_allowed).
  virtual Expr expression(const YAML::Node& node, const std::string& what,
                          bool time_allowed) const = 0;
  // A driver's `effort:` law: an expression of the parameters, t and the driver's own coordinate
  // and rate, written `q` and `qd` (Model::driver_q, Model::driver_qd).
  virtual Expr effort_law(const YAML::Node& node, const std::string& what) const = 0;
};

// A driver's `passive: true` (planar and spatial): an undriven coordinate, such as a joint's
// spring, whose effort is always its `effort:` law (which it must have; ModelError at the key
// otherwise). False when the key is absent.
bool passive_driver(const YAML::Node& driver, const DescriptionSyntax& syntax,
                    const std::string& what);

// Why a name cannot be a field of a generated kernel (a C++ keyword, a name the kernels use,
// `__`): empty when it can. Every reader refuses such names; `mechgen import` renames them.
std::string reserved_name_reason(const std::string& name);

// The text of a description file; ModelError when it is missing, a directory or unreadable.
std::string read_description_file(const std::string& path);

// The top-level keys of a spatial description besides those every description has.
const std::set<std::string>& spatial_description_keys();

// Reads gravity, bodies, joints and drivers of a spatial description; `common` already holds the
// name, description, parameters and step. Throws ModelError.
SpatialModel read_spatial_elements(const YAML::Node& root, const DescriptionSyntax& syntax,
                                   Model common);

}  // namespace mechgen
