#include "report/planar_view_scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "report/view_columns.hpp"

namespace mechgen::report {

namespace {

struct XY {
  double x = 0, y = 0;
};

// Layer k of the alternating sequence 0, +1, -1, +2, -2, ...
double layer(int k) {
  return k == 0 ? 0.0 : (k % 2 ? 1.0 : -1.0) * ((k + 1) / 2);
}

ViewShape box_between(XY a, XY b, double z, double width, double thickness) {
  ViewShape s;
  s.kind = ViewShape::Kind::box;
  const double length = std::hypot(b.x - a.x, b.y - a.y);
  s.center = {(a.x + b.x) / 2, (a.y + b.y) / 2, z};
  s.size = {length + width, width, thickness};  // rounded ends would reach width / 2 beyond
  s.rotation = planar_rotation(std::atan2(b.y - a.y, b.x - a.x));
  return s;
}

}  // namespace

ViewScene planar_view_scene(const Model& model, const std::vector<double>& parameters,
                            const CsvTable& table) {
  const GiNaC::exmap subs = model.substitutions(parameters);
  auto value = [&](const Expr& e) { return model.evaluate(e, subs); };
  auto local = [&](const BodyPoint& p) { return XY{value(p.local.x), value(p.local.y)}; };
  ViewScene scene;
  scene.dimension = "planar";
  const double gx = value(model.gravity.x), gy = value(model.gravity.y);
  const double g = std::hypot(gx, gy);
  scene.up = g > 0 ? Vec3{-gx / g, -gy / g, 0} : Vec3{0, 1, 0};
  scene.times = table.values(view_column(table, "t"));
  const size_t frames = table.rows.size();

  // The mechanism's size (first frame's named points) sets joint and line sizes.
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (const auto& [name, body] : model.named_points()) {
    const int x = table.column(name + ".x"), y = table.column(name + ".y");
    if (x < 0 || y < 0 || table.rows.empty()) continue;
    const double px = table.rows[0][static_cast<size_t>(x)],
                 py = table.rows[0][static_cast<size_t>(y)];
    lo[0] = std::min(lo[0], px), hi[0] = std::max(hi[0], px);
    lo[1] = std::min(lo[1], py), hi[1] = std::max(hi[1], py);
  }
  const double size = lo[0] <= hi[0] ? std::max(std::hypot(hi[0] - lo[0], hi[1] - lo[1]), 1e-3) : 1;
  double thickness = 0;  // the thickest bar or plate
  for (const Body& b : model.bodies)
    if (b.mass.source == MassProperties::Source::bar ||
        b.mass.source == MassProperties::Source::bars ||
        b.mass.source == MassProperties::Source::plate)
      thickness = std::max(thickness, value(b.mass.thickness));
  if (!(thickness > 0)) thickness = 0.01 * size;
  scene.size = size;
  const double dz = 1.6 * thickness;                           // layer spacing
  const double pin = std::max(0.012 * size, 0.6 * thickness);  // joint radius

  // Per body: its tracked centre (body frame) and layer height.
  std::vector<XY> centre(model.bodies.size());
  std::vector<double> z(model.bodies.size());
  int moving = 0;
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    const Body& body = model.bodies[b];
    z[b] = body.ground ? 0.0 : layer(moving++) * dz;
    const bool tracked = !body.ground || table.column(body.name + ".x") >= 0;
    if (!tracked) continue;  // the fixed ground: its frame is the world's
    if (body.mass.source != MassProperties::Source::none) {
      centre[b] = {value(body.mass.com.x), value(body.mass.com.y)};
    } else if (!body.points.empty()) {  // a massless ground: its points' centroid (as walk does)
      for (const BodyPoint& p : body.points) {
        centre[b].x += local(p).x / static_cast<double>(body.points.size());
        centre[b].y += local(p).y / static_cast<double>(body.points.size());
      }
    }
  }
  auto at = [&](size_t b, XY p) { return XY{p.x - centre[b].x, p.y - centre[b].y}; };
  auto point_of = [&](const Body& body, const std::string& name) {
    const BodyPoint* p = body.find_point(name);
    if (!p) throw std::invalid_argument("body '" + body.name + "' has no point '" + name + "'");
    return local(*p);
  };

