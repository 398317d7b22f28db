#include "analysis/link_loads.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace mechgen::analysis {

namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

Eigen::Vector2d local_point(const Model& model, const BodyPoint& p, const GiNaC::exmap& subs) {
  return {model.evaluate(p.local.x, subs), model.evaluate(p.local.y, subs)};
}

std::string millimetres(double metres) {
  std::ostringstream out;
  out << metres * 1e3;
  return out.str();
}

// A concentrated load on the axis: axial and transverse components, couple about its projection.
struct AxisLoad {
  double s = 0, fa = 0, ft = 0, c = 0;
};

// Sums over the part of the bar left of the cut s of the concentrated loads (those at s_i < s,
// or s_i <= s when `inclusive`) and of the line loads c0 + c1 (u - L/2) on [0, L].
struct LineLoad {
  double c0 = 0, c1 = 0;
};

void cut(const std::vector<AxisLoad>& loads, const LineLoad& axial, const LineLoad& transverse,
         double length, double s, bool inclusive, double& n, double& v, double& m) {
  double fa = 0, ft = 0, moment = 0;
  for (const AxisLoad& l : loads) {
    if (l.s > s || (!inclusive && l.s == s)) continue;
    fa += l.fa;
    ft += l.ft;
    moment += (s - l.s) * l.ft - l.c;
  }
  // Line loads on [0, min(max(s, 0), L)]: integral of q and of (s - u) q.
  const double e = std::clamp(s, 0.0, length), half = length / 2;
  const double int1 = e, int_lin = e * e / 2 - half * e;
  const double arm1 = s * e - e * e / 2;
  const double arm_lin = s * int_lin - (e * e * e / 3 - half * e * e / 2);
  fa += axial.c0 * int1 + axial.c1 * int_lin;
  ft += transverse.c0 * int1 + transverse.c1 * int_lin;
  moment += transverse.c0 * arm1 + transverse.c1 * arm_lin;
  n = -fa;
  v = ft;
  m = moment;
}

}  // namespace

std::optional<BarAxis> bar_axis(const Model& model, int body, const GiNaC::exmap& subs) {
  const Body& b = model.bodies[static_cast<size_t>(body)];
  if (b.mass.source == MassProperties::Source::bar) {
    const BodyPoint *from = b.find_point(b.mass.bar_from), *to = b.find_point(b.mass.bar_to);
    if ((local_point(model, *to, subs) - local_point(model, *from, subs)).norm() == 0)
      return std::nullopt;
    return BarAxis{body, b.mass.bar_from, b.mass.bar_to, true};
  }
  double farthest = 0;
  std::optional<BarAxis> axis;
  for (size_t i = 0; i < b.points.size(); ++i)
    for (size_t j = i + 1; j < b.points.size(); ++j) {
      const double d =
          (local_point(model, b.points[j], subs) - local_point(model, b.points[i], subs)).norm();
      if (d > farthest) {
        farthest = d;
        axis = BarAxis{body, b.points[i].name, b.points[j].name, false};
      }
    }
  return axis;
}

std::optional<SectionProperties> section_properties(const Model& model, int body,
                                                    const GiNaC::exmap& subs,
                                                    std::optional<double> yield_override) {
  const Body& b = model.bodies[static_cast<size_t>(body)];
  SectionProperties p;
  p.yield = yield_override         ? *yield_override
            : model.yield_strength ? model.evaluate(*model.yield_strength, subs)
                                   : std::numeric_limits<double>::quiet_NaN();
  p.modulus = model.youngs_modulus ? model.evaluate(*model.youngs_modulus, subs)
                                   : std::numeric_limits<double>::quiet_NaN();
  const auto rectangle = [&](double width, double thickness, const std::string& origin) {
    p.area = width * thickness;
    p.inertia = thickness * width * width * width / 12;
    p.buckling_inertia = std::min(p.inertia, width * thickness * thickness * thickness / 12);
    p.fibre = width / 2;
    p.shear_peak = 1.5;
    p.text = "rectangle " + millimetres(width) + " x " + millimetres(thickness) + " mm" + origin;
  };
  if (b.section) {
    const Section& s = *b.section;
    if (s.shape == Section::Shape::rectangle) {
      rectangle(model.evaluate(s.width, subs), model.evaluate(s.thickness, subs), "");
    } else {
      p.area = model.evaluate(s.area, subs);
      p.inertia = model.evaluate(s.inertia, subs);
      p.fibre = model.evaluate(s.fibre, subs);
      p.buckling_inertia = p.inertia;
      p.shear_peak = 1;
      std::ostringstream text;
      text << "A " << p.area * 1e6 << " mm^2, I " << p.inertia * 1e12 << " mm^4, c "
           << p.fibre * 1e3 << " mm";
      p.text = text.str();
    }
    if (s.yield_strength) p.yield = model.evaluate(*s.yield_strength, subs);
    if (s.youngs_modulus) p.modulus = model.evaluate(*s.youngs_modulus, subs);
    return p;
  }
  if (b.mass.source == MassProperties::Source::bar) {
    rectangle(model.evaluate(b.mass.width, subs), model.evaluate(b.mass.thickness, subs),
              " (bar mass)");
    return p;
  }
  return std::nullopt;
}

