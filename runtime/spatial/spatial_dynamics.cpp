// Spatial Newton-Euler: assembly of A x = b and its minimum-norm solution (spatial_dynamics.hpp).
#include "spatial/spatial_dynamics.hpp"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <Eigen/SparseQR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <utility>

namespace mechgen::spatial {

namespace {

using geometry::cross;

Eigen::Matrix3d skew(const V3& p) {
  Eigen::Matrix3d S;
  S << 0, -p[2], p[1], p[2], 0, -p[0], -p[1], p[0], 0;
  return S;
}
Eigen::Vector3d e3(const V3& v) {
  return {v[0], v[1], v[2]};
}
V3 v3(const Eigen::Vector3d& v) {
  return {v[0], v[1], v[2]};
}
Eigen::Matrix3d m3(const M3& m) {
  Eigen::Matrix3d out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out(i, j) = m(i, j);
  return out;
}

// A is sparse: a joint's six unknowns touch its two bodies' rows and its own columns' rows, a
// driver's effort its two bodies'. Dense, it would be (6 bodies + columns) x (6 joints + drivers):
// 390 MB and an O(n^3) solve for 1 000 bodies (issue 26 item 1).
using Sparse = Eigen::SparseMatrix<double>;
struct System {
  Sparse A;
  Eigen::VectorXd b;
  std::vector<V3> point;
};

// Above this many unknowns the system is solved sparse (a supernodal LU with a fill-reducing
// column order when A is square, as for trees and chains of loops: near-linear in the bodies; a
// QR otherwise); below, dense as always.
constexpr Eigen::Index kSparseAbove = 200;

// The sparse LU and the ratio of its smallest to largest pivot (|U_jj|: they lie in L's
// supernodes), a cheap stand-in for the dense LU's reciprocal condition number.
class PivotedLU : public Eigen::SparseLU<Sparse, Eigen::COLAMDOrdering<int>> {
 public:
  explicit PivotedLU(const Sparse& A) : Eigen::SparseLU<Sparse, Eigen::COLAMDOrdering<int>>(A) {}
  double pivot_ratio() {
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    for (Eigen::Index j = 0; j < cols(); ++j)
      for (SCMatrix::InnerIterator it(m_Lstore, j); it; ++it)
        if (it.index() == j) {
          lo = std::min(lo, std::abs(it.value())), hi = std::max(hi, std::abs(it.value()));
          break;
        }
    return hi > 0 ? lo / hi : 0;
  }
};

// x with A x = b when A has full column rank (square: the LU's pivots no smaller than 1e-12 of
// the largest, as the dense path's rcond; else the sparse QR's rank), else nothing.
std::optional<Eigen::VectorXd> full_rank_sparse_solve(const Sparse& A, const Eigen::VectorXd& b) {
  Eigen::VectorXd x;
  if (A.rows() == A.cols()) {
    PivotedLU lu(A);
    if (lu.info() != Eigen::Success || !(lu.pivot_ratio() > 1e-12)) return std::nullopt;
    x = lu.solve(b);
  } else {
    Eigen::SparseQR<Sparse, Eigen::COLAMDOrdering<int>> qr(A);
    if (qr.info() != Eigen::Success || qr.rank() < A.cols()) return std::nullopt;
    x = qr.solve(b);
  }
  if (!x.allFinite()) return std::nullopt;
  return x;
}

template <int R, int C>
void add_block(std::vector<Eigen::Triplet<double>>& t, int row, int col,
               const Eigen::Matrix<double, R, C>& m) {
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < C; ++j)
      if (m(i, j) != 0) t.emplace_back(row + i, col + j, m(i, j));
}

// Rows: 6 per non-ground body (force, moment about the ground origin), then one per column.
// Unknowns: 6 per joint (force, moment about the joint point), then one per primary column.
System assemble(const SpatialSolver& solver, const SpatialState& s) {
  const SpatialModel& model = solver.model();
  const SpatialGraph& g = solver.graph();
  const SpatialInstance& in = solver.instance();
  const int nb = static_cast<int>(model.bodies.size()), nj = static_cast<int>(model.joints.size());
  const int np = static_cast<int>(g.primary.size());
  std::vector<int> body_row(static_cast<size_t>(nb), -1);
  int rows = 0;
  for (int b = 0; b < nb; ++b)
    if (b != model.ground) body_row[static_cast<size_t>(b)] = rows, rows += 6;
  const int column_row = rows;
  rows += g.cols();
  System sys{Sparse(rows, 6 * nj + np), Eigen::VectorXd::Zero(rows), {}};
  std::vector<Eigen::Triplet<double>> entries;  // summed where they repeat

  for (int j = 0; j < nj; ++j) {
    const SpatialJoint& joint = model.joints[static_cast<size_t>(j)];
    const V3 P = geometry::apply(s.D[static_cast<size_t>(joint.second)],
                                 in.joint_point[static_cast<size_t>(j)]);
    sys.point.push_back(P);
    // Wrench about the origin from the unknowns (f, m_P): T = [[I, 0], [[P], I]].
    Eigen::Matrix<double, 6, 6> T = Eigen::Matrix<double, 6, 6>::Identity();
    T.block<3, 3>(3, 0) = skew(P);
    for (const auto& [body, sign] : {std::pair{joint.second, 1.0}, std::pair{joint.first, -1.0}})
      if (body != model.ground)
        add_block<6, 6>(entries, body_row[static_cast<size_t>(body)], 6 * j, sign * T);
    for (size_t k = 0; k < joint.columns.size(); ++k) {
      const int c = g.joint_column[static_cast<size_t>(j)] + static_cast<int>(k);
      const Twist& sc = s.screw[static_cast<size_t>(c)];
      Eigen::Matrix<double, 1, 6> power;  // reciprocal product with (f, m_o)
      power << sc.v[0], sc.v[1], sc.v[2], sc.w[0], sc.w[1], sc.w[2];
      add_block<1, 6>(entries, column_row + c, 6 * j, power * T);
    }
  }
  // A driven coordinate's effort: a couple about its axis (rotation, helical) or a force along
  // it through the joint point (translation), on the second body, its opposite on the first.
  for (int k = 0; k < np; ++k) {
    const int c = g.primary[static_cast<size_t>(k)];
    const SpatialColumn& col = g.columns[static_cast<size_t>(c)];
    const SpatialJoint& joint = model.joints[static_cast<size_t>(col.joint)];
    const Twist& sc = s.screw[static_cast<size_t>(c)];
    Eigen::Matrix<double, 6, 1> w = Eigen::Matrix<double, 6, 1>::Zero();
    if (in.axes[static_cast<size_t>(c)].kind == geometry::ScrewKind::translation) {
      const V3 P = sys.point[static_cast<size_t>(col.joint)];
      w << e3(sc.v), e3(cross(P, sc.v));
    } else {
      w.tail<3>() = e3(sc.w);
    }
    for (const auto& [body, sign] : {std::pair{joint.second, 1.0}, std::pair{joint.first, -1.0}})
      if (body != model.ground)
        add_block<6, 1>(entries, body_row[static_cast<size_t>(body)], 6 * nj + k, sign * w);
  }
  sys.A.setFromTriplets(entries.begin(), entries.end());
  sys.A.makeCompressed();
  // Right-hand side: rate of momentum minus gravity and applied loads, about the ground origin.
  const std::vector<Wrench> applied = solver.applied_wrenches(s);
  for (int b = 0; b < nb; ++b) {
    if (b == model.ground) continue;
    const double m = in.mass[static_cast<size_t>(b)];
    const V3 com = in.com[static_cast<size_t>(b)];
    const Pose frame = solver.body_pose(s, b);
    const Eigen::Vector3d c = e3(geometry::apply(frame, com));
    const Eigen::Matrix3d R = m3(frame.R);
    const Eigen::Matrix3d I = R * m3(in.inertia[static_cast<size_t>(b)]) * R.transpose();
    const Eigen::Vector3d w = e3(s.V[static_cast<size_t>(b)].w);
    const Eigen::Vector3d al = e3(s.A[static_cast<size_t>(b)].w);
    const Eigen::Vector3d a = e3(solver.point_acceleration(s, b, com));
    const Eigen::Vector3d F = m * (a - e3(in.gravity));
    const Eigen::Vector3d M = I * al + w.cross(I * w) + c.cross(F);
    sys.b.segment<3>(body_row[static_cast<size_t>(b)]) = F - e3(applied[static_cast<size_t>(b)].f);
    sys.b.segment<3>(body_row[static_cast<size_t>(b)] + 3) =
        M - e3(applied[static_cast<size_t>(b)].m);
  }
  return sys;
}

}  // namespace

