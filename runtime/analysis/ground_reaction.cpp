#include "analysis/ground_reaction.hpp"

#include <cmath>
#include <limits>
#include <set>

namespace mechgen::analysis {

namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

}  // namespace

Reaction reaction_from_joints(const FreeBody& ground, const Eigen::Vector2d& gravity) {
  Reaction r;
  const Eigen::Vector2d weight = ground.mass * gravity;
  r.force = -weight;
  r.moment = -cross(ground.com, weight);
  for (const PointLoad& l : ground.forces) {
    r.force -= l.force;
    r.moment -= cross(l.at, l.force);
  }
  for (const Couple& c : ground.couples) r.moment -= c.moment;
  return r;
}

Reaction reaction_from_momentum(const Model& model, const std::vector<FreeBody>& bodies,
                                const Eigen::Vector2d& gravity) {
  std::set<std::string> external;
  for (const ForceElement& f : model.forces)
    if (f.type != ForceType::spring_damper) external.insert(f.name);
  Reaction r;
  for (const FreeBody& b : bodies) {
    // The ground body does not move: its acceleration is zero and only its weight counts.
    const Eigen::Vector2d rate = b.mass * (b.acc - gravity);
    r.force += rate;
    r.moment += b.inertia * b.al + cross(b.com, rate);
    for (const PointLoad& l : b.forces)
      if (external.count(l.source)) {
        r.force -= l.force;
        r.moment -= cross(l.at, l.force);
      }
    for (const Couple& c : b.couples)
      if (external.count(c.source)) r.moment -= c.moment;
  }
  return r;
}

double centre_of_pressure(const Reaction& r, const Eigen::Vector2d& heel,
                          const Eigen::Vector2d& toe) {
  const Eigen::Vector2d d = (toe - heel).normalized();
  const double across = cross(d, r.force);
  if (across == 0) return std::numeric_limits<double>::quiet_NaN();
  // The moment of R applied at heel + u d equals M: cross(heel, R) + u cross(d, R) = M.
  return (r.moment - cross(heel, r.force)) / across;
}

std::pair<std::string, std::string> sole_points(const Model& model,
                                                const std::vector<double>& parameters,
                                                const std::string& heel, const std::string& toe) {
  const Body& ground = model.bodies[static_cast<size_t>(model.ground)];
  const GiNaC::exmap subs = model.substitutions(parameters);
  const auto where = [&](const BodyPoint& p) -> Eigen::Vector2d {
    return {model.evaluate(p.local.x, subs), model.evaluate(p.local.y, subs)};
  };
  for (const std::string& name : {heel, toe})
    if (!name.empty() && !ground.find_point(name))
      throw ModelError(ground.loc, "ground body '" + ground.name + "' has no point '" + name +
                                       "' (the sole's heel and toe are points of the ground body)");
  if (!heel.empty() && !toe.empty()) return {heel, toe};
  if (ground.points.size() < 2)
    throw ModelError(ground.loc, "ground body '" + ground.name +
                                     "' needs two points to define a sole (heel and toe)");
  size_t first = 0, second = 1;
  double farthest = -1;
  for (size_t i = 0; i < ground.points.size(); ++i)
    for (size_t j = i + 1; j < ground.points.size(); ++j) {
      const double d = (where(ground.points[j]) - where(ground.points[i])).norm();
      if (d > farthest) farthest = d, first = i, second = j;
    }
  if (where(ground.points[second]).x() < where(ground.points[first]).x()) std::swap(first, second);
  std::string h = ground.points[first].name, t = ground.points[second].name;
  if (!heel.empty()) h = heel, t = (t == heel ? ground.points[first].name : t);
  if (!toe.empty()) t = toe, h = (h == toe ? ground.points[second].name : h);
  return {h, t};
}

ZmpReport zmp_over(const Model& model, const std::vector<double>& parameters,
                   const std::vector<std::string>& columns,
                   const std::vector<std::vector<double>>& rows, const std::string& heel,
                   const std::string& toe) {
  ZmpReport report;
  std::tie(report.heel, report.toe) = sole_points(model, parameters, heel, toe);
  if (report.heel == report.toe)
    throw ModelError(model.bodies[static_cast<size_t>(model.ground)].loc,
                     "the heel and the toe are the same point '" + report.heel + "'");
  const FreeBodies free_bodies(model, parameters, columns);
  int time_column = -1;
  for (size_t c = 0; c < columns.size(); ++c)
    if (columns[c] == "t") time_column = static_cast<int>(c);
  const Eigen::Vector2d g = free_bodies.gravity();
  report.min_margin = std::numeric_limits<double>::infinity();
  report.min_normal = std::numeric_limits<double>::infinity();
  for (const std::vector<double>& row : rows) {
    const std::vector<FreeBody> bodies = free_bodies.at(row);
    const Eigen::Vector2d h = free_bodies.point(report.heel, row);
    const Eigen::Vector2d to = free_bodies.point(report.toe, row);
    const Eigen::Vector2d d = (to - h).normalized();
    report.sole_length = (to - h).norm();
    ZmpSample s;
    s.t = time_column >= 0 ? row[static_cast<size_t>(time_column)] : 0;
    s.reaction = reaction_from_joints(bodies[static_cast<size_t>(model.ground)], g);
    s.momentum = reaction_from_momentum(model, bodies, g);
    s.normal = cross(d, s.reaction.force);
    s.zmp = centre_of_pressure(s.reaction, h, to);
    s.heel_margin = s.zmp;
    s.toe_margin = report.sole_length - s.zmp;
    report.largest_disagreement =
        std::max({report.largest_disagreement, (s.reaction.force - s.momentum.force).norm(),
                  std::abs(s.reaction.moment - s.momentum.moment) / report.sole_length});
    if (s.heel_margin < report.min_margin)
      report.min_margin = s.heel_margin, report.min_margin_t = s.t, report.min_margin_end = "heel";
    if (s.toe_margin < report.min_margin)
      report.min_margin = s.toe_margin, report.min_margin_t = s.t, report.min_margin_end = "toe";
    report.min_normal = std::min(report.min_normal, s.normal);
    if (s.heel_margin >= 0 && s.toe_margin >= 0) {
      if (report.inside++ == 0) report.inside_t0 = s.t;
      report.inside_t1 = s.t;
    }
    report.samples.push_back(s);
  }
  return report;
}

}  // namespace mechgen::analysis