BeamLoads beam_loads(const FreeBody& body, const BarAxis& axis, const Eigen::Vector2d& a,
                     const Eigen::Vector2d& b, const Eigen::Vector2d& gravity, int intervals) {
  BeamLoads out;
  out.length = (b - a).norm();
  const double length = out.length;
  const Eigen::Vector2d e = (b - a) / length, n{-e.y(), e.x()};
  std::vector<AxisLoad> loads;
  const auto add_force = [&](const Eigen::Vector2d& at, const Eigen::Vector2d& force) {
    const Eigen::Vector2d r = at - a;
    const double s = r.dot(e), offset = r.dot(n);
    // The couple of the force about its projection on the axis: offset n x F.
    loads.push_back({s, force.dot(e), force.dot(n), offset * cross(n, force)});
  };
  for (const PointLoad& l : body.forces) add_force(l.at, l.force);
  for (const Couple& c : body.couples) {
    // A couple without a point of application acts at the centre of mass's projection.
    loads.push_back({((c.at ? *c.at : body.com) - a).dot(e), 0, 0, c.moment});
  }
  LineLoad axial, transverse;
  const Eigen::Vector2d weight_and_inertia = body.mass * (gravity - body.acc);
  if (axis.distributed) {
    axial.c0 = weight_and_inertia.dot(e) / length;
    transverse.c0 = weight_and_inertia.dot(n) / length;
    axial.c1 = body.mass * body.w * body.w / length;
    transverse.c1 = -12 * body.inertia * body.al / (length * length * length);
  } else {
    add_force(body.com, weight_and_inertia);
    loads.push_back({(body.com - a).dot(e), 0, 0, -body.inertia * body.al});
  }

  out.s_min = 0;
  out.s_max = length;
  for (const AxisLoad& l : loads) {
    out.s_min = std::min(out.s_min, l.s);
    out.s_max = std::max(out.s_max, l.s);
  }
  std::vector<double> where;
  for (int i = 0; i <= intervals; ++i)
    where.push_back(out.s_min + (out.s_max - out.s_min) * i / intervals);
  for (const AxisLoad& l : loads) where.push_back(l.s);
  std::sort(where.begin(), where.end());
  where.erase(std::unique(where.begin(), where.end()), where.end());
  for (const double s : where) {
    BeamStation st;
    st.s = s;
    double m_before = 0;
    cut(loads, axial, transverse, length, s, true, st.n, st.v, st.m);
    cut(loads, axial, transverse, length, s, false, st.n_before, st.v_before, m_before);
    out.stations.push_back(st);
  }
  cut(loads, axial, transverse, length, out.s_max, true, out.end_n, out.end_v, out.end_m);
  return out;
}

BeamLoads link_diagram(const Model& model, const std::vector<double>& parameters,
                       const std::vector<std::string>& columns, const std::vector<double>& row,
                       const std::string& link, int intervals) {
  const int body = model.body_index(link);
  if (body < 0 || model.bodies[static_cast<size_t>(body)].ground)
    throw std::invalid_argument("'" + link + "' is not a moving body of model '" + model.name +
                                "'");
  const std::optional<BarAxis> axis = bar_axis(model, body, model.substitutions(parameters));
  if (!axis) throw std::invalid_argument("'" + link + "' has no two distinct points: no bar axis");
  const FreeBodies free_bodies(model, parameters, columns);
  return beam_loads(free_bodies.at(row)[static_cast<size_t>(body)], *axis,
                    free_bodies.point(axis->from, row), free_bodies.point(axis->to, row),
                    free_bodies.gravity(), intervals);
}