NewtonEulerSystem newton_euler_system(const SpatialSolver& solver, const SpatialState& s) {
  System sys = assemble(solver, s);
  return {Eigen::MatrixXd(sys.A), std::move(sys.b)};
}

SpatialLoads inverse_dynamics(const SpatialSolver& solver, const SpatialState& s) {
  const System sys = assemble(solver, s);
  // Without redundancy A is square and regular: an LU solve. Otherwise (or when LU finds A
  // nearly singular) the minimum-norm least-squares solution of a complete orthogonal
  // decomposition, whose rank gives the redundancy.
  // Large: the sparse QR when A has full column rank (no redundancy); a redundant large model
  // still takes the dense decomposition (cubic: named in README.md "Growth with size").
  Eigen::VectorXd x;
  int redundancy = 0;
  bool solved = false;
  if (sys.A.cols() > kSparseAbove) {
    if (auto sparse = full_rank_sparse_solve(sys.A, sys.b)) x = std::move(*sparse), solved = true;
  } else if (sys.A.rows() == sys.A.cols()) {
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu{Eigen::MatrixXd(sys.A)};
    if (lu.rcond() > 1e-12) x = lu.solve(sys.b), solved = true;
  }
  if (!solved) {
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod{Eigen::MatrixXd(sys.A)};
    cod.setThreshold(1e-10);
    x = cod.solve(sys.b);
    redundancy = static_cast<int>(sys.A.cols() - cod.rank());
  }
  const double residual = (sys.A * x - sys.b).norm();
  if (!(residual <= 1e-8 * (1 + sys.b.norm()))) {
    std::ostringstream m;
    m << "Newton-Euler has no solution at t = " << s.t << " (residual " << residual
      << "): the joints cannot transmit the loads; check the joint types";
    throw ModelError({solver.model().common.file, 0, 0}, m.str());
  }
  SpatialLoads out;
  const int nj = static_cast<int>(solver.model().joints.size());
  for (int j = 0; j < nj; ++j)
    out.reaction.push_back({v3(x.segment<3>(6 * j)), v3(x.segment<3>(6 * j + 3))});
  out.effort = x.tail(static_cast<Eigen::Index>(solver.graph().primary.size()));
  out.point = sys.point;
  out.redundancy = redundancy;
  return out;
}