  for (size_t b = 0; b < model.bodies.size(); ++b) {
    const Body& body = model.bodies[b];
    ViewBody vb;
    vb.name = body.name;
    vb.ground = body.ground;
    const MassProperties& m = body.mass;
    const ViewShape::Role role = body.ground ? ViewShape::Role::ground : ViewShape::Role::link;
    if (m.source == MassProperties::Source::bar || m.source == MassProperties::Source::bars) {
      const std::vector<std::string> ends = m.source == MassProperties::Source::bar
                                                ? std::vector<std::string>{m.bar_from, m.bar_to}
                                                : m.outline;
      for (size_t k = 0; k + 1 < ends.size(); k += 2) {
        ViewShape s =
            box_between(at(b, point_of(body, ends[k])), at(b, point_of(body, ends[k + 1])), z[b],
                        value(m.width), value(m.thickness));
        s.role = role;
        vb.shapes.push_back(s);
      }
    } else if (m.source == MassProperties::Source::plate) {
      ViewShape s;
      s.kind = ViewShape::Kind::plate;
      s.role = role;
      for (const std::string& name : m.outline) {
        const XY p = at(b, point_of(body, name));
        s.outline.push_back({p.x, p.y, z[b]});
      }
      s.thickness = value(m.thickness);
      vb.shapes.push_back(s);
    } else if (!body.points.empty()) {
      // An explicit mass or none: thin lines through its points (closed around three or more,
      // in the order of their angle about the centroid), and a ball at the centre of mass.
      std::vector<XY> ps;
      XY mid;
      for (const BodyPoint& p : body.points) {
        ps.push_back(at(b, local(p)));
        mid.x += ps.back().x / static_cast<double>(body.points.size());
        mid.y += ps.back().y / static_cast<double>(body.points.size());
      }
      std::sort(ps.begin(), ps.end(), [&](const XY& p, const XY& q) {
        return std::atan2(p.y - mid.y, p.x - mid.x) < std::atan2(q.y - mid.y, q.x - mid.x);
      });
      if (ps.size() >= 3) ps.push_back(ps.front());
      ViewShape s;
      s.kind = ViewShape::Kind::line;
      s.role = role;
      for (const XY& p : ps) s.outline.push_back({p.x, p.y, z[b]});
      if (s.outline.size() >= 2) vb.shapes.push_back(s);
      if (m.source == MassProperties::Source::explicit_values && value(m.mass) > 0) {
        ViewShape c;
        c.kind = ViewShape::Kind::sphere;
        c.role = role;
        c.center = {0, 0, z[b]};
        c.radius = pin * 1.2;
        vb.shapes.push_back(c);
      }
    }
    // The pose per frame, straight from the table.
    const int x = table.column(body.name + ".x"), y = table.column(body.name + ".y");
    const int th = table.column(body.name + ".th");
    if (x >= 0 && y >= 0 && th >= 0) {
      for (const std::vector<double>& row : table.rows) {
        vb.position.push_back({row[static_cast<size_t>(x)], row[static_cast<size_t>(y)], 0});
        vb.orientation.push_back(planar_rotation(row[static_cast<size_t>(th)]));
      }
    } else if (body.ground) {
      vb.position.assign(1, {0, 0, 0});
      vb.orientation.assign(1, {1, 0, 0, 0});
    } else {
      view_column(table, body.name + (x < 0 ? ".x" : y < 0 ? ".y" : ".th"));  // throws
    }
    scene.bodies.push_back(std::move(vb));
  }