LinkLoadReport link_loads(const Model& model, const std::vector<double>& parameters,
                          const std::vector<std::string>& columns,
                          const std::vector<std::vector<double>>& rows,
                          const LinkLoadOptions& options) {
  LinkLoadReport report;
  const FreeBodies free_bodies(model, parameters, columns);
  const GiNaC::exmap subs = model.substitutions(parameters);
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    const Body& body = model.bodies[b];
    if (body.ground) continue;
    const std::optional<BarAxis> axis = bar_axis(model, static_cast<int>(b), subs);
    if (!axis) {
      report.skipped.push_back(body.name + ": no two distinct points, no bar axis");
      continue;
    }
    const std::optional<SectionProperties> section =
        section_properties(model, static_cast<int>(b), subs, options.yield_override);
    if (!section) {
      report.skipped.push_back(body.name + ": no section (give `section:` or a bar mass)");
      continue;
    }
    LinkResult link;
    link.body = static_cast<int>(b);
    link.name = body.name;
    link.axis = *axis;
    link.section = *section;
    report.links.push_back(link);
  }

  int time_column = -1;
  for (size_t c = 0; c < columns.size(); ++c)
    if (columns[c] == "t") time_column = static_cast<int>(c);
  const auto keep = [](Peak& peak, double value, double t, double s) {
    if (std::abs(value) > std::abs(peak.value)) peak = {value, t, s};
  };
  for (const std::vector<double>& row : rows) {
    const double t = time_column >= 0 ? row[static_cast<size_t>(time_column)] : 0;
    report.t.push_back(t);
    const std::vector<FreeBody> bodies = free_bodies.at(row);
    for (LinkResult& link : report.links) {
      const BeamLoads beam = beam_loads(
          bodies[static_cast<size_t>(link.body)], link.axis, free_bodies.point(link.axis.from, row),
          free_bodies.point(link.axis.to, row), free_bodies.gravity(), options.intervals);
      link.length = beam.length;
      report.largest_end_residual =
          std::max({report.largest_end_residual, std::abs(beam.end_n), std::abs(beam.end_v),
                    std::abs(beam.end_m) / beam.length});
      const SectionProperties& sec = link.section;
      double n_max = 0, v_max = 0, m_max = 0, sigma_max = 0;
      for (const BeamStation& st : beam.stations) {
        for (const double n : {st.n, st.n_before}) {
          keep(link.n, n, t, st.s);
          if (n < link.compression.value) link.compression = {n, t, st.s};
        }
        for (const double v : {st.v, st.v_before}) keep(link.v, v, t, st.s);
        keep(link.m, st.m, t, st.s);
        const double n_abs = std::max(std::abs(st.n), std::abs(st.n_before));
        const double v_abs = std::max(std::abs(st.v), std::abs(st.v_before));
        const double sigma = n_abs / sec.area + std::abs(st.m) * sec.fibre / sec.inertia;
        const double tau = sec.shear_peak * v_abs / sec.area;
        keep(link.sigma, sigma, t, st.s);
        keep(link.tau, tau, t, st.s);
        n_max = std::max(n_max, n_abs);
        v_max = std::max(v_max, v_abs);
        m_max = std::max(m_max, std::abs(st.m));
        sigma_max = std::max(sigma_max, sigma);
      }
      link.n_t.push_back(n_max);
      link.v_t.push_back(v_max);
      link.m_t.push_back(m_max);
      link.sigma_t.push_back(sigma_max);
    }
  }
  for (size_t i = 0; i < report.links.size(); ++i) {
    LinkResult& link = report.links[i];
    const double equivalent = std::max(link.sigma.value, std::sqrt(3.0) * link.tau.value);
    link.safety = link.section.yield / equivalent;
    link.buckling_load = std::numbers::pi * std::numbers::pi * link.section.modulus *
                         link.section.buckling_inertia / (link.length * link.length);
    // A compression at round-off level (a bar in tension whose far end balances to 1e-14 N)
    // is none.
    const bool compressed = -link.compression.value > 1e-9 * std::abs(link.n.value);
    if (!compressed) link.compression = {};
    link.buckling_safety = std::isnan(link.buckling_load) ? link.buckling_load
                           : compressed ? link.buckling_load / -link.compression.value
                                        : std::numeric_limits<double>::infinity();
    const auto worse = [&](const LinkResult& a, const LinkResult& b) {
      if (!std::isnan(a.safety) && !std::isnan(b.safety)) return a.safety < b.safety;
      return a.sigma.value > b.sigma.value;
    };
    if (report.critical < 0 || worse(link, report.links[static_cast<size_t>(report.critical)]))
      report.critical = static_cast<int>(i);
  }
  return report;
}

}  // namespace mechgen::analysis