Redundancy redundancy(const SpatialSolver& solver, const SpatialState& s) {
  const System sys = assemble(solver, s);
  const int nj = static_cast<int>(solver.model().joints.size());
  Redundancy r;
  // Large and of full column rank (the sparse solve): no redundancy, every reaction unique, without
  // the dense SVD (cubic).
  if (sys.A.cols() > kSparseAbove) {
    if (full_rank_sparse_solve(sys.A, sys.b)) {
      r.joint_unique.assign(static_cast<size_t>(nj), true);
      r.component_unique.assign(static_cast<size_t>(nj),
                                std::array<bool, 6>{true, true, true, true, true, true});
      r.efforts_unique = true;
      return r;
    }
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd{Eigen::MatrixXd(sys.A), Eigen::ComputeFullV};
  svd.setThreshold(1e-10);
  const auto rank = svd.rank();
  const Eigen::MatrixXd null = svd.matrixV().rightCols(sys.A.cols() - rank);
  r.degree = static_cast<int>(null.cols());
  for (int j = 0; j < nj; ++j) {
    r.joint_unique.push_back(null.middleRows(6 * j, 6).norm() < 1e-8);
    std::array<bool, 6> unique;
    for (int k = 0; k < 6; ++k) unique[static_cast<size_t>(k)] = null.row(6 * j + k).norm() < 1e-8;
    r.component_unique.push_back(unique);
  }
  r.efforts_unique = null.bottomRows(null.rows() - 6 * nj).norm() < 1e-8;
  return r;
}

Energy energy(const SpatialSolver& solver, const SpatialState& s) {
  const SpatialModel& model = solver.model();
  const SpatialInstance& in = solver.instance();
  Energy e;
  const Eigen::Vector3d g = e3(in.gravity);
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    if (static_cast<int>(b) == model.ground) continue;
    const int bi = static_cast<int>(b);
    const double m = in.mass[b];
    const Pose frame = solver.body_pose(s, bi);
    const Eigen::Matrix3d R = m3(frame.R);
    const Eigen::Matrix3d I = R * m3(in.inertia[b]) * R.transpose();
    const Eigen::Vector3d c = e3(geometry::apply(frame, in.com[b]));
    const Eigen::Vector3d v = e3(solver.point_velocity(s, bi, in.com[b]));
    const Eigen::Vector3d a = e3(solver.point_acceleration(s, bi, in.com[b]));
    const Eigen::Vector3d w = e3(s.V[b].w), al = e3(s.A[b].w);
    e.kinetic += 0.5 * m * v.dot(v) + 0.5 * w.dot(I * w);
    e.kinetic_rate += m * v.dot(a) + w.dot(I * al);
    e.potential -= m * g.dot(c);
    e.potential_rate -= m * g.dot(v);
  }
  return e;
}

}  // namespace mechgen::spatial