  // Joints: on the second body (and a rail on the first for a line joint).
  for (const Joint& j : model.joints) {
    const size_t f = static_cast<size_t>(j.first), s = static_cast<size_t>(j.second);
    const XY p = at(s, point_of(model.bodies[s], j.point));
    const double z0 = std::min(z[f], z[s]) - thickness, z1 = std::max(z[f], z[s]) + thickness;
    scene.joints.push_back({j.name, static_cast<int>(s), {p.x, p.y, z[s]}});
    ViewShape glyph;
    glyph.role = ViewShape::Role::joint;
    if (j.type == JointType::revolute || j.type == JointType::pin_in_slot) {
      glyph.kind = ViewShape::Kind::cylinder;
      glyph.a = {p.x, p.y, z0};
      glyph.b = {p.x, p.y, z1};
      glyph.radius = pin;
      scene.bodies[s].shapes.push_back(glyph);
    }
    if (j.type == JointType::revolute) continue;
    // The line's direction and the joint point's travel along it (first body frame, over the
    // table's frames), for the rail's length.
    const XY through{value(j.line.through.x), value(j.line.through.y)};
    XY d{value(j.line.direction.x), value(j.line.direction.y)};
    const double dn = std::hypot(d.x, d.y);
    d = {d.x / dn, d.y / dn};
    double s_lo = INFINITY, s_hi = -INFINITY;
    const int px = table.column(j.point + ".x"), py = table.column(j.point + ".y");
    for (size_t i = 0; i < frames && px >= 0 && py >= 0; ++i) {
      const ViewBody& first = scene.bodies[f];
      const Vec3& o = first.position[std::min(i, first.position.size() - 1)];
      const Quat& q = first.orientation[std::min(i, first.orientation.size() - 1)];
      const double th = 2 * std::atan2(q[3], q[0]);
      const double wx = table.rows[i][static_cast<size_t>(px)] - o[0];
      const double wy = table.rows[i][static_cast<size_t>(py)] - o[1];
      const XY body_frame{std::cos(th) * wx + std::sin(th) * wy + centre[f].x,
                          -std::sin(th) * wx + std::cos(th) * wy + centre[f].y};
      const double along = (body_frame.x - through.x) * d.x + (body_frame.y - through.y) * d.y;
      s_lo = std::min(s_lo, along), s_hi = std::max(s_hi, along);
    }
    if (!(s_lo <= s_hi)) s_lo = -0.1 * size, s_hi = 0.1 * size;
    const double margin = 3 * pin;
    ViewShape rail =
        box_between(at(f, {through.x + d.x * (s_lo - margin), through.y + d.y * (s_lo - margin)}),
                    at(f, {through.x + d.x * (s_hi + margin), through.y + d.y * (s_hi + margin)}),
                    z0 - thickness / 2, pin, thickness / 2);
    rail.role = ViewShape::Role::joint;
    scene.bodies[f].shapes.push_back(rail);
    if (j.type == JointType::prismatic) {  // the block, along the line in the second body
      const double angle = value(j.angle);
      ViewShape block =
          box_between({p.x - 2 * pin * (d.x * std::cos(angle) + d.y * std::sin(angle)),
                       p.y - 2 * pin * (d.y * std::cos(angle) - d.x * std::sin(angle))},
                      {p.x + 2 * pin * (d.x * std::cos(angle) + d.y * std::sin(angle)),
                       p.y + 2 * pin * (d.y * std::cos(angle) - d.x * std::sin(angle))},
                      z[s], 2.5 * pin, z1 - z0);
      block.role = ViewShape::Role::joint;
      scene.bodies[s].shapes.push_back(block);
    }
  }
  for (const auto& [name, body] : model.named_points()) {
    const size_t b = static_cast<size_t>(body);
    const XY p = at(b, point_of(model.bodies[b], name));
    scene.points.push_back({name, body, {p.x, p.y, z[b]}});
  }
  return scene;
}

}  // namespace mechgen::report
