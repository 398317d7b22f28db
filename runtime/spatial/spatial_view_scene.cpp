#include "spatial/spatial_view_scene.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "report/view_columns.hpp"

namespace mechgen::spatial {

namespace {

using report::ViewShape;

report::Vec3 arr(const V3& v) {
  return {v[0], v[1], v[2]};
}

ViewShape cylinder(const V3& centre, const V3& axis, double half_length, double radius) {
  ViewShape s;
  s.kind = ViewShape::Kind::cylinder;
  s.role = ViewShape::Role::joint;
  s.a = arr(centre - half_length * axis);
  s.b = arr(centre + half_length * axis);
  s.radius = radius;
  return s;
}

ViewShape ball(const V3& centre, double radius, ViewShape::Role role) {
  ViewShape s;
  s.kind = ViewShape::Kind::sphere;
  s.role = role;
  s.center = arr(centre);
  s.radius = radius;
  return s;
}

report::Quat matrix_quaternion(const Eigen::Matrix3d& R) {
  const Eigen::Quaterniond q(R);
  return {q.w(), q.x(), q.y(), q.z()};
}

}  // namespace

report::ViewScene spatial_view_scene(const SpatialSolver& solver, const report::CsvTable& table) {
  const SpatialModel& model = solver.model();
  const SpatialInstance& in = solver.instance();
  const SpatialGraph& graph = solver.graph();
  report::ViewScene scene;
  scene.dimension = "spatial";
  const double g = std::sqrt(geometry::dot(in.gravity, in.gravity));
  scene.up = g > 0 ? arr((-1 / g) * in.gravity) : report::Vec3{0, 0, 1};
  scene.times = table.values(report::view_column(table, "t"));
  const GiNaC::exmap subs = model.common.substitutions(solver.parameters());

  // The size of the mechanism at its reference pose sets the joints' and lines' sizes.
  V3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  auto grow = [&](const V3& x) {
    for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], x[i]), hi[i] = std::max(hi[i], x[i]);
  };
  for (size_t j = 0; j < model.joints.size(); ++j)
    if (!model.joints[j].is_virtual) grow(in.joint_point[j]);
  for (size_t b = 0; b < model.bodies.size(); ++b)
    if (!model.bodies[b].is_virtual)
      for (const V3& p : in.points[b]) grow(geometry::apply(in.body_frame[b], p));
  const double size =
      lo[0] <= hi[0] ? std::max(std::sqrt(geometry::dot(hi - lo, hi - lo)), 1e-3) : 1;
  double bar = 0;  // the thickest bar
  for (const SpatialBody& b : model.bodies)
    if (b.mass.source == SpatialMass::Source::bar)
      bar = std::max(bar, model.evaluate(b.mass.radius, subs));
  const double rj = std::max(0.012 * size, 1.5 * bar);
  scene.size = size;

  // Body b's tracked frame: its body frame moved to its centre of mass (the ground: its frame).
  std::vector<int> index(model.bodies.size(), -1);
  auto to_local = [&](size_t b, const V3& world_ref) {
    const Pose& f = in.body_frame[b];
    const V3 x = geometry::transpose(f.R) * (world_ref - f.p);
    return model.bodies[b].ground ? x : x - in.com[b];
  };
  auto dir_local = [&](size_t b, const V3& axis) {
    return geometry::transpose(in.body_frame[b].R) * axis;
  };
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    const SpatialBody& body = model.bodies[b];
    if (body.is_virtual) continue;
    index[b] = static_cast<int>(scene.bodies.size());
    report::ViewBody vb;
    vb.name = body.name;
    vb.ground = body.ground;
    const ViewShape::Role role = body.ground ? ViewShape::Role::ground : ViewShape::Role::link;
    auto point_local = [&](const std::string& name) {
      for (size_t k = 0; k < body.points.size(); ++k)
        if (body.points[k].name == name)
          return body.ground ? in.points[b][k] : in.points[b][k] - in.com[b];
      throw std::invalid_argument("body '" + body.name + "' has no point '" + name + "'");
    };
    const SpatialMass& m = body.mass;
    if (m.source == SpatialMass::Source::bar) {
      ViewShape s;
      s.kind = ViewShape::Kind::cylinder;
      s.role = role;
      s.a = arr(point_local(m.bar_from));
      s.b = arr(point_local(m.bar_to));
      s.radius = model.evaluate(m.radius, subs);
      vb.shapes.push_back(s);
    } else if (m.source == SpatialMass::Source::box) {
      ViewShape s;
      s.kind = ViewShape::Kind::box;
      s.role = role;
      s.center = body.ground ? arr(in.com[b]) : report::Vec3{0, 0, 0};
      s.size = {model.evaluate(m.box_size.x, subs), model.evaluate(m.box_size.y, subs),
                model.evaluate(m.box_size.z, subs)};
      vb.shapes.push_back(s);
    } else if (in.mass[b] > 0) {
      // The box with the same mass and principal inertias: edges a_i = sqrt(6 (I_j + I_k - I_i)
      // / m) along the principal axes (translucent in the page: it stands for a mass, not a part).
      Eigen::Matrix3d I;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) I(i, j) = in.inertia[b](i, j);
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(I);
      const Eigen::Vector3d p = eig.eigenvalues();
      Eigen::Matrix3d axes = eig.eigenvectors();
      if (axes.determinant() < 0) axes.col(2) *= -1;
      ViewShape s;
      s.kind = ViewShape::Kind::box;
      s.role = role;
      s.center = body.ground ? arr(in.com[b]) : report::Vec3{0, 0, 0};
      for (int i = 0; i < 3; ++i) {
        const double e2 = 6 * (p[(i + 1) % 3] + p[(i + 2) % 3] - p[i]) / in.mass[b];
        s.size[static_cast<size_t>(i)] = std::sqrt(std::max(e2, 0.0));
      }
      if (s.size[0] > 0 || s.size[1] > 0 || s.size[2] > 0) {
        for (double& e : s.size) e = std::max(e, 0.2 * rj);
        s.rotation = matrix_quaternion(axes);
        s.inertia_box = true;
        vb.shapes.push_back(s);
      }
    }
    // Thin lines: from the joint carrying the body to its other joints and its points.
    std::vector<V3> ends;
    V3 from{0, 0, 0};
    bool have_from = false;
    for (size_t j = 0; j < model.joints.size(); ++j) {
      const SpatialJoint& joint = model.joints[j];
      if (joint.is_virtual) continue;
      if (joint.second == static_cast<int>(b) && !have_from)
        from = to_local(b, in.joint_point[j]), have_from = true;
      else if (joint.first == static_cast<int>(b) || joint.second == static_cast<int>(b))
        ends.push_back(to_local(b, in.joint_point[j]));
    }
    for (size_t k = 0; k < body.points.size(); ++k) {
      const V3 p = body.ground ? in.points[b][k] : in.points[b][k] - in.com[b];
      if (!have_from)
        from = p, have_from = true;
      else
        ends.push_back(p);
    }
    for (const V3& e : ends) {
      if (std::sqrt(geometry::dot(e - from, e - from)) < 1e-9) continue;
      ViewShape s;
      s.kind = ViewShape::Kind::line;
      s.role = role;
      s.outline = {arr(from), arr(e)};
      vb.shapes.push_back(s);
    }
    // Pose per frame, straight from the table; the ground stays where the model puts it.
    if (body.ground) {
      vb.position.assign(1, arr(in.body_frame[b].p));
      const std::array<double, 4> q = quaternion(in.body_frame[b].R);
      vb.orientation.assign(1, {q[0], q[1], q[2], q[3]});
    } else {
      std::vector<int> c;
      for (const char* k : {".x", ".y", ".z", ".qw", ".qx", ".qy", ".qz"})
        c.push_back(report::view_column(table, body.name + k));
      for (const std::vector<double>& row : table.rows) {
        auto v = [&](int i) { return row[static_cast<size_t>(c[static_cast<size_t>(i)])]; };
        vb.position.push_back({v(0), v(1), v(2)});
        vb.orientation.push_back({v(3), v(4), v(5), v(6)});
      }
    }
    scene.bodies.push_back(std::move(vb));
  }

  for (size_t j = 0; j < model.joints.size(); ++j) {
    const SpatialJoint& joint = model.joints[j];
    if (joint.is_virtual) continue;
    const size_t f = static_cast<size_t>(joint.first), s = static_cast<size_t>(joint.second);
    if (index[f] < 0 || index[s] < 0) continue;
    const V3 at_f = to_local(f, in.joint_point[j]), at_s = to_local(s, in.joint_point[j]);
    scene.joints.push_back({joint.name, index[s], arr(at_s)});
    std::vector<ViewShape>& first = scene.bodies[static_cast<size_t>(index[f])].shapes;
    std::vector<ViewShape>& second = scene.bodies[static_cast<size_t>(index[s])].shapes;
    const int c0 = graph.joint_column[j];
    const V3 axis = c0 >= 0 ? in.axes[static_cast<size_t>(c0)].s : V3{0, 0, 1};
    switch (joint.type) {
      case SpatialJointType::revolute:
      case SpatialJointType::helical:
        second.push_back(cylinder(at_s, dir_local(s, axis), 2 * rj, rj));
        break;
      case SpatialJointType::prismatic:
      case SpatialJointType::cylindrical: {
        // The translation's axis (a cylindrical joint's first coordinate).
        first.push_back(cylinder(at_f, dir_local(f, axis), 3 * rj, 1.4 * rj));
        second.push_back(cylinder(at_s, dir_local(s, axis), 6 * rj, 0.6 * rj));
        break;
      }
      case SpatialJointType::spherical:
        second.push_back(ball(at_s, 1.5 * rj, ViewShape::Role::joint));
        break;
      case SpatialJointType::universal: {
        const V3 axis2 = in.axes[static_cast<size_t>(c0 + 1)].s;
        second.push_back(ball(at_s, 1.1 * rj, ViewShape::Role::joint));
        first.push_back(cylinder(at_f, dir_local(f, axis), 2.2 * rj, 0.5 * rj));
        second.push_back(cylinder(at_s, dir_local(s, axis2), 2.2 * rj, 0.5 * rj));
        break;
      }
      case SpatialJointType::fixed: {
        ViewShape cube;
        cube.kind = ViewShape::Kind::box;
        cube.role = ViewShape::Role::joint;
        cube.center = arr(at_s);
        cube.size = {1.6 * rj, 1.6 * rj, 1.6 * rj};
        second.push_back(cube);
        break;
      }
    }
  }
  for (const auto& [name, body] : model.named_points()) {
    const size_t b = static_cast<size_t>(body);
    const SpatialBody& sb = model.bodies[b];
    for (size_t k = 0; k < sb.points.size(); ++k)
      if (sb.points[k].name == name)
        scene.points.push_back(
            {name, index[b], arr(sb.ground ? in.points[b][k] : in.points[b][k] - in.com[b])});
  }
  return scene;
}

}  // namespace mechgen::spatial
