// Closing the loops of an imported tree: Newton-Raphson on the free joints' coordinates, the
// actuated joints held at the source's values, minimum-norm steps (the Jacobian of the closure
// residuals by central differences; the residual itself is exact, so Newton still reaches
// round-off).
#include <Eigen/QR>
#include <cmath>
#include <random>

#include "import/import_tree.hpp"

namespace mechgen::import {

Frame joint_motion(const TreeJoint& j, const Eigen::VectorXd& q) {
  Frame m = Frame::Identity();
  switch (j.type) {
    case JointType::revolute:
      m.linear() = Eigen::AngleAxisd(q[0], j.axis).toRotationMatrix();
      break;
    case JointType::prismatic:
      m.translation() = j.axis * q[0];
      break;
    case JointType::spherical:
      m.linear() = (Eigen::AngleAxisd(q[0], Vec3::UnitX()) *
                    Eigen::AngleAxisd(q[1], Vec3::UnitY()) * Eigen::AngleAxisd(q[2], Vec3::UnitZ()))
                       .toRotationMatrix();
      break;
    case JointType::universal:
      m.linear() = (Eigen::AngleAxisd(q[0], Vec3::UnitX()) * Eigen::AngleAxisd(q[1], Vec3::UnitY()))
                       .toRotationMatrix();
      break;
    case JointType::fixed:
      break;
  }
  return m;
}

TreePose place(const Tree& tree, const std::vector<Eigen::VectorXd>& q) {
  TreePose pose;
  pose.q = q;
  pose.link.assign(tree.links.size(), Frame::Identity());
  for (size_t i = 0; i < tree.joints.size(); ++i) {
    const TreeJoint& j = tree.joints[i];
    pose.link[static_cast<size_t>(j.child)] =
        pose.link[static_cast<size_t>(j.parent)] * j.origin * joint_motion(j, q[i]) * j.after;
  }
  return pose;
}

Eigen::VectorXd closure_residual(const Tree& tree, const TreePose& pose) {
  std::vector<double> r;
  for (const Closure& c : tree.closures) {
    const Frame a = pose.link[static_cast<size_t>(c.link_a)] * c.in_a;
    const Frame b = pose.link[static_cast<size_t>(c.link_b)] * c.in_b;
    const Vec3 d = b.translation() - a.translation();
    r.insert(r.end(), {d.x(), d.y(), d.z()});
    if (c.weld) {
      const Eigen::AngleAxisd aa(Mat3(a.linear().transpose() * b.linear()));
      const Vec3 w = a.linear() * (aa.angle() * aa.axis());
      r.insert(r.end(), {w.x(), w.y(), w.z()});
    }
  }
  return Eigen::Map<Eigen::VectorXd>(r.data(), static_cast<long>(r.size()));
}

namespace {

// Newton-Raphson with halved steps on the unknown coordinates; returns the steps taken.
int newton(const Tree& tree, std::vector<Eigen::VectorXd>& q,
           const std::vector<std::pair<size_t, int>>& unknowns, Eigen::VectorXd& r) {
  auto residual = [&](const std::vector<Eigen::VectorXd>& x) {
    return closure_residual(tree, place(tree, x));
  };
  r = residual(q);
  const long n = static_cast<long>(unknowns.size());
  int it = 0;
  for (; it < 200 && r.size() && r.cwiseAbs().maxCoeff() > 1e-15; ++it) {
    Eigen::MatrixXd J(r.size(), n);
    const double h = 1e-6;
    for (long k = 0; k < n; ++k) {
      auto [jnt, dof] = unknowns[static_cast<size_t>(k)];
      std::vector<Eigen::VectorXd> plus = q, minus = q;
      plus[jnt][dof] += h;
      minus[jnt][dof] -= h;
      J.col(k) = (residual(plus) - residual(minus)) / (2 * h);
    }
    // Gauss-Newton's minimum-norm step first; when it does not decrease the residual,
    // Levenberg-Marquardt steps of growing damping (far from assembly).
    bool improved = false;
    auto attempt = [&](const Eigen::VectorXd& step) {
      std::vector<Eigen::VectorXd> trial = q;
      for (long k = 0; k < n; ++k) {
        auto [jnt, dof] = unknowns[static_cast<size_t>(k)];
        trial[jnt][dof] += step[k];
      }
      const Eigen::VectorXd rt = residual(trial);
      if (rt.norm() < r.norm()) q = trial, r = rt, improved = true;
    };
    attempt(-J.completeOrthogonalDecomposition().solve(r));
    const Eigen::MatrixXd JtJ = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    for (double mu = 1e-6 * (1 + JtJ.diagonal().maxCoeff()); !improved && mu < 1e12; mu *= 4)
      attempt(-(JtJ + mu * Eigen::MatrixXd::Identity(n, n)).ldlt().solve(g));
    if (!improved) break;
  }
  return it;
}

}  // namespace

TreePose assemble(const Tree& tree, AssemblyReport& report) {
  std::vector<Eigen::VectorXd> q(tree.joints.size());
  std::vector<bool> held(tree.joints.size(), false);
  for (const Actuator& a : tree.actuators) held[static_cast<size_t>(a.joint)] = true;
  std::vector<std::pair<size_t, int>> unknowns;  // (joint, dof)
  for (size_t i = 0; i < tree.joints.size(); ++i) {
    const TreeJoint& j = tree.joints[i];
    q[i] = Eigen::VectorXd::Zero(j.dofs());
    if (j.dofs() == 1) q[i][0] = j.value;
    for (size_t k = 0; k < j.start.size() && static_cast<int>(k) < j.dofs(); ++k)
      q[i][static_cast<long>(k)] = j.start[k];
    if (!held[i])
      for (int k = 0; k < j.dofs(); ++k) unknowns.push_back({i, k});
  }
  Eigen::VectorXd r = closure_residual(tree, place(tree, q));
  report.initial = r.size() ? r.cwiseAbs().maxCoeff() : 0;
  // Positions first (every closure as a ball), then the welds' orientations too: from far away
  // the orientation rows (a rotation vector, discontinuous at pi) would trap Newton.
  Tree balls = tree;
  bool welds = false;
  for (Closure& c : balls.closures) welds = welds || c.weld, c.weld = false;
  const std::vector<Eigen::VectorXd> q0 = q;
  int it = 0;
  auto close = [&](std::vector<Eigen::VectorXd>& x) {
    it += welds ? newton(balls, x, unknowns, r) : 0;
    it += newton(tree, x, unknowns, r);
    return r.size() == 0 || r.cwiseAbs().maxCoeff() <= 1e-10;
  };
  // From the source's configuration; when Newton is trapped there, from deterministic
  // pseudo-random configurations, keeping the assembly nearest the source's.
  if (!close(q)) {
    std::mt19937 random(21);
    std::uniform_real_distribution<double> angle(-M_PI, M_PI);
    Eigen::VectorXd best_r = r;
    std::vector<Eigen::VectorXd> best = q;
    double best_distance = INFINITY;
    for (int start = 0; start < 64; ++start) {
      std::vector<Eigen::VectorXd> x = q0;
      for (auto [jnt, dof] : unknowns)
        if (tree.joints[jnt].type != JointType::prismatic) x[jnt][dof] = angle(random);
      if (!close(x)) {
        if (best_distance == INFINITY && r.cwiseAbs().maxCoeff() < best_r.cwiseAbs().maxCoeff())
          best = x, best_r = r;
        continue;
      }
      double distance = 0;
      for (auto [jnt, dof] : unknowns) {
        const double d = std::remainder(x[jnt][dof] - q0[jnt][dof], 2 * M_PI);
        distance += d * d;
      }
      if (distance < best_distance) best_distance = distance, best = x, best_r = r;
      if (start >= 8 && best_distance < INFINITY) break;
    }
    q = best, r = best_r;
    if (best_distance < INFINITY) report.restarts = true;
  }
  report.iterations = it;
  report.final = r.size() ? r.cwiseAbs().maxCoeff() : 0;
  auto distance_from_source = [&](const std::vector<Eigen::VectorXd>& x) {
    double d = 0;
    for (auto [jnt, dof] : unknowns) {
      const double e = tree.joints[jnt].type == JointType::prismatic
                           ? x[jnt][dof] - q0[jnt][dof]
                           : std::remainder(x[jnt][dof] - q0[jnt][dof], 2 * M_PI);
      d += e * e;
    }
    return std::sqrt(d);
  };
  if (report.final <= 1e-10 && !tree.closures.empty() && !unknowns.empty()) {
    // Other assemblies at these motor positions, so the choice can be told: the loops closed
    // from deterministic pseudo-random starts, told apart by where the moving joints and the
    // balls of 3d closures are (an idle spin, of a rod about the line through its balls, moves
    // none of them; it may move a fixed frame or a weld's frame off that line).
    auto anchors = [&](const std::vector<Eigen::VectorXd>& x) {
      const TreePose p = place(tree, x);
      std::vector<Vec3> a;
      for (const TreeJoint& j : tree.joints)
        if (j.dofs() > 0)
          a.push_back((p.link[static_cast<size_t>(j.parent)] * j.origin).translation());
      for (const Closure& c : tree.closures)
        if (!c.weld) a.push_back((p.link[static_cast<size_t>(c.link_a)] * c.in_a).translation());
      return a;
    };
    auto apart = [](const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
      for (size_t k = 0; k < a.size(); ++k)
        if ((a[k] - b[k]).norm() > 1e-6) return true;
      return false;
    };
    const Eigen::VectorXd kept_r = r;
    const int kept_it = it;
    std::vector<std::vector<Vec3>> found{anchors(q)};
    report.kept_distance = distance_from_source(q);
    report.other_distance = INFINITY;
    std::mt19937 random(2121);
    std::uniform_real_distribution<double> angle(-M_PI, M_PI);
    report.starts = 16;
    for (int start = 0; start < report.starts; ++start) {
      std::vector<Eigen::VectorXd> x = q0;
      for (auto [jnt, dof] : unknowns)
        if (tree.joints[jnt].type != JointType::prismatic) x[jnt][dof] = angle(random);
      if (!close(x)) continue;
      const std::vector<Vec3> a = anchors(x);
      bool known = false;
      for (const auto& f : found) known = known || !apart(a, f);
      if (known) continue;
      found.push_back(a);
      ++report.others;
      report.other_distance = std::min(report.other_distance, distance_from_source(x));
    }
    r = kept_r, it = kept_it;
  }
  if (report.final > 1e-10) {
    // Which closure cannot close: the loops closed one more at a time, in the file's order; the
    // first that fails is named with what it leaves open.
    size_t bad = tree.closures.size() - 1;
    Eigen::VectorXd left = r;
    for (size_t n = 1; n < tree.closures.size(); ++n) {
      Tree part = tree;
      part.closures.resize(n);
      std::vector<Eigen::VectorXd> x = q0;
      Eigen::VectorXd rp;
      newton(part, x, unknowns, rp);
      if (rp.cwiseAbs().maxCoeff() > 1e-10) {
        bad = n - 1, left = rp;
        break;
      }
    }
    const Closure& open = tree.closures[bad];
    long at = 0;
    for (size_t c = 0; c < bad; ++c) at += tree.closures[c].weld ? 6 : 3;
    std::string what = "distance left " + std::to_string(left.segment(at, 3).norm()) + " m";
    if (open.weld)
      what += ", angle left " + std::to_string(left.segment(at + 3, 3).norm()) + " rad";
    throw ImportError(open.file.empty() ? tree.source : open.file, open.line,
                      "closure " + open.a + " - " + open.b +
                          " cannot close with the actuated joints at their source values: " + what +
                          " (the loops closed from a residual of " +
                          std::to_string(report.initial) + ")");
  }
  return place(tree, q);
}

}  // namespace mechgen::import

