#include "model/value_checks.hpp"

#include <cmath>
#include <sstream>

namespace mechgen {

namespace {

std::string short_number(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

// The checks themselves, on the values `parameters` (substituted into every expression).
void check_all(const Model& model, const std::vector<double>& parameters) {
  for (size_t i = 0; i < model.parameters.size(); ++i)
    if (!std::isfinite(parameters[i]))
      throw ModelError(model.parameters[i].loc,
                       "parameter '" + model.parameters[i].name + "' is not finite");
  const GiNaC::exmap subs = model.substitutions(parameters);
  for (const Body& b : model.bodies) {
    for (const BodyPoint& p : b.points) {
      model.evaluate(p.local.x, subs);
      model.evaluate(p.local.y, subs);
    }
    if (b.ground) continue;
    const MassProperties& m = b.mass;
    if (m.source == MassProperties::Source::bars || m.source == MassProperties::Source::plate) {
      std::vector<const Expr*> sizes{&m.thickness, &m.density};
      if (m.source == MassProperties::Source::bars) sizes.push_back(&m.width);
      for (const Expr* e : sizes)
        if (model.evaluate(*e, subs) <= 0)
          throw ModelError(e->loc, "body '" + b.name + "': '" + e->text + "' must be positive");
    }
    if (m.source == MassProperties::Source::bar) {
      const std::pair<const char*, const Expr*> sizes[] = {
          {"width", &m.width}, {"thickness", &m.thickness}, {"density", &m.density}};
      for (const auto& [field, e] : sizes)
        if (model.evaluate(*e, subs) <= 0)
          throw ModelError(e->loc, "body '" + b.name + "': bar " + field + " '" + e->text +
                                       "' must be positive");
    }
    if (model.evaluate(m.mass, subs) <= 0)
      throw ModelError(m.mass.loc, "body '" + b.name + "' has a non-positive mass");
    if (model.evaluate(m.inertia, subs) <= 0)
      throw ModelError(m.inertia.loc, "body '" + b.name + "' has a non-positive inertia");
    model.evaluate(m.com.x, subs);
    model.evaluate(m.com.y, subs);
    if (b.assembly_angle) model.evaluate(*b.assembly_angle, subs);
    if (b.section) {
      const Section& s = *b.section;
      std::vector<const Expr*> sizes;
      if (s.shape == Section::Shape::rectangle)
        sizes = {&s.width, &s.thickness};
      else
        sizes = {&s.area, &s.inertia, &s.fibre};
      if (s.yield_strength) sizes.push_back(&*s.yield_strength);
      if (s.youngs_modulus) sizes.push_back(&*s.youngs_modulus);
      for (const Expr* e : sizes)
        if (model.evaluate(*e, subs) <= 0)
          throw ModelError(
              e->loc, "body '" + b.name + "': section value '" + e->text + "' must be positive");
    }
  }
  for (const std::optional<Expr>* value : {&model.yield_strength, &model.youngs_modulus})
    if (*value && model.evaluate(**value, subs) <= 0)
      throw ModelError((*value)->loc, "material value '" + (*value)->text + "' must be positive");
  for (const Joint& j : model.joints) {
    if (j.type == JointType::revolute) continue;
    const double dx = model.evaluate(j.line.direction.x, subs);
    const double dy = model.evaluate(j.line.direction.y, subs);
    if (dx * dx + dy * dy <= 0)
      throw ModelError(j.line.direction.x.loc, "joint '" + j.name + "': zero line direction");
    model.evaluate(j.line.through.x, subs);
    model.evaluate(j.line.through.y, subs);
    if (j.type == JointType::prismatic) model.evaluate(j.angle, subs);
  }
  model.evaluate(model.gravity.x, subs);
  model.evaluate(model.gravity.y, subs);
  GiNaC::exmap at_t0 = subs;
  at_t0[model.t] = model.evaluate(model.step.t0, subs);
  for (const Driver& d : model.drivers) model.evaluate(d.value, at_t0);
  for (const ForceElement& f : model.forces) {
    if (f.type == ForceType::spring_damper) {
      if (model.evaluate(f.stiffness, subs) < 0)
        throw ModelError(f.stiffness.loc, "force '" + f.name + "': negative stiffness");
      if (model.evaluate(f.damping, subs) < 0)
        throw ModelError(f.damping.loc, "force '" + f.name + "': negative damping");
      if (model.evaluate(f.free_length, subs) < 0)
        throw ModelError(f.free_length.loc, "force '" + f.name + "': negative free length");
    } else if (f.type == ForceType::force) {
      model.evaluate(f.force.x, at_t0);
      model.evaluate(f.force.y, at_t0);
    } else {
      model.evaluate(f.torque, at_t0);
    }
  }
  const double t0 = model.evaluate(model.step.t0, subs);
  const double t1 = model.evaluate(model.step.t1, subs);
  if (!(t1 > t0)) {
    std::ostringstream message;
    message << "step: t1 (" << t1 << ") must be greater than t0 (" << t0 << ")";
    throw ModelError(model.step.t1.loc, message.str());
  }
}

}  // namespace

void check_values(const Model& model, const std::vector<double>& parameters) {
  if (parameters.size() != model.parameters.size())
    throw ModelError({model.file, 0, 0}, std::to_string(parameters.size()) +
                                             " parameter values given, model '" + model.name +
                                             "' has " + std::to_string(model.parameters.size()));
  try {
    check_all(model, parameters);
  } catch (const ModelError& error) {
    std::string changed;
    for (size_t i = 0; i < parameters.size(); ++i)
      if (!(parameters[i] == model.parameters[i].value))
        changed += (changed.empty() ? " (with " : ", ") + model.parameters[i].name + " = " +
                   short_number(parameters[i]);
    if (changed.empty()) throw;
    const std::string what = error.what();
    const auto split = what.find(": error: ");
    throw ModelError(error.where(),
                     (split == what.npos ? what : what.substr(split + 9)) + changed + ")");
  }
}

}  // namespace mechgen
