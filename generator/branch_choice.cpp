#include "branch_choice.hpp"

#include <cmath>
#include <sstream>

namespace mechgen::gen {

namespace {

double wrap(double a) {
  return std::remainder(a, 2 * M_PI);
}

std::string angle_text(double a) {
  std::ostringstream out;
  out.precision(4);
  out << std::fixed << a;
  return out.str();
}

std::string angles(const Model& model, const BranchChoice& c, const std::vector<double>& th) {
  std::string text;
  for (size_t i = 0; i < c.bodies.size(); ++i)
    text += (i ? ", " : "") + model.bodies[static_cast<size_t>(c.bodies[i])].name + " " +
            angle_text(th[i]);
  return text;
}

}  // namespace

bool branch_pinned(const Model& model, const BranchChoice& choice) {
  const std::vector<double> defaults = model.default_parameters();
  GiNaC::exmap subs = model.substitutions(defaults);
  subs[model.t] = model.evaluate(model.step.t0, subs);
  for (size_t i = 0; i < choice.bodies.size(); ++i) {
    const Body& body = model.bodies[static_cast<size_t>(choice.bodies[i])];
    if (!body.assembly_angle) continue;
    const double hint = model.evaluate(*body.assembly_angle, subs);
    if (std::abs(wrap(hint - choice.taken[i])) <= model.assembly_tolerance &&
        std::abs(wrap(hint - choice.other[i])) > model.assembly_tolerance)
      return true;
  }
  return false;
}

std::vector<std::string> unpinned_branch_warnings(const Model& model,
                                                  const std::vector<BranchChoice>& choices) {
  std::vector<std::string> lines;
  for (const BranchChoice& c : choices) {
    if (branch_pinned(model, c)) continue;
    // The body whose angle differs most between the branches pins it best.
    size_t best = 0;
    for (size_t i = 1; i < c.bodies.size(); ++i)
      if (std::abs(wrap(c.taken[i] - c.other[i])) > std::abs(wrap(c.taken[best] - c.other[best])))
        best = i;
    const std::string body = model.bodies[static_cast<size_t>(c.bodies[best])].name;
    lines.push_back(c.group + ": no assembly hint tells its two branches apart; took branch " +
                    (c.sign > 0 ? "+1" : "-1") + " (" + angles(model, c, c.taken) +
                    " rad at t0), not the other (" + angles(model, c, c.other) +
                    " rad); pin it with `assembly: " + angle_text(c.taken[best]) + "` on body '" +
                    body + "' (or `assembly: " + angle_text(c.other[best]) + "` for the other)");
  }
  return lines;
}

}  // namespace mechgen::gen