namespace mechgen::import {

void hold_free_joints(Tree& tree, TreePose& pose) {
  // The links below each link (inclusive), by walking the joints backwards (parents first).
  const size_t n = tree.links.size();
  std::vector<std::vector<bool>> below(n, std::vector<bool>(n, false));
  for (size_t l = 0; l < n; ++l) below[l][l] = true;
  for (size_t i = tree.joints.size(); i-- > 0;) {
    const TreeJoint& j = tree.joints[i];
    for (size_t l = 0; l < n; ++l)
      if (below[static_cast<size_t>(j.child)][l]) below[static_cast<size_t>(j.parent)][l] = true;
  }
  for (size_t i = 0; i < tree.joints.size(); ++i) {
    TreeJoint& j = tree.joints[i];
    if (j.dofs() == 0) continue;
    bool actuated = false, in_loop = false;
    for (const Actuator& a : tree.actuators) actuated = actuated || a.joint == static_cast<int>(i);
    for (const Closure& c : tree.closures)
      in_loop = in_loop || below[static_cast<size_t>(j.child)][static_cast<size_t>(c.link_a)] !=
                               below[static_cast<size_t>(j.child)][static_cast<size_t>(c.link_b)];
    if (actuated || in_loop) continue;
    j.origin = j.origin * joint_motion(j, pose.q[i]) * j.after;
    j.after = Frame::Identity();
    j.type = JointType::fixed;
    pose.q[i] = Eigen::VectorXd();
    tree.notes.push_back("joint " + j.name +
                         " is neither actuated nor in a loop: held at its source value (no "
                         "driver would fix it)");
  }
}

}  // namespace mechgen::import
