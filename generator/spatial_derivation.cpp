// Symbolic derivation of a spatial tree's kernel (spatial_derivation.hpp).
#include "spatial_derivation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <utility>

#include "branch_sign.hpp"
#include "geometry/screw.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"
#include "spatial_circuit_solvers.hpp"
#include "spatial_primary_inputs.hpp"

namespace mechgen::gen {

using GiNaC::ex;
using GiNaC::symbol;
// Vec3 is a std::array: the geometry layer's operators are not found by argument-dependent lookup.
using geometry::operator+;
using geometry::operator-;
using geometry::operator*;

namespace {

using V = geometry::Vec3<ex>;
using M = geometry::Mat3<ex>;
using Pose = geometry::Pose<ex>;
// Substitution maps keyed by symbols alone: a lookup per node instead of GiNaC's pattern match
// against every key (which made evaluating thousands of definitions at the assembly quadratic).
constexpr unsigned kSymbolKeys =
    GiNaC::subs_options::no_pattern | GiNaC::subs_options::pattern_is_not_product;
using Twist = geometry::Twist<ex>;
using Wrench = geometry::Wrench<ex>;

const char* const kAxis[3] = {"x", "y", "z"};

// A number, a name, or a number times a name: not worth a definition of its own.
bool trivial(const ex& e) {
  if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<symbol>(e)) return true;
  return GiNaC::is_a<GiNaC::mul>(e) && e.nops() == 2 &&
         ((GiNaC::is_a<GiNaC::numeric>(e.op(0)) && GiNaC::is_a<symbol>(e.op(1))) ||
          (GiNaC::is_a<symbol>(e.op(0)) && GiNaC::is_a<GiNaC::numeric>(e.op(1))));
}

struct Column {
  geometry::ScrewAxis<ex> axis;
  ex q, qd, qdd;      // the driver's input symbols
  Pose displacement;  // the screw displacement by q, cosine and sine named
  Twist unit;         // unit screw at the reference pose, its moment named
  Twist screw, rate;  // current unit screw and its time derivative
  std::string name;   // joint, or joint_2 for a multi-coordinate joint's second coordinate
};

class Builder {
 public:
  Builder(const SpatialModel& model, const SpatialGraph& graph)
      : m_(model),
        g_(graph),
        params_(spatial_parameter_symbols(model)),
        inputs_(spatial_primary_inputs(model, graph)),
        input_of_column_(static_cast<size_t>(graph.cols()), -1) {
    for (size_t k = 0; k < inputs_.size(); ++k)
      input_of_column_[static_cast<size_t>(inputs_[k].graph_column)] = static_cast<int>(k);
  }

  SpatialDerivation run() {
    check_supported();
    const size_t start = out_.definitions.size();
    columns();
    positions();
    if (closed()) {
      close_positions(start);
      secondary_rates(false);
    }
    twists();
    if (closed()) secondary_rates(true);
    twist_rates();
    body_outputs();
    jacobians();
    if (closed())
      closed_efforts();
    else
      dynamics();
    ne_system();
    out_.primary_count = static_cast<int>(g_.primary.size());
    out_.closed_chain = closed();
    return std::move(out_);
  }

 private:
  ex param(const ex& e) const { return e.subs(params_); }
  V vec(const Vec3Expr& v) const { return {param(v.x.ex), param(v.y.ex), param(v.z.ex)}; }

  ex named(const std::string& name, const ex& e) {
    const ex x = e.expand();
    if (trivial(x)) return x;
    const symbol s(name);
    sink_->emplace_back(s, x);
    return s;
  }
  V named(const std::string& name, const V& v) {
    return {named(name + "_x", v[0]), named(name + "_y", v[1]), named(name + "_z", v[2])};
  }
  M named(const std::string& name, const M& R) {
    M out;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        out(i, j) = named(name + "_" + std::to_string(i) + std::to_string(j), R(i, j));
    return out;
  }
  Twist named(const std::string& w, const std::string& v, const Twist& t) {
    return {named(w, t.w), named(v, t.v)};
  }
  void output(std::vector<SpatialOutput>& list, const std::string& target, const ex& value) {
    list.push_back({target, value});
  }
  void output(std::vector<SpatialOutput>& list, const std::string& owner,
              const std::vector<std::string>& fields, const V& v) {
    for (int i = 0; i < 3; ++i) list.push_back({owner + fields[static_cast<size_t>(i)], v[i]});
  }
  const std::string& body_name(int b) const { return m_.bodies[static_cast<size_t>(b)].name; }

  void check_supported() const {
    const std::string file = m_.common.file + ": error: ";
    for (const SpatialColumn& c : g_.columns)
      if (!c.primary && !closed())
        throw std::runtime_error(file + "joint '" + m_.joints[static_cast<size_t>(c.joint)].name +
                                 "' has an undriven coordinate: a tree needs every one driven");
  }

  void columns() {
    for (size_t c = 0; c < g_.columns.size(); ++c) {
      const SpatialColumn& sc = g_.columns[c];
      const SpatialJoint& j = m_.joints[static_cast<size_t>(sc.joint)];
      Column col;
      col.name = j.columns.size() == 1 ? j.name : j.name + "_" + std::to_string(sc.index + 1);
      const ScrewColumnExpr& e = j.columns[static_cast<size_t>(sc.index)];
      col.axis.kind = e.kind == ScrewColumnKind::rotation      ? geometry::ScrewKind::rotation
                      : e.kind == ScrewColumnKind::translation ? geometry::ScrewKind::translation
                                                               : geometry::ScrewKind::helical;
      // Parameter expressions (a joint point at -l1 - l2) are named, so that they multiply as
      // one number instead of expanding into every product.
      col.axis.s = named("s_" + col.name, vec(e.s));
      col.axis.s0 = named("s0_" + col.name, vec(j.s0));
      col.axis.pitch = named("pitch_" + col.name, param(j.pitch.ex));
      if (const SpatialPrimaryInput* in = input(c)) {
        // A pose coordinate's input is absolute; its virtual joint's coordinate is measured from
        // the reference pose (the numeric solver's q = value - reference).
        col.q = named("q_" + col.name, symbol("in." + in->name) - param(in->reference));
        col.qd = symbol("in." + in->name + "_d");
        col.qdd = symbol("in." + in->name + "_dd");
      } else {
        // A secondary coordinate: defined by the closure (close_positions, secondary_rates).
        col.q = symbol("q_" + col.name);
      }
      // The shared layer's displacement, with the coordinate's cosine and sine named once.
      const Pose E = geometry::screw_displacement(col.axis, col.q);
      GiNaC::exmap trig;
      if (col.axis.kind != geometry::ScrewKind::translation) {
        trig[GiNaC::cos(col.q)] = named_always("cos_" + col.name, GiNaC::cos(col.q));
        trig[GiNaC::sin(col.q)] = named_always("sin_" + col.name, GiNaC::sin(col.q));
      }
      for (size_t k = 0; k < 9; ++k) col.displacement.R.m[k] = E.R.m[k].subs(trig).expand();
      for (size_t k = 0; k < 3; ++k) col.displacement.p[k] = E.p[k].subs(trig).expand();
      const Twist unit = geometry::unit_twist(col.axis);
      col.unit = {unit.w, named("sm_" + col.name, unit.v)};
      // A driven coordinate's displacement is named entry by entry: products of unnamed
      // entries down a chain expand into every body's pose (a Bioloid hip's position: 86
      // operations a coordinate about a run-time axis, against 6 as a named product). A
      // closure's own coordinates stay explicit, for the loop solvers that read them.
      if (input(c) != nullptr && col.axis.kind != geometry::ScrewKind::translation) {
        col.displacement.R = named("E_" + col.name, col.displacement.R);
        if (col.axis.kind == geometry::ScrewKind::rotation) {
          // s0 - R s0 about a unit axis s: (1 - cos q) (s0 - s (s.s0)) + sin q (s0 x s), the
          // two vectors the parameters' alone (12 operations a coordinate, against 38).
          const V& s = col.axis.s;
          const V foot = named("sf_" + col.name, col.axis.s0 - geometry::dot(s, col.axis.s0) * s);
          const ex versine = named("vers_" + col.name, 1 - trig[GiNaC::cos(col.q)]);
          col.displacement.p = versine * foot + trig[GiNaC::sin(col.q)] * col.unit.v;
        }
        col.displacement.p = named("e_" + col.name, col.displacement.p);
      }
      cols_.push_back(col);
    }
  }
  const SpatialPrimaryInput* input(size_t column) const {
    const int k = input_of_column_[column];
    return k < 0 ? nullptr : &inputs_[static_cast<size_t>(k)];
  }
  ex named_always(const std::string& name, const ex& e) {
    const symbol s(name);
    sink_->emplace_back(s, e);
    return s;
  }

  // The motion of joint j: the product of its coordinates' displacements, named factor by factor
  // (a spherical's three displacements expanded at once: 74 operations an entry of its
  // translation).
  Pose joint_motion(int j) {
    const SpatialJoint& joint = m_.joints[static_cast<size_t>(j)];
    const auto c0 = static_cast<size_t>(g_.joint_column[static_cast<size_t>(j)]);
    Pose E;  // a weld's: none
    if (!joint.columns.empty()) E = cols_[c0].displacement;
    for (size_t k = 1; k < joint.columns.size(); ++k) {
      E = E * cols_[c0 + k].displacement;
      const std::string f = "E_" + joint.name + "_" + std::to_string(k + 1);
      E = {named(f + "_R", E.R), named(f + "_p", E.p)};
    }
    return E;
  }

  void positions() {
    const size_t nb = m_.bodies.size();
    D_.assign(nb, Pose{});
    frame_.assign(nb, Pose{});
    for (const int b : g_.order) {
      const auto bi = static_cast<size_t>(b);
      const SpatialBody& body = m_.bodies[bi];
      if (b != m_.ground) {
        const int p = g_.parent[bi], j = g_.parent_joint[bi];
        const SpatialJoint& joint = m_.joints[static_cast<size_t>(j)];
        Pose E = joint_motion(j);
        // The joint's motion is named before it multiplies the parent's pose, so that the
        // product stays 9 + 9 multiplications (an inverted hinge's translation, -E^T e,
        // expanded into the product, was 27 operations an entry; a cylinder rod's, behind a
        // spherical joint, 249).
        if (joint.first != p) E = geometry::inverse(E);
        E = {named("E_" + joint.name + "_R", E.R), named("E_" + joint.name + "_p", E.p)};
        const Pose D = D_[static_cast<size_t>(p)] * E;
        D_[bi] = {named("R_" + body.name, D.R), named("p_" + body.name, D.p)};
        out_.groups.push_back(body.name);
        out_.plan.push_back(body.name + ": " + to_string(joint.type) + " '" + joint.name +
                            "' from '" + body_name(p) + "' (product of exponentials)");
      }
      // The frame's reference pose is the parameters' alone: named, so that it is computed once
      // (and hoisted out of point_positions' samples).
      const Pose reference{
          named("Rref_" + body.name,
                geometry::rodrigues(vec(body.rotation_axis), param(body.rotation_angle.ex))),
          named("oref_" + body.name, vec(body.origin))};
      const Pose F = D_[bi] * reference;
      frame_[bi] = {named("Rf_" + body.name, F.R), named("of_" + body.name, F.p)};
    }
    // Current screws: each joint's first coordinate carried by its first body, the next ones
    // also by the coordinates before them.
    for (size_t j = 0; j < m_.joints.size(); ++j) {
      Pose G = D_[static_cast<size_t>(m_.joints[j].first)];
      const auto c0 = static_cast<size_t>(g_.joint_column[j]);
      for (size_t k = 0; k < m_.joints[j].columns.size(); ++k) {
        Column& col = cols_[c0 + k];
        // The adjoint R v + p x (R w) with the reference moment v and the current axis R w
        // named: expanded, each moment entry was 20 operations against 9.
        const V w = named("sw_" + col.name, G.R * col.unit.w);
        col.screw = {w, named("sv_" + col.name, G.R * col.unit.v + geometry::cross(G.p, w))};
        // Named before the next coordinate's screw: a universal's or spherical's products
        // expanded at once swell (a Delta's wrists: 20 kB per screw entry).
        if (k + 1 < m_.joints[j].columns.size()) {
          G = G * col.displacement;
          G = {named("G_" + col.name + "_R", G.R), named("G_" + col.name + "_p", G.p)};
        }
      }
    }
  }

  bool closed() const { return g_.circuits() > 0; }

  // Straight-line Gaussian elimination of a square system whose k-th row is the k-th pivot row
  // (the pivot order fixed at generation time): every step a named definition, structural zeros
  // skipped.
  struct Lu {
    std::vector<std::vector<ex>> a;  // upper triangle after elimination
    std::vector<std::vector<ex>> f;  // multipliers below the diagonal
    std::vector<ex> inv;             // reciprocal pivots
    std::vector<ex> pivots;          // a[k][k] before its reciprocal
    std::string prefix;
  };
  Lu factor(std::vector<std::vector<ex>> a, const std::string& prefix) {
    const size_t n = a.size();
    Lu lu;
    lu.prefix = prefix;
    lu.f.assign(n, std::vector<ex>(n, 0));
    for (size_t k = 0; k < n; ++k) {
      const std::string sk = std::to_string(k);
      lu.pivots.push_back(a[k][k]);
      lu.inv.push_back(named_always(prefix + "ipiv" + sk, 1 / a[k][k]));
      for (size_t i = k + 1; i < n; ++i) {
        if (a[i][k].is_zero()) continue;
        const std::string si = std::to_string(i);
        lu.f[i][k] = named(prefix + "f" + si + "_" + sk, a[i][k] * lu.inv[k]);
        for (size_t j = k + 1; j < n; ++j)
          if (!a[k][j].is_zero())
            a[i][j] = named(prefix + "a" + sk + "_" + si + "_" + std::to_string(j),
                            a[i][j] - lu.f[i][k] * a[k][j]);
      }
    }
    lu.a = std::move(a);
    return lu;
  }
  std::vector<ex> solve(const Lu& lu, std::vector<ex> b, const std::string& prefix) {
    const size_t n = b.size();
    for (size_t k = 0; k < n; ++k)
      for (size_t i = k + 1; i < n; ++i)
        if (!lu.f[i][k].is_zero())
          b[i] = named(prefix + "b" + std::to_string(k) + "_" + std::to_string(i),
                       b[i] - lu.f[i][k] * b[k]);
    std::vector<ex> x(n);
    for (size_t k = n; k-- > 0;) {
      ex sum = b[k];
      for (size_t j = k + 1; j < n; ++j) sum -= lu.a[k][j] * x[j];
      x[k] = named(prefix + "x" + std::to_string(k), sum * lu.inv[k]);
    }
    return x;
  }

  // The closure error of each circuit (6 rows: the chord's pose error D_F E D_S^-1 as a small
  // twist) and Davies' network N (rows x columns), from the current (named) screws.
  void circuit_rows() {
    for (size_t ci = 0; ci < g_.chords.size(); ++ci) {
      const int j = g_.chords[ci];
      const SpatialJoint& joint = m_.joints[static_cast<size_t>(j)];
      const std::string n = "X" + std::to_string(ci);
      // Named factor by factor: the product of the first body's pose, each of the chord's screw
      // displacements and the second body's inverse, expanded at once, swells (a Delta's chords,
      // universal joints between two moved bodies: 0.8 MB of code for 60 entries).
      Pose X = D_[static_cast<size_t>(joint.first)];
      const auto c0 = static_cast<size_t>(g_.joint_column[static_cast<size_t>(j)]);
      for (size_t k = 0; k < joint.columns.size(); ++k) {
        X = X * cols_[c0 + k].displacement;
        const std::string f = n + "_f" + std::to_string(k);
        X = {named(f + "_R", X.R), named(f + "_p", X.p)};
      }
      X = X * geometry::inverse(D_[static_cast<size_t>(joint.second)]);
      const M R = named(n + "_R", X.R);
      residual_.push_back(named(n + "_wx", (R(2, 1) - R(1, 2)) / 2));
      residual_.push_back(named(n + "_wy", (R(0, 2) - R(2, 0)) / 2));
      residual_.push_back(named(n + "_wz", (R(1, 0) - R(0, 1)) / 2));
      for (int k = 0; k < 3; ++k)
        residual_.push_back(named(n + "_v" + kAxis[k], X.p[static_cast<size_t>(k)]));
      std::vector<int> coef(g_.columns.size(), 0);
      for (size_t c = 0; c < g_.columns.size(); ++c)
        coef[c] = g_.path_sign[static_cast<size_t>(joint.first)][c] -
                  g_.path_sign[static_cast<size_t>(joint.second)][c] +
                  (g_.columns[c].joint == j ? 1 : 0);
      for (int r = 0; r < 6; ++r) {
        std::vector<ex> row;
        for (size_t c = 0; c < g_.columns.size(); ++c)
          row.push_back(coef[c] * (r < 3 ? cols_[c].screw.w[static_cast<size_t>(r)]
                                         : cols_[c].screw.v[static_cast<size_t>(r - 3)]));
        network_.push_back(row);
      }
      circuit_coef_.push_back(coef);
    }
  }

  // N_s at sample configurations (default parameters, the numeric solver's poses), from which
  // every pivot order is fixed at generation time: kPivotSamples instants of the model's step
  // (the first is the assembly), then poses over the drivers' declared ranges (a driver's
  // `range:`, else its joint's), each driver moved alone from the assembly to both ends of its
  // range by continuation, so that the rows kept and the pivots hold wherever a `--set` or a
  // driven call takes the drivers (issue 27: an over-constrained loop's redundant rows change
  // along the motion). Range poses where N_s is near singular (a true singularity, where no
  // order holds) or that do not assemble are left out.
  static constexpr int kPivotSamples = 72;
  static constexpr int kRangeSamples = 48;  // over all ranged drivers, both directions
  void sample_secondary_matrix(size_t start) {
    const std::vector<double> defaults = m_.common.default_parameters();
    const spatial::SpatialSolver solver(m_, defaults);
    const spatial::SpatialSweepOptions sweep = spatial::default_spatial_sweep(m_, defaults);
    const size_t rows = network_.size(), ns = g_.secondary.size();
    const GiNaC::exmap parameters = numeric_parameters(defaults);
    // `previous`: the sample before this one on the same continuous path, or -1.
    const auto add_sample = [&](const spatial::SpatialState& st, int previous) {
      previous_.push_back(previous);
      GiNaC::exmap num = parameters;
      for (size_t c = 0; c < cols_.size(); ++c)
        num[cols_[c].q] = GiNaC::numeric(st.q[static_cast<Eigen::Index>(c)]);
      // A primary coordinate's own definition (a pose coordinate's input minus its reference)
      // is not needed: its value is the solver's.
      for (size_t k = start; k < out_.definitions.size(); ++k)
        if (!num.count(out_.definitions[k].first))
          num[out_.definitions[k].first] =
              out_.definitions[k].second.subs(num, kSymbolKeys).evalf();
      std::vector<std::vector<double>> m(rows, std::vector<double>(ns));
      for (size_t r = 0; r < rows; ++r)
        for (size_t i = 0; i < ns; ++i)
          m[r][i] =
              GiNaC::ex_to<GiNaC::numeric>(
                  network_[r][static_cast<size_t>(g_.secondary[i])].subs(num, kSymbolKeys).evalf())
                  .to_double();
      samples_.push_back(m);
    };
    spatial::SpatialState st;
    for (int sample = 0; sample < kPivotSamples; ++sample) {
      solver.solve(sweep.t0 + (sweep.t1 - sweep.t0) * sample / kPivotSamples, st);
      if (sample == 0) assembly_ = st;
      add_sample(st, sample - 1);
    }
    // The drivers' ranges, in the solver's primary order.
    std::vector<std::pair<size_t, std::array<double, 2>>> ranged;
    const GiNaC::exmap subs = m_.common.substitutions(defaults);
    for (const SpatialDriver& d : m_.drivers) {
      const SpatialJoint& joint = m_.joints[static_cast<size_t>(d.joint)];
      std::optional<std::array<Expr, 2>> range = d.range;
      if (!range && joint.columns.size() == 1) range = joint.range;
      const int column = g_.joint_column[static_cast<size_t>(d.joint)] + d.column;
      const auto primary = std::find(g_.primary.begin(), g_.primary.end(), column);
      if (!range || primary == g_.primary.end()) continue;
      ranged.push_back({static_cast<size_t>(primary - g_.primary.begin()),
                        {m_.evaluate((*range)[0], subs), m_.evaluate((*range)[1], subs)}});
    }
    if (ranged.empty() || ns == 0) return;
    const int steps = std::max(1, kRangeSamples / static_cast<int>(2 * ranged.size()));
    Eigen::VectorXd qp0, qpd, qpdd;
    solver.primary_motion(sweep.t0, qp0, qpd, qpdd);
    qpd.setZero();
    qpdd.setZero();
    for (const auto& [k, ends] : ranged)
      for (const double end : ends) {
        spatial::SpatialState walk = assembly_;
        Eigen::VectorXd qp = qp0;
        const auto at = static_cast<Eigen::Index>(k);
        int previous = 0;  // the assembly
        for (int step = 1; step <= steps; ++step) {
          qp[at] = qp0[at] + (end - qp0[at]) * step / steps;
          try {
            solver.solve(sweep.t0, qp, qpd, qpdd, walk);
          } catch (const std::exception&) {
            break;  // the range leaves where the mechanism assembles: no pose beyond
          }
          Eigen::MatrixXd n_s(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(ns));
          const Eigen::MatrixXd n = solver.network(walk);
          for (size_t i = 0; i < ns; ++i)
            n_s.col(static_cast<Eigen::Index>(i)) = n.col(g_.secondary[i]);
          const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(n_s).singularValues();
          if (sv.size() > 0 && sv[sv.size() - 1] > 1e-3 * sv[0]) {
            add_sample(walk, previous);
            previous = static_cast<int>(samples_.size()) - 1;
          } else {
            previous = -1;  // a crossing through a true singularity says nothing of an order
          }
        }
      }
  }
  GiNaC::exmap numeric_parameters(const std::vector<double>& values) const {
    GiNaC::exmap num;
    for (size_t i = 0; i < m_.common.parameters.size(); ++i)
      num[params_.at(m_.common.parameters[i].symbol)] = GiNaC::numeric(values[i]);
    return num;
  }

  // Complete pivoting fixed over the samples, on the block of N_s made of `rows` and the
  // secondary coordinates `columns` (indices into g_.secondary): each step the (row, column)
  // whose entry is largest against the remaining block's largest in its worst sample, so that no
  // pivot passes through zero on the step (a pivot through zero at a regular pose would make the
  // elimination meaningless there). Rows never chosen are redundant (an overconstrained circuit).
  struct PivotOrder {
    std::vector<size_t> rows, columns;  // unknown k of the elimination is columns[k]
    std::vector<double> pivots;         // each pivot's value at the assembly
    std::vector<size_t> blocks;         // each pivot's independent block of N_s
    double worst = 1;                   // the smallest pivot ratio over the samples
    bool crosses = false;  // a pivot changes sign along a path: no fixed order holds there
    // Every nonzero row of the block kept (rows), eliminated as N_s^T N_s (see least_squares).
    bool least_squares = false;
  };
  // The independent blocks of N_s: secondary coordinates joined by a closure row that holds both
  // (nonzero in some sample; an exact zero in every sample is a structural zero). Circuits that
  // share no coordinate are separate blocks, and elimination never mixes blocks, so the pivots of
  // a block multiply to its determinant whatever the order.
  std::vector<size_t> secondary_blocks() const {
    std::vector<size_t> parent(g_.secondary.size());
    for (size_t i = 0; i < parent.size(); ++i) parent[i] = i;
    const auto root = [&](size_t i) {
      while (parent[i] != i) i = parent[i] = parent[parent[i]];
      return i;
    };
    for (size_t r = 0; r < network_.size(); ++r) {
      size_t first = parent.size();
      for (size_t i = 0; i < parent.size(); ++i) {
        bool nonzero = false;
        for (const auto& m : samples_) nonzero = nonzero || m[r][i] != 0;
        if (!nonzero) continue;
        if (first == parent.size())
          first = i;
        else
          parent[root(i)] = root(first);
      }
    }
    std::vector<size_t> block(parent.size()), number(parent.size(), parent.size());
    size_t blocks = 0;
    for (size_t i = 0; i < parent.size(); ++i) {
      size_t& n = number[root(i)];
      if (n == parent.size()) n = blocks++;
      block[i] = n;
    }
    return block;
  }
  static constexpr double kSteadyPivot = 1e-3;  // of its block's largest, in every sample
  // A pivot candidate over the samples of the reduced N_s: its smallest ratio to the block's
  // largest entry, and whether its sign changes between two neighbours on a path (it passes
  // through zero between them, however large it is at every sample: Bennett's wx, wy, wz rows at
  // the crank angle pi, between two range samples).
  struct Candidate {
    double ratio = 1;
    bool crosses = false;
  };
  Candidate candidate(const std::vector<std::vector<std::vector<double>>>& a,
                      const std::vector<double>& largest, size_t r, size_t i) const {
    Candidate c;
    for (size_t sample = 0; sample < a.size(); ++sample) {
      c.ratio = std::min(c.ratio,
                         largest[sample] > 0 ? std::abs(a[sample][r][i]) / largest[sample] : 0.0);
      const int before = previous_[sample];
      c.crosses =
          c.crosses || (before >= 0 && a[sample][r][i] * a[static_cast<size_t>(before)][r][i] < 0);
    }
    return c;
  }
  // Threshold pivoting (Markowitz): among the steady candidates whose smallest ratio is within
  // this factor of the steadiest one, the one whose elimination fills the fewest entries, so the
  // generated elimination stays short (a Delta's 30 x 30 N_s: half its motion code was fill).
  static constexpr double kMarkowitzThreshold = 0.9;
  // Only in blocks of more coordinates than this: fill grows as the block's size cubed, and below
  // it the steadiest order is kept (its zero crossings are the singular refusals the branch
  // property tests rely on: quadruped_leg with theta8 = 0, where the cylinder's spin aliases).
  static constexpr size_t kMarkowitzAbove = 24;
  // Picks, among steady candidates at least kMarkowitzThreshold x `steady`, the smallest
  // Markowitz cost (row count - 1) x (column count - 1) of entries nonzero in some sample of the
  // reduced matrix; ties keep the higher ratio, then the first.
  void markowitz(const std::vector<std::vector<std::vector<double>>>& a,
                 const std::vector<double>& largest, const std::vector<size_t>& rows,
                 const std::vector<size_t>& columns, const std::vector<bool>& used,
                 const std::vector<bool>& done, double steady, size_t& best, size_t& column,
                 double& value) const {
    auto nonzero = [&](size_t r, size_t i) {
      for (size_t sample = 0; sample < a.size(); ++sample)
        if (std::abs(a[sample][r][i]) > 1e-12 * largest[sample]) return true;
      return false;
    };
    std::map<size_t, size_t> row_count, column_count;
    for (const size_t r : rows)
      for (const size_t i : columns)
        if (!used[r] && !done[i] && nonzero(r, i)) ++row_count[r], ++column_count[i];
    size_t cost = (row_count[best] - 1) * (column_count[column] - 1);
    for (const size_t r : rows)
      for (const size_t i : columns) {
        if (used[r] || done[i] || !nonzero(r, i)) continue;
        const Candidate k = candidate(a, largest, r, i);
        if (k.crosses || k.ratio < kMarkowitzThreshold * steady) continue;
        const size_t c = (row_count[r] - 1) * (column_count[i] - 1);
        if (c < cost || (c == cost && k.ratio > value * (1 + 1e-9)))
          best = r, column = i, value = k.ratio, cost = c;
      }
  }
  PivotOrder pivot_order(const std::vector<size_t>& rows,
                         const std::vector<size_t>& columns) const {
    std::vector<std::vector<std::vector<double>>> a = samples_;
    std::vector<bool> used(network_.size(), true), done(g_.secondary.size(), true);
    for (const size_t r : rows) used[r] = false;
    for (const size_t i : columns) done[i] = false;
    PivotOrder order;
    const std::vector<size_t> block = secondary_blocks();
    std::map<size_t, size_t> block_size;
    for (const size_t i : columns) ++block_size[block[i]];
    for (size_t k = 0; k < columns.size(); ++k) {
      size_t best = network_.size(), column = g_.secondary.size();
      double value = 0;
      std::vector<double> largest;
      for (const auto& m : a) {
        double l = 0;
        for (const size_t r : rows)
          for (const size_t i : columns)
            if (!used[r] && !done[i]) l = std::max(l, std::abs(m[r][i]));
        largest.push_back(l);
      }
      // A candidate that crosses zero (Candidate) is avoided while one that does not keeps a
      // steady ratio, else the best ratio as before.
      size_t steady_row = network_.size(), steady_column = g_.secondary.size();
      double steady = 0;
      bool best_crosses = false;
      for (const size_t r : rows)
        for (const size_t i : columns) {
          if (used[r] || done[i]) continue;
          const Candidate k = candidate(a, largest, r, i);
          // Ties up to round-off keep the first candidate: the samples' last bits follow GiNaC's
          // term order, which changes from run to run (regeneration must be byte-identical).
          if (k.ratio > value * (1 + 1e-9))
            best = r, column = i, value = k.ratio, best_crosses = k.crosses;
          if (!k.crosses && k.ratio > steady * (1 + 1e-9))
            steady_row = r, steady_column = i, steady = k.ratio;
        }
      if (steady >= kSteadyPivot) {
        best = steady_row, column = steady_column, value = steady;
        if (block_size[block[column]] > kMarkowitzAbove)
          markowitz(a, largest, rows, columns, used, done, steady, best, column, value);
      } else {
        order.crosses = order.crosses || best_crosses;
      }
      if (best == network_.size() || value <= 1e-6)
        throw std::runtime_error(m_.common.file +
                                 ": error: no pivot order fixed at generation time stays "
                                 "regular over the step (smallest pivot " +
                                 std::to_string(value) + " of its block)");
      used[best] = true;
      done[column] = true;
      order.worst = std::min(order.worst, value);
      order.pivots.push_back(a[0][best][column]);
      order.blocks.push_back(block[column]);
      order.rows.push_back(best);
      order.columns.push_back(column);
      for (auto& m : a)
        for (const size_t r : rows)
          if (!used[r]) {
            const double f = m[r][column] / m[best][column];
            for (const size_t i : columns) m[r][i] -= f * m[best][i];
          }
    }
    return order;
  }
  // Where rows are left over that are not structural zeros (an over-constrained block: Bennett's
  // loop, a planar loop in a plane no axis is normal to), the order keeps every nonzero row and
  // its solves take the normal equations N_s^T N_s x = N_s^T b. Which rows a fixed choice may
  // keep changes along the motion and with the parameters (issue 27: Bennett's three kept rows
  // pass through a singular minor at a regular pose, and for some Bennett linkages no three rows
  // hold over a turn), while N_s keeps its full column rank. N_s^T N_s is symmetric positive
  // definite wherever N_s has full column rank, so a fixed order never meets a zero pivot, and
  // the closure's systems are consistent: the solution is exact. A planar loop whose plane an
  // axis is normal to keeps its three in-plane rows (the others are exact zeros) and its LU.
  PivotOrder least_squares(PivotOrder order, const std::vector<size_t>& rows) const {
    std::vector<size_t> nonzero;
    for (const size_t r : rows) {
      bool any = false;
      for (const auto& m : samples_)
        for (const size_t i : order.columns) any = any || m[r][i] != 0;
      if (any) nonzero.push_back(r);
    }
    if (nonzero.size() <= order.rows.size()) return order;
    order.least_squares = true;
    order.crosses = false;
    order.rows = nonzero;
    order.pivots.clear();
    order.worst = 1;
    // Its pivots at each sample: at the assembly for the singular check; their smallest ratio
    // to their column's diagonal entry for the plan.
    const size_t n = order.columns.size();
    for (size_t sample = 0; sample < samples_.size(); ++sample) {
      std::vector<std::vector<double>> g(n, std::vector<double>(n, 0));
      for (size_t a = 0; a < n; ++a)
        for (size_t b = 0; b < n; ++b)
          for (const size_t r : nonzero)
            g[a][b] +=
                samples_[sample][r][order.columns[a]] * samples_[sample][r][order.columns[b]];
      std::vector<double> diagonal(n);
      for (size_t k = 0; k < n; ++k) diagonal[k] = g[k][k];
      for (size_t k = 0; k < n; ++k) {
        if (sample == 0) order.pivots.push_back(g[k][k]);
        order.worst = std::min(order.worst, diagonal[k] > 0 ? g[k][k] / diagonal[k] : 0.0);
        for (size_t i = k + 1; i < n; ++i) {
          const double f = g[k][k] != 0 ? g[i][k] / g[k][k] : 0.0;
          for (size_t j = k; j < n; ++j) g[i][j] -= f * g[k][j];
        }
      }
    }
    return order;
  }
  // The pivot order of the whole N_s (Davies' rates) and the plan's closure line.
  void choose_pivots(const std::vector<size_t>& newton_rows, size_t newton_columns,
                     bool newton_crosses) {
    std::vector<size_t> rows(network_.size()), columns(g_.secondary.size());
    for (size_t r = 0; r < rows.size(); ++r) rows[r] = r;
    for (size_t i = 0; i < columns.size(); ++i) columns[i] = i;
    const PivotOrder order = least_squares(pivot_order(rows, columns), rows);
    pivot_ = order;
    out_.closure_pivots = order.pivots;
    out_.closure_blocks = order.blocks;
    out_.closure_least_squares = order.least_squares;
    out_.groups.push_back("closure");
    std::string dropped;
    std::vector<bool> used(rows.size(), false);
    for (const size_t r : order.rows) used[r] = true;
    for (size_t r = 0; r < rows.size() && !order.least_squares; ++r)
      if (!used[r])
        dropped += (dropped.empty() ? "" : ", ") + std::string(r % 6 < 3 ? "w" : "v") +
                   kAxis[r % 3] + " of circuit " + std::to_string(r / 6);
    char ratio[32];
    std::snprintf(ratio, sizeof ratio, "%.2g", order.worst);
    out_.plan.push_back(
        "closure: " + std::to_string(g_.secondary.size()) + " secondary coordinates, " +
        std::to_string(rows.size()) + " closure rows; " +
        (newton_columns == 0
             ? std::string("every circuit in closed form, no Newton")
             : "Newton fallback on " + std::to_string(newton_columns) + " coordinates, " +
                   std::to_string(newton_rows.size()) + " rows") +
        "; Davies' pivot order from " + std::to_string(kPivotSamples) + " samples" +
        (samples_.size() > static_cast<size_t>(kPivotSamples)
             ? " and " + std::to_string(samples_.size() - static_cast<size_t>(kPivotSamples)) +
                   " over driver ranges"
             : std::string()) +
        " (smallest pivot " + ratio + " of its column)" +
        (dropped.empty() ? "" : "; redundant rows dropped: " + dropped) +
        (order.least_squares
             ? "; redundant rows: all " + std::to_string(order.rows.size()) +
                   " nonzero rows kept, solved as N_s^T N_s (least squares, exact on the closure: "
                   "no fixed choice of rows holds at every pose and parameter set)"
             : std::string()) +
        (order.crosses || newton_crosses
             ? "; warning: no fixed pivot order stays away from zero over the step and the "
               "drivers' ranges (a pivot changes sign between two samples): near where it passes "
               "zero the kernel refuses (singular or unreachable in group closure, its residual "
               "checks) rather than lose precision; --solver numeric pivots at run time"
             : ""));
  }

  // Definitions in an order where each follows those it reads: passes over the list in order,
  // each emitting what is ready (deterministic).
  void emit_in_dependency_order(std::vector<std::pair<symbol, ex>> items) {
    std::set<ex, GiNaC::ex_is_less> pending;
    for (const auto& item : items) pending.insert(item.first);
    while (!items.empty()) {
      std::vector<std::pair<symbol, ex>> rest;
      for (auto& item : items) {
        bool ready = true;
        for (auto it = item.second.preorder_begin(); it != item.second.preorder_end() && ready;
             ++it)
          ready = !(GiNaC::is_a<symbol>(*it) && pending.count(*it) > 0);
        if (!ready) {
          rest.push_back(std::move(item));
          continue;
        }
        pending.erase(item.first);
        out_.definitions.push_back(std::move(item));
      }
      if (rest.size() == items.size())
        throw std::logic_error("closed-form positions: definitions read each other");
      items = std::move(rest);
    }
  }

  // Unknown k of the elimination is secondary coordinate order.columns[k].
  std::vector<ex> unpermute(const PivotOrder& order, const std::vector<ex>& x) const {
    std::vector<ex> y(g_.secondary.size());
    for (size_t k = 0; k < x.size(); ++k) y[order.columns[k]] = x[k];
    return y;
  }
  std::vector<std::vector<ex>> secondary_matrix(const PivotOrder& order,
                                                const GiNaC::exmap& subs) const {
    std::vector<std::vector<ex>> a;
    for (const size_t r : order.rows) {
      std::vector<ex> row;
      for (const size_t i : order.columns)
        row.push_back(network_[r][static_cast<size_t>(g_.secondary[i])].subs(subs));
      a.push_back(row);
    }
    return a;
  }
  // The matrix `order` eliminates: N_s on its pivot rows, or N_s^T N_s over its rows (least
  // squares), in the elimination's column order.
  std::vector<std::vector<ex>> closure_matrix(const PivotOrder& order, const GiNaC::exmap& subs,
                                              const std::string& prefix) {
    const std::vector<std::vector<ex>> a = secondary_matrix(order, subs);
    if (!order.least_squares) return a;
    const size_t n = order.columns.size();
    std::vector<std::vector<ex>> g(n, std::vector<ex>(n));
    for (size_t i = 0; i < n; ++i)
      for (size_t j = i; j < n; ++j) {
        ex sum = 0;
        for (const std::vector<ex>& row : a) sum += row[i] * row[j];
        g[i][j] = g[j][i] = named(prefix + "g" + std::to_string(i) + "_" + std::to_string(j), sum);
      }
    return g;
  }
  // The right-hand side `order` eliminates, from b on its rows: b itself, or N_s^T b.
  std::vector<ex> closure_rhs(const PivotOrder& order, const std::vector<ex>& b,
                              const GiNaC::exmap& subs, const std::string& prefix) {
    if (!order.least_squares) return b;
    std::vector<ex> rows;
    for (size_t r = 0; r < b.size(); ++r)
      rows.push_back(named(prefix + "rb" + std::to_string(r), b[r]));
    std::vector<ex> out;
    for (size_t k = 0; k < order.columns.size(); ++k) {
      ex sum = 0;
      for (size_t r = 0; r < order.rows.size(); ++r)
        sum += network_[order.rows[r]][static_cast<size_t>(g_.secondary[order.columns[k]])].subs(
                   subs) *
               rows[r];
      out.push_back(named(prefix + "nb" + std::to_string(k), sum));
    }
    return out;
  }

  // The closed-form solvers (spatial_circuit_solvers.hpp) tried on each circuit, first match wins:
  // each defines some secondary coordinates from the primary inputs and the coordinates known
  // so far; the unclosed circuits are offered again after each pass that closed one (dependency
  // order). Returns per secondary coordinate its value (empty: left to Newton) and per circuit
  // whether it is closed; the closed forms' cosines and sines in trig_.
  std::vector<std::optional<ex>> solve_in_closed_form(size_t start,
                                                      std::vector<bool>& circuit_closed) {
    std::vector<std::optional<ex>> value(g_.secondary.size());
    circuit_closed.assign(g_.chords.size(), false);
    CircuitSolverContext context{m_, g_, {}, {}, {}, {}, {}, D_, {}};
    for (const SpatialColumn& c : g_.columns) context.known.push_back(c.primary);
    for (const Column& c : cols_) context.columns.push_back({c.axis, c.q, c.displacement});
    for (size_t c = 0; c < cols_.size(); ++c)
      context.assembly_q.push_back(assembly_.q[static_cast<Eigen::Index>(c)]);
    context.named = [this](const std::string& name, const ex& e) { return named(name, e); };
    GiNaC::exmap num = numeric_parameters(m_.common.default_parameters());
    for (size_t c = 0; c < cols_.size(); ++c) num[cols_[c].q] = context.assembly_q[c];
    num[follow_symbol()] = 1;  // the closed forms' roots at the assembly: the warm start's side
    size_t evaluated = start;
    // The warm start of a closed form's coordinate is the last accepted call's value carried to
    // this call's time along its rate and acceleration (zero at the first call): second order as
    // the numeric solver's prediction before Newton-Raphson, so that where two roots meet (a
    // parallelogram folding flat) the root nearer the prediction is the one the motion goes on.
    context.warm_start = [this, &num](int column) {
      const size_t k = out_.angle_start.size();
      const std::string index = "[" + std::to_string(k) + "]";
      const symbol w("s.closure.w" + index), wd("s.closure.wd" + index),
          wdd("s.closure.wdd" + index);
      out_.angle_start.push_back(assembly_.q[static_cast<Eigen::Index>(column)]);
      out_.angle_columns.push_back(column);
      num[w] = out_.angle_start.back();
      num[wd] = num[wdd] = 0;
      output(out_.kinematics, "s.closure.wnext" + index, cols_[static_cast<size_t>(column)].q);
      const ex dt = symbol("in.t") - symbol("s.closure.wt");
      return w + (wd + wdd / 2 * dt) * dt;
    };
    context.at_assembly = [this, &num, evaluated](const ex& e) mutable {
      for (; evaluated < out_.definitions.size(); ++evaluated)
        if (!num.count(out_.definitions[evaluated].first))
          num[out_.definitions[evaluated].first] =
              out_.definitions[evaluated].second.subs(num, kSymbolKeys).evalf();
      return GiNaC::ex_to<GiNaC::numeric>(e.subs(num, kSymbolKeys).evalf()).to_double();
    };
    std::vector<int> secondary_index(g_.columns.size(), -1);
    for (size_t i = 0; i < g_.secondary.size(); ++i)
      secondary_index[static_cast<size_t>(g_.secondary[i])] = static_cast<int>(i);
    // The fallback solvers join only once the others make no more progress.
    std::vector<CircuitSolver> solvers = circuit_solvers();
    for (int phase = 0; phase < 2; ++phase) {
      if (phase == 1)
        solvers.insert(solvers.end(), fallback_circuit_solvers().begin(),
                       fallback_circuit_solvers().end());
      for (bool progress = true; progress;) {
        progress = false;
        for (size_t ci = 0; ci < g_.chords.size(); ++ci)
          for (const CircuitSolver& solver : solvers) {
            if (circuit_closed[ci]) break;
            const std::optional<CircuitClosedForm> group = solver(context, static_cast<int>(ci));
            if (!group) continue;
            circuit_closed[ci] = group->closes;
            progress = true;
            const int index = static_cast<int>(out_.groups.size());
            out_.closed_form_groups.push_back(index);
            out_.groups.push_back(group->name);
            out_.plan.push_back(group->name + ": " + group->plan);
            for (const ex& reach : group->reach) out_.guards.push_back({reach, index});
            for (const auto& [column, q] : group->coordinates) {
              value[static_cast<size_t>(secondary_index[static_cast<size_t>(column)])] = q;
              context.known[static_cast<size_t>(column)] = true;
            }
            for (const auto& [column, cs] : group->cos_sin) {
              trig_[GiNaC::cos(cols_[static_cast<size_t>(column)].q)] = cs.first;
              trig_[GiNaC::sin(cols_[static_cast<size_t>(column)].q)] = cs.second;
            }
          }
      }
    }
    return value;
  }

  // Positions of the secondary coordinates: the closed forms first, then kNewtonSteps
  // Newton-Raphson steps from the State's warm start on the rest (the circuits not closed in
  // closed form): one step derived on its own list (out_.newton_step, on a renamed copy of the
  // position definitions that depend on those coordinates), which the kernel repeats in a loop
  // (one function for every entry point: the header grows with one step, not five per entry);
  // then the definitions themselves at the result.
  static constexpr int kNewtonSteps = 5;
  void close_positions(size_t start) {
    circuit_rows();
    sample_secondary_matrix(start);
    const size_t chain_end = out_.definitions.size();
    std::vector<bool> circuit_closed;
    const std::vector<std::optional<ex>> closed_form = solve_in_closed_form(start, circuit_closed);
    std::vector<size_t> newton_rows, newton_columns;
    for (size_t r = 0; r < network_.size(); ++r)
      if (!circuit_closed[r / 6]) newton_rows.push_back(r);
    for (size_t i = 0; i < g_.secondary.size(); ++i)
      if (!closed_form[i]) newton_columns.push_back(i);
    const PivotOrder newton = least_squares(pivot_order(newton_rows, newton_columns), newton_rows);
    choose_pivots(newton_rows, newton_columns.size(), newton.crosses);
    // Program order: what depends on no secondary coordinate, the closed forms, what depends on
    // them only, then the Newton steps and what depends on the Newton coordinates.
    std::vector<std::pair<symbol, ex>> chain(
        out_.definitions.begin() + static_cast<std::ptrdiff_t>(start),
        out_.definitions.begin() + static_cast<std::ptrdiff_t>(chain_end));
    std::vector<std::pair<symbol, ex>> closed_forms(
        out_.definitions.begin() + static_cast<std::ptrdiff_t>(chain_end), out_.definitions.end());
    out_.definitions.resize(start);
    std::set<ex, GiNaC::ex_is_less> solved, moving;
    for (size_t i = 0; i < g_.secondary.size(); ++i)
      (closed_form[i] ? solved : moving).insert(cols_[static_cast<size_t>(g_.secondary[i])].q);
    const auto uses = [](const ex& value, const std::set<ex, GiNaC::ex_is_less>& names) {
      for (auto it = value.preorder_begin(); it != value.preorder_end(); ++it)
        if (names.count(*it)) return true;
      return false;
    };
    std::vector<std::pair<symbol, ex>> after_closed_form, dependent;
    for (const auto& [sym, value] : chain) {
      if (uses(value, moving)) {
        moving.insert(sym);
        dependent.emplace_back(sym, value);
      } else if (uses(value, solved)) {
        solved.insert(sym);
        after_closed_form.emplace_back(sym, value);
      } else {
        out_.definitions.emplace_back(sym, value);
      }
    }
    // A closed form may read coordinates another gave (and what depends on them): each
    // definition after those it reads (the order above where it already is one).
    for (size_t i = 0; i < g_.secondary.size(); ++i)
      if (closed_form[i])
        closed_forms.emplace_back(
            GiNaC::ex_to<symbol>(cols_[static_cast<size_t>(g_.secondary[i])].q), *closed_form[i]);
    for (auto& [sym, value] : after_closed_form) {
      const auto it = trig_.find(value);
      if (it != trig_.end()) value = it->second;
      closed_forms.emplace_back(sym, value);
    }
    emit_in_dependency_order(std::move(closed_forms));
    const size_t nn = newton_columns.size();
    std::vector<ex> q(g_.secondary.size());  // the iterate, s.closure.next[k]
    for (size_t k = 0; k < nn; ++k) {
      q[newton_columns[k]] = symbol("s.closure.next[" + std::to_string(k) + "]");
      out_.closure_start.push_back(
          assembly_.q[static_cast<Eigen::Index>(g_.secondary[newton_columns[k]])]);
      out_.closure_columns.push_back(g_.secondary[newton_columns[k]]);
    }
    if (nn > 0) {
      sink_ = &out_.newton_step;
      GiNaC::exmap subs;
      for (const size_t i : newton_columns)
        subs[cols_[static_cast<size_t>(g_.secondary[i])].q] = q[i];
      for (const auto& [sym, value] : dependent) {
        const symbol copy(sym.get_name() + "_n");
        out_.newton_step.emplace_back(copy, value.subs(subs));
        subs[sym] = copy;
      }
      const Lu lu = factor(closure_matrix(newton, subs, "n_"), "n_");
      std::vector<ex> rhs;
      for (const size_t r : newton.rows) rhs.push_back(-residual_[r].subs(subs));
      const std::vector<ex> dq =
          unpermute(newton, solve(lu, closure_rhs(newton, rhs, subs, "n_"), "n_"));
      for (const size_t i : newton_columns)
        out_.newton_update.push_back(named_always(
            "q_" + cols_[static_cast<size_t>(g_.secondary[i])].name + "_n", q[i] + dq[i]));
      sink_ = &out_.definitions;
      out_.newton_steps = kNewtonSteps;
    }
    // The positions read the loop's result.
    for (size_t k = 0; k < nn; ++k) {
      const ex& coordinate = cols_[static_cast<size_t>(g_.secondary[newton_columns[k]])].q;
      out_.definitions.emplace_back(GiNaC::ex_to<symbol>(coordinate), q[newton_columns[k]]);
    }
    for (const auto& definition : dependent) out_.definitions.push_back(definition);
    closure_residual();
  }
  void closure_residual() {
    ex sum = 0;
    for (const ex& r : residual_) sum += r * r;
    output(out_.kinematics, "s.closure.residual", named("closure_residual", sum));
  }

  // Davies' method at the closed pose: q_s' = -N_s^-1 N_p q_p' (and the sensitivity
  // -N_s^-1 N_p for the Jacobians), q_s'' from the derivative of the circulation law,
  // N q'' + sum_i q_i' d$_i/dt = 0, through one elimination.
  void secondary_rates(bool accelerations) {
    const size_t ns = g_.secondary.size();
    if (!accelerations) {
      lu_ = factor(closure_matrix(pivot_, {}, "lu_"), "lu_");
      for (size_t k = 0; k < lu_.pivots.size(); ++k)
        output(out_.kinematics, "s.closure.pivot[" + std::to_string(k) + "]", lu_.pivots[k]);
      std::vector<ex> rhs;
      for (const size_t r : pivot_.rows) {
        ex b = 0;
        for (const int c : g_.primary)
          b -= network_[r][static_cast<size_t>(c)] * cols_[static_cast<size_t>(c)].qd;
        rhs.push_back(b);
      }
      const std::vector<ex> qd =
          unpermute(pivot_, solve(lu_, closure_rhs(pivot_, rhs, {}, "vel_"), "vel_"));
      for (size_t i = 0; i < ns; ++i) {
        Column& col = cols_[static_cast<size_t>(g_.secondary[i])];
        col.qd = named("qd_" + col.name, qd[i]);
      }
      backward_error("rate", rhs,
                     [&](size_t i) { return cols_[static_cast<size_t>(g_.secondary[i])].qd; });
      // The closed forms' warm starts move along these rates to the next call's time.
      for (size_t k = 0; k < out_.angle_columns.size(); ++k)
        output(out_.kinematics, "s.closure.wdnext[" + std::to_string(k) + "]",
               cols_[static_cast<size_t>(out_.angle_columns[k])].qd);
      sensitivity_.assign(g_.columns.size(), std::vector<ex>(g_.primary.size(), 0));
      for (size_t k = 0; k < g_.primary.size(); ++k) {
        sensitivity_[static_cast<size_t>(g_.primary[k])][k] = 1;
        std::vector<ex> b;
        for (const size_t r : pivot_.rows)
          b.push_back(-network_[r][static_cast<size_t>(g_.primary[k])]);
        const std::string prefix = "sen" + std::to_string(k) + "_";
        const std::vector<ex> x =
            unpermute(pivot_, solve(lu_, closure_rhs(pivot_, b, {}, prefix), prefix));
        for (size_t i = 0; i < ns; ++i)
          sensitivity_[static_cast<size_t>(g_.secondary[i])][k] = x[i];
      }
      return;
    }
    std::vector<ex> rhs;
    for (const size_t r : pivot_.rows) {
      const std::vector<int>& coef = circuit_coef_[r / 6];
      ex b = 0;
      for (const int c : g_.primary)
        b -= network_[r][static_cast<size_t>(c)] * cols_[static_cast<size_t>(c)].qdd;
      for (size_t c = 0; c < g_.columns.size(); ++c) {
        const Twist& rate = cols_[c].rate;
        b -= coef[c] * cols_[c].qd * (r % 6 < 3 ? rate.w[r % 6] : rate.v[r % 6 - 3]);
      }
      rhs.push_back(named("acc_rhs" + std::to_string(r), b));
    }
    const std::vector<ex> qdd =
        unpermute(pivot_, solve(lu_, closure_rhs(pivot_, rhs, {}, "acc_"), "acc_"));
    for (size_t i = 0; i < ns; ++i) {
      Column& col = cols_[static_cast<size_t>(g_.secondary[i])];
      col.qdd = named("qdd_" + col.name, qdd[i]);
    }
    backward_error("acc", rhs,
                   [&](size_t i) { return cols_[static_cast<size_t>(g_.secondary[i])].qdd; });
    for (size_t k = 0; k < out_.angle_columns.size(); ++k)
      output(out_.kinematics, "s.closure.wddnext[" + std::to_string(k) + "]",
             cols_[static_cast<size_t>(out_.angle_columns[k])].qdd);
  }

  // The backward error of a solve through lu_ (N_s x = b over the pivot rows): the squared
  // residual and the squared size of its terms, as s.closure.<name>_residual and _scale. The
  // pivot order is fixed at generation time, and one of its pivots can pass near zero at a
  // regular pose the samples did not see (lecture_leg_ik with py = 0: the ankle level with the
  // hip); the elimination then returns finite rates that are wrong, which the entries refuse.
  template <class Solution>
  void backward_error(const std::string& name, const std::vector<ex>& b, Solution x) {
    ex residual = 0, scale = 0;
    for (size_t k = 0; k < pivot_.rows.size(); ++k) {
      const ex rhs = named(name + "_rhs" + std::to_string(k), b[k]);
      ex sum = -rhs;
      scale += rhs * rhs;
      for (size_t i = 0; i < g_.secondary.size(); ++i) {
        const ex term = network_[pivot_.rows[k]][static_cast<size_t>(g_.secondary[i])] * x(i);
        sum += term;
        scale += term * term;
      }
      const ex row = named(name + "_residual" + std::to_string(k), sum);
      residual += row * row;
    }
    output(out_.kinematics, "s.closure." + name + "_residual", named(name + "_residual", residual));
    output(out_.kinematics, "s.closure." + name + "_scale", named(name + "_scale", scale));
  }

  // Body twists, each screw's rate (the Lie bracket of the twist of the frame carrying it with
  // it) and, for a tree, the twist rates in the same pass. A closed chain's secondary
  // accelerations need the screw rates first: twist_rates() follows them.
  void twists() {
    const size_t nb = m_.bodies.size();
    V_.assign(nb, Twist{});
    A_.assign(nb, Twist{});
    for (const int b : g_.order) {
      if (b == m_.ground) continue;
      const auto bi = static_cast<size_t>(b);
      const int p = g_.parent[bi], j = g_.parent_joint[bi];
      const SpatialJoint& joint = m_.joints[static_cast<size_t>(j)];
      const ex sign = joint.first == p ? 1 : -1;
      const auto c0 = static_cast<size_t>(g_.joint_column[static_cast<size_t>(j)]);
      Twist V = V_[static_cast<size_t>(p)];
      for (size_t k = 0; k < joint.columns.size(); ++k)
        V = V + (sign * cols_[c0 + k].qd) * cols_[c0 + k].screw;
      V_[bi] = named("w_" + body_name(b), "v_" + body_name(b), V);
      screw_rates(static_cast<size_t>(j));
      if (!closed()) twist_rate(b);
    }
    for (const int j : g_.chords) screw_rates(static_cast<size_t>(j));
  }
  void screw_rates(size_t j) {
    Twist carrier = V_[static_cast<size_t>(m_.joints[j].first)];
    const auto c0 = static_cast<size_t>(g_.joint_column[j]);
    for (size_t k = 0; k < m_.joints[j].columns.size(); ++k) {
      Column& col = cols_[c0 + k];
      col.rate =
          named("dsw_" + col.name, "dsv_" + col.name, geometry::lie_bracket(carrier, col.screw));
      carrier = carrier + col.qd * col.screw;
    }
  }
  void twist_rate(int b) {
    const auto bi = static_cast<size_t>(b);
    const int p = g_.parent[bi], j = g_.parent_joint[bi];
    const SpatialJoint& joint = m_.joints[static_cast<size_t>(j)];
    const ex sign = joint.first == p ? 1 : -1;
    const auto c0 = static_cast<size_t>(g_.joint_column[static_cast<size_t>(j)]);
    Twist A = A_[static_cast<size_t>(p)];
    for (size_t k = 0; k < joint.columns.size(); ++k) {
      const Column& col = cols_[c0 + k];
      A = A + (sign * col.qdd) * col.screw + (sign * col.qd) * col.rate;
    }
    A_[bi] = named("dw_" + body_name(b), "dv_" + body_name(b), A);
  }
  void twist_rates() {
    if (!closed()) return;
    for (const int b : g_.order)
      if (b != m_.ground) twist_rate(b);
  }

  void body_outputs() {
    const size_t nb = m_.bodies.size();
    com_.assign(nb, V{});
    acc_.assign(nb, V{});
    for (size_t b = 0; b < nb; ++b) {
      const SpatialBody& body = m_.bodies[b];
      if (body.ground) continue;
      const Pose& F = frame_[b];
      com_[b] = named("com_" + body.name,
                      F.R * named("com_local_" + body.name, vec(body.mass.com)) + F.p);
      // The centre of mass's acceleration dv + dw x c + w x (v + w x c), through its velocity.
      const V vc = named("vc_" + body.name, geometry::point_velocity(V_[b], com_[b]));
      acc_[b] = named("ac_" + body.name,
                      geometry::point_velocity(A_[b], com_[b]) + geometry::cross(V_[b].w, vc));
      if (body.is_virtual) continue;
      const std::string o = "s.bodies." + body.name + ".";
      output(out_.kinematics, o, {"x", "y", "z"}, com_[b]);
      for (size_t k = 0; k < 9; ++k)
        output(out_.kinematics, o + "R[" + std::to_string(k) + "]", F.R.m[k]);
      output(out_.kinematics, o, {"vx", "vy", "vz"}, vc);
      output(out_.kinematics, o, {"ax", "ay", "az"}, acc_[b]);
      output(out_.kinematics, o, {"wx", "wy", "wz"}, V_[b].w);
      output(out_.kinematics, o, {"alx", "aly", "alz"}, A_[b].w);
    }
    for (const auto& [point, b] : m_.named_points()) {
      const SpatialBody& body = m_.bodies[static_cast<size_t>(b)];
      for (const SpatialPoint& sp : body.points)
        if (sp.name == point) {
          const Pose& F = frame_[static_cast<size_t>(b)];
          point_[point] =
              named("pt_" + point, F.R * named("pt_local_" + point, vec(sp.local)) + F.p);
          const std::string o = "s.points." + point + ".";
          output(out_.kinematics, o, {"x", "y", "z"}, point_[point]);
          const auto bi = static_cast<size_t>(b);
          const V v = named("vp_" + point, geometry::point_velocity(V_[bi], point_[point]));
          output(out_.kinematics, o, {"vx", "vy", "vz"}, v);
          output(out_.kinematics, o, {"ax", "ay", "az"},
                 geometry::point_velocity(A_[bi], point_[point]) + geometry::cross(V_[bi].w, v));
          break;
        }
    }
    for (size_t j = 0; j < m_.joints.size(); ++j) {
      const SpatialJoint& joint = m_.joints[j];
      if (joint.is_virtual) continue;
      for (size_t k = 0; k < joint.columns.size(); ++k) {
        const Column& col = cols_[static_cast<size_t>(g_.joint_column[j]) + k];
        const std::string q = joint.columns.size() == 1 ? "q" : "q" + std::to_string(k + 1);
        const std::string o = "s.joints." + joint.name + "." + q;
        output(out_.kinematics, o, col.q);
        output(out_.kinematics, o + "d", col.qd);
        output(out_.kinematics, o + "dd", col.qdd);
      }
    }
    for (const SpatialPrimaryInput& in : inputs_) {
      const Column& col = cols_[static_cast<size_t>(in.graph_column)];
      const std::string o = "s.drivers." + in.name + ".";
      output(out_.kinematics, o + "q", symbol("in." + in.name));
      output(out_.kinematics, o + "qd", col.qd);
      output(out_.kinematics, o + "qdd", col.qdd);
    }
  }

  // Column k of a body's twist Jacobian is the signed screw of primary k on its tree path; of a
  // point's velocity Jacobian, that screw's velocity at the point.
  void jacobians() {
    if (closed()) {
      closed_jacobians();
      return;
    }
    for (size_t b = 0; b < m_.bodies.size(); ++b) {
      const SpatialBody& body = m_.bodies[b];
      if (body.ground || body.is_virtual || !m_.emits_jacobian(body.name)) continue;
      for (size_t k = 0; k < g_.primary.size(); ++k) {
        const auto c = static_cast<size_t>(g_.primary[k]);
        const ex sign = g_.path_sign[b][c];
        for (int r = 0; r < 6; ++r)
          output(out_.jacobians,
                 "s.body_jacobians." + body.name + "[" + std::to_string(r) + "][" +
                     std::to_string(k) + "]",
                 (sign * (r < 3 ? cols_[c].screw.w[static_cast<size_t>(r)]
                                : cols_[c].screw.v[static_cast<size_t>(r - 3)]))
                     .expand());
      }
    }
    for (const auto& [point, b] : m_.named_points()) {
      if (m_.bodies[static_cast<size_t>(b)].ground || !m_.emits_jacobian(point)) continue;
      const V& x = point_.at(point);
      for (size_t k = 0; k < g_.primary.size(); ++k) {
        const auto c = static_cast<size_t>(g_.primary[k]);
        const ex sign = g_.path_sign[static_cast<size_t>(b)][c];
        const V v = geometry::point_velocity(cols_[c].screw, x);
        for (int r = 0; r < 3; ++r)
          output(out_.jacobians,
                 "s.point_jacobians." + point + "[" + std::to_string(r) + "][" + std::to_string(k) +
                     "]",
                 (sign * v[static_cast<size_t>(r)]).expand());
      }
    }
  }

  // A closed chain's: column k of a body's twist Jacobian is sum_i sign_i $_i dq_i/dq_pk over
  // its tree path, with the secondary coordinates' sensitivity from Davies' elimination.
  void closed_jacobians() {
    std::vector<std::vector<Twist>>& J = jacobian_;
    J.assign(m_.bodies.size(), {});
    for (size_t b = 0; b < m_.bodies.size(); ++b) {
      const SpatialBody& body = m_.bodies[b];
      if (body.ground) continue;
      for (size_t k = 0; k < g_.primary.size(); ++k) {
        Twist t;
        for (size_t c = 0; c < g_.columns.size(); ++c)
          if (g_.path_sign[b][c] != 0 && !sensitivity_[c][k].is_zero())
            t = t + (g_.path_sign[b][c] * sensitivity_[c][k]) * cols_[c].screw;
        J[b].push_back(named("jw_" + body.name + "_" + std::to_string(k),
                             "jv_" + body.name + "_" + std::to_string(k), t));
        if (body.is_virtual || !m_.emits_jacobian(body.name)) continue;
        for (int r = 0; r < 6; ++r)
          output(out_.jacobians,
                 "s.body_jacobians." + body.name + "[" + std::to_string(r) + "][" +
                     std::to_string(k) + "]",
                 r < 3 ? J[b][k].w[static_cast<size_t>(r)] : J[b][k].v[static_cast<size_t>(r - 3)]);
      }
    }
    for (const auto& [point, b] : m_.named_points()) {
      if (m_.bodies[static_cast<size_t>(b)].ground || !m_.emits_jacobian(point)) continue;
      for (size_t k = 0; k < g_.primary.size(); ++k) {
        const V v = geometry::point_velocity(J[static_cast<size_t>(b)][k], point_.at(point));
        for (int r = 0; r < 3; ++r)
          output(out_.jacobians,
                 "s.point_jacobians." + point + "[" + std::to_string(r) + "][" + std::to_string(k) +
                     "]",
                 v[static_cast<size_t>(r)].expand());
      }
    }
  }

  // A closed chain's driver efforts by virtual power: effort k = sum_b W_b . J_bk, each body's
  // rate of momentum minus gravity W_b (about the ground origin) against column k of its twist
  // Jacobian (unique even where the circuits are redundant); then the reactions.
  void closed_efforts() {
    momentum_.assign(m_.bodies.size(), Wrench{});
    std::vector<ex> effort(g_.primary.size(), 0);
    for (size_t b = 0; b < m_.bodies.size(); ++b) {
      if (static_cast<int>(b) == m_.ground) continue;
      const Wrench W = momentum_rate(b);
      for (size_t k = 0; k < g_.primary.size(); ++k)
        effort[k] += geometry::reciprocal(jacobian_[b][k], W);
    }
    for (size_t k = 0; k < g_.primary.size(); ++k) {
      const std::string& name = input(static_cast<size_t>(g_.primary[k]))->name;
      effort[k] = named("tau_" + name, effort[k]);
      output(out_.dynamics, "s.drivers." + name + ".effort", effort[k]);
    }
    closed_reactions(effort);
  }

  // A closed chain's reactions, as the numeric solver defines them (A x = b, minimum norm where
  // redundant). Each circuit's chord carries an unknown wrench y_c (first body on second, about
  // the ground origin); a tree joint transmits what the tree's backward pass gives plus the
  // wrenches of the chords whose circuits pass through it (the circuit's column signs), so "no
  // work on a secondary screw" is N_s^T y = r: Davies' network transposed, solved through the
  // same fixed-order elimination (lu_, transposed). Rows the pivot order dropped (redundant
  // closure rows) leave y free along N_s's left null space (one direction per dropped row); the
  // minimum-norm reactions are the particular one (y zero there) minus its projection on that
  // space: a d x d Gram solve, symmetric positive definite, in a fixed order.
  void closed_reactions(const std::vector<ex>& tau) {
    const size_t nb = m_.bodies.size(), nj = m_.joints.size();
    std::vector<Wrench> transmitted(nb);  // on each body's subtree, from the tree alone
    for (auto it = g_.order.rbegin(); it != g_.order.rend(); ++it) {
      const auto b = static_cast<size_t>(*it);
      if (*it == m_.ground) continue;
      Wrench T = momentum_[b];
      for (size_t ch = 0; ch < nb; ++ch)
        if (g_.parent[ch] == *it) T = T + transmitted[ch];
      transmitted[b] = {named("tf_" + body_name(*it), T.f), named("tm_" + body_name(*it), T.m)};
    }
    // Per joint: the tree's wrench of its first body on its second, its effort wrench, and the
    // sign of each circuit's chord wrench in it.
    std::vector<Wrench> tree(nj), effort(nj);
    std::vector<std::vector<int>> coef(nj, std::vector<int>(g_.chords.size(), 0));
    joint_point_.assign(nj, V{});
    for (size_t j = 0; j < nj; ++j) joint_point_[j] = joint_point(static_cast<int>(j));
    for (size_t b = 0; b < nb; ++b) {
      if (static_cast<int>(b) == m_.ground) continue;
      const auto j = static_cast<size_t>(g_.parent_joint[b]);
      const int sign = m_.joints[j].first == g_.parent[b] ? 1 : -1;
      tree[j] = sign == 1 ? transmitted[b] : Wrench{-transmitted[b].f, -transmitted[b].m};
      for (size_t c = 0; c < g_.chords.size(); ++c) {
        const SpatialJoint& chord = m_.joints[static_cast<size_t>(g_.chords[c])];
        coef[j][c] = sign * (in_subtree(chord.first, static_cast<int>(b)) -
                             in_subtree(chord.second, static_cast<int>(b)));
      }
    }
    for (size_t c = 0; c < g_.chords.size(); ++c) coef[static_cast<size_t>(g_.chords[c])][c] = 1;
    for (size_t k = 0; k < g_.primary.size(); ++k) {
      const auto c = static_cast<size_t>(g_.primary[k]);
      const auto j = static_cast<size_t>(g_.columns[c].joint);
      const Wrench e = unit_effort(cols_[c], joint_point_[j]);
      effort[j] = effort[j] + Wrench{tau[k] * e.f, tau[k] * e.m};
    }
    // r: per elimination unknown (a secondary column of joint j), what the tree and the efforts
    // leave: <$, E_j - W_tree_j>.
    std::vector<ex> r;
    for (const size_t i : pivot_.columns) {
      const auto c = static_cast<size_t>(g_.secondary[i]);
      const auto j = static_cast<size_t>(g_.columns[c].joint);
      r.push_back(geometry::reciprocal(cols_[c].screw,
                                       Wrench{effort[j].f - tree[j].f, effort[j].m - tree[j].m}));
    }
    if (pivot_.least_squares) {
      output_reactions(least_squares_reactions(r, tree, effort, coef));
      return;
    }
    const std::vector<Wrench> x =
        chord_reactions(on_rows(solve_transposed(lu_, r, "rct_")), "rx", tree, effort, coef);
    // The null space: per dropped row, y = e_row - (S^-T N_s[row]^T on the pivot rows).
    std::vector<std::vector<Wrench>> z;
    const std::vector<Wrench> none(nj);
    for (size_t row = 0; row < network_.size(); ++row) {
      if (std::find(pivot_.rows.begin(), pivot_.rows.end(), row) != pivot_.rows.end()) continue;
      const std::string n = "null" + std::to_string(z.size());
      std::vector<ex> b;
      for (const size_t i : pivot_.columns)
        b.push_back(-network_[row][static_cast<size_t>(g_.secondary[i])]);
      std::vector<ex> y = on_rows(solve_transposed(lu_, b, n + "_"));
      y[row] = 1;
      z.push_back(chord_reactions(y, n, none, none, coef));
    }
    // Minimum norm: x - Z (Z^T Z)^-1 Z^T x over every joint's six components.
    std::vector<std::vector<ex>> gram(z.size(), std::vector<ex>(z.size()));
    std::vector<ex> rhs;
    for (size_t a = 0; a < z.size(); ++a) {
      for (size_t b = 0; b < z.size(); ++b)
        gram[a][b] = b < a ? gram[b][a]
                           : named("gram" + std::to_string(a) + "_" + std::to_string(b),
                                   reaction_dot(z[a], z[b]));
      rhs.push_back(named("gram_rhs" + std::to_string(a), -reaction_dot(z[a], x)));
    }
    const std::vector<ex> alpha = solve(factor(gram, "gram_"), rhs, "gram_");
    std::vector<Wrench> w = x;
    for (size_t j = 0; j < nj; ++j)
      for (size_t a = 0; a < z.size(); ++a)
        w[j] = w[j] + Wrench{alpha[a] * z[a][j].f, alpha[a] * z[a][j].m};
    output_reactions(w);
  }
  void output_reactions(const std::vector<Wrench>& w) {
    for (size_t j = 0; j < m_.joints.size(); ++j) {
      const SpatialJoint& joint = m_.joints[j];
      if (joint.is_virtual) continue;
      const std::string o = "s.joints." + joint.name + ".";
      output(out_.dynamics, o, {"fx", "fy", "fz"}, named("rf_" + joint.name, w[j].f));
      output(out_.dynamics, o, {"mx", "my", "mz"}, named("rm_" + joint.name, w[j].m));
    }
  }
  // The norm the reactions minimise: every joint's six components.
  static ex reaction_dot(const std::vector<Wrench>& a, const std::vector<Wrench>& b) {
    ex sum = 0;
    for (size_t j = 0; j < a.size(); ++j)
      sum += geometry::dot(a[j].f, b[j].f) + geometry::dot(a[j].m, b[j].m);
    return sum;
  }
  // A vector over the pivot rows (elimination order) spread over all of N's rows (zero elsewhere).
  std::vector<ex> on_rows(const std::vector<ex>& y) const {
    std::vector<ex> out(network_.size(), 0);
    for (size_t k = 0; k < pivot_.rows.size(); ++k) out[pivot_.rows[k]] = y[k];
    return out;
  }

  // Least squares (no square set of rows, see least_squares()): the chord wrenches y, one per
  // closure row, that satisfy N_s^T y = r with the smallest reactions. With Z the reactions of a
  // unit chord wrench per row and x0 those of the tree and the efforts alone, the KKT conditions
  // of min |x0 + Z y|^2 are y = -H^-1 (g + N_s l) with H = Z^T Z, g = Z^T x0 and
  // (N_s^T H^-1 N_s) l = -r - N_s^T H^-1 g. H is positive definite (each chord joint carries its
  // own wrench alone) and N_s^T H^-1 N_s wherever N_s has full column rank: both eliminations
  // keep a fixed order.
  std::vector<Wrench> least_squares_reactions(const std::vector<ex>& r,
                                              const std::vector<Wrench>& tree,
                                              const std::vector<Wrench>& effort,
                                              const std::vector<std::vector<int>>& coef) {
    const size_t nr = network_.size(), n = pivot_.columns.size();
    const std::vector<Wrench> none(m_.joints.size());
    const std::vector<Wrench> x0 =
        chord_reactions(std::vector<ex>(nr, 0), "kx", tree, effort, coef);
    std::vector<std::vector<Wrench>> z;
    for (size_t row = 0; row < nr; ++row) {
      std::vector<ex> unit(nr, 0);
      unit[row] = 1;
      z.push_back(chord_reactions(unit, "kz" + std::to_string(row), none, none, coef));
    }
    std::vector<std::vector<ex>> h(nr, std::vector<ex>(nr));
    std::vector<ex> g;
    for (size_t a = 0; a < nr; ++a) {
      for (size_t b = a; b < nr; ++b)
        h[a][b] = h[b][a] =
            named("kh" + std::to_string(a) + "_" + std::to_string(b), reaction_dot(z[a], z[b]));
      g.push_back(named("kg" + std::to_string(a), reaction_dot(z[a], x0)));
    }
    const Lu lh = factor(h, "kh_");
    const auto column = [&](size_t k) {  // N_s's column of elimination unknown k
      std::vector<ex> c;
      for (size_t row = 0; row < nr; ++row)
        c.push_back(network_[row][static_cast<size_t>(g_.secondary[pivot_.columns[k]])]);
      return c;
    };
    std::vector<std::vector<ex>> u;  // H^-1 N_s, per elimination unknown
    for (size_t k = 0; k < n; ++k)
      u.push_back(solve(lh, column(k), "ku" + std::to_string(k) + "_"));
    const std::vector<ex> hg = solve(lh, g, "khg_");
    std::vector<std::vector<ex>> kkt(n, std::vector<ex>(n));
    std::vector<ex> rhs;
    for (size_t a = 0; a < n; ++a) {
      const std::vector<ex> na = column(a);
      for (size_t b = a; b < n; ++b) {
        ex sum = 0;
        for (size_t row = 0; row < nr; ++row) sum += na[row] * u[b][row];
        kkt[a][b] = kkt[b][a] = named("kk" + std::to_string(a) + "_" + std::to_string(b), sum);
      }
      ex sum = -r[a];
      for (size_t row = 0; row < nr; ++row) sum -= na[row] * hg[row];
      rhs.push_back(named("kl_rhs" + std::to_string(a), sum));
    }
    const std::vector<ex> l = solve(factor(kkt, "kk_"), rhs, "kl_");
    std::vector<ex> y;
    for (size_t row = 0; row < nr; ++row) {
      ex sum = -hg[row];
      for (size_t a = 0; a < n; ++a) sum -= u[a][row] * l[a];
      y.push_back(named("ky" + std::to_string(row), sum));
    }
    return chord_reactions(y, "rx", tree, effort, coef);
  }

  // Every joint's reaction (force, moment at its point) from the chords' wrenches y (one per
  // network row), the tree's wrench and the efforts: W_j = tree_j + sum_c coef_jc y_c - effort_j.
  std::vector<Wrench> chord_reactions(const std::vector<ex>& y, const std::string& prefix,
                                      const std::vector<Wrench>& tree,
                                      const std::vector<Wrench>& effort,
                                      const std::vector<std::vector<int>>& coef) {
    std::vector<Wrench> chord(g_.chords.size());
    auto place = [&](size_t row, const ex& value) {
      Wrench& w = chord[row / 6];
      (row % 6 < 3 ? w.m[row % 6] : w.f[row % 6 - 3]) += value;  // N's rows: w then v
    };
    for (size_t row = 0; row < y.size(); ++row) place(row, y[row]);
    std::vector<Wrench> out;
    for (size_t j = 0; j < m_.joints.size(); ++j) {
      Wrench w{tree[j].f - effort[j].f, tree[j].m - effort[j].m};
      for (size_t c = 0; c < chord.size(); ++c)
        if (coef[j][c] != 0)
          w = w + Wrench{ex(coef[j][c]) * chord[c].f, ex(coef[j][c]) * chord[c].m};
      const std::string n = prefix + "_" + m_.joints[j].name;
      const V f = named(n + "_f", w.f);
      out.push_back({f, named(n + "_m", w.m - geometry::cross(joint_point_[j], f))});
    }
    return out;
  }

  // Solves S^T y = b with S = L U the elimination `lu` (U^T z = b forward, then L^T y = z).
  std::vector<ex> solve_transposed(const Lu& lu, std::vector<ex> b, const std::string& prefix) {
    const size_t n = b.size();
    for (size_t k = 0; k < n; ++k) {
      ex sum = b[k];
      for (size_t i = 0; i < k; ++i) sum -= lu.a[i][k] * b[i];
      b[k] = named(prefix + "z" + std::to_string(k), sum * lu.inv[k]);
    }
    for (size_t k = n; k-- > 0;) {
      ex sum = b[k];
      for (size_t i = k + 1; i < n; ++i) sum -= lu.f[i][k] * b[i];
      b[k] = named(prefix + "y" + std::to_string(k), sum);
    }
    return b;
  }

  // Whether body b lies in the subtree of body root (root itself included).
  int in_subtree(int b, int root) const {
    for (; b >= 0; b = g_.parent[static_cast<size_t>(b)])
      if (b == root) return 1;
    return 0;
  }

  // Rate of momentum minus gravity and the applied loads of body b, as a wrench about the ground
  // origin (the numeric solver's right-hand side).
  Wrench momentum_rate(size_t b) {
    const SpatialBody& body = m_.bodies[b];
    const std::string& n = body.name;
    // Mass and inertia (parameter expressions, e.g. a bar's from its density) named once, so
    // that they multiply as numbers instead of expanding into every product.
    const ex mass = named("m_" + n, param(body.mass.mass.ex));
    M I;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const ex e = param(body.mass.inertia[static_cast<size_t>(3 * i + j)]);
        I(i, j) = j < i && (e - param(body.mass.inertia[static_cast<size_t>(3 * j + i)]))
                               .expand()
                               .is_zero()
                      ? I(j, i)
                      : named("I_" + n + "_" + std::to_string(i) + std::to_string(j), e);
      }
    const M Rt = geometry::transpose(frame_[b].R);
    // Angular momentum about the centre of mass and its rate, through the body frame.
    const V h =
        named("h_" + n, frame_[b].R * named("Iwb_" + n, I * named("wb_" + n, Rt * V_[b].w)));
    const V Ia = frame_[b].R * named("Ialb_" + n, I * named("alb_" + n, Rt * A_[b].w));
    const V F = named("F_" + n, mass * (acc_[b] - vec(m_.gravity)));
    const V Mo = named("M_" + n, Ia + geometry::cross(V_[b].w, h) + geometry::cross(com_[b], F));
    const std::optional<Wrench> applied = applied_wrench(b);
    momentum_[b] =
        applied ? Wrench{named("Fnet_" + n, F - applied->f), named("Mnet_" + n, Mo - applied->m)}
                : Wrench{F, Mo};
    return momentum_[b];
  }

  // The applied loads (`forces:`) on body b as one wrench about the ground origin, as the
  // numeric solver's applied_wrenches: a force at a point of the body (its moment x x f), a
  // couple; components are ground-frame functions of the parameters and t (the input in.t).
  std::optional<Wrench> applied_wrench(size_t b) {
    std::optional<Wrench> sum;
    const GiNaC::exmap time{{m_.common.t, symbol("in.t")}};
    for (const SpatialLoad& load : m_.loads) {
      if (load.body != static_cast<int>(b)) continue;
      V value = vec(load.value);
      for (ex& e : value) e = e.subs(time);
      value = named("load_" + load.name, value);
      Wrench w{V{0, 0, 0}, value};
      if (!load.torque) {
        const Pose& F = frame_[b];
        for (const SpatialPoint& sp : m_.bodies[b].points)
          if (sp.name == load.point)
            w = {value,
                 geometry::cross(named("at_" + load.name, F.R * vec(sp.local) + F.p), value)};
      }
      sum = sum ? *sum + w : w;
    }
    return sum;
  }

  void dynamics() {
    const size_t nb = m_.bodies.size();
    std::vector<Wrench> transmitted(nb);
    momentum_.assign(nb, Wrench{});
    joint_point_.assign(m_.joints.size(), V{});
    for (auto it = g_.order.rbegin(); it != g_.order.rend(); ++it) {
      const int b = *it;
      if (b == m_.ground) continue;
      const auto bi = static_cast<size_t>(b);
      Wrench T = momentum_rate(bi);
      for (size_t ch = 0; ch < nb; ++ch)
        if (g_.parent[ch] == b) T = T + transmitted[ch];
      transmitted[bi] = {named("tf_" + body_name(b), T.f), named("tm_" + body_name(b), T.m)};
      joint_loads(g_.parent_joint[bi], g_.parent[bi], transmitted[bi]);
    }
  }

  // Joint j's point s0, carried by its second body.
  V joint_point(int j) {
    const SpatialJoint& joint = m_.joints[static_cast<size_t>(j)];
    return named("P_" + joint.name,
                 geometry::apply(D_[static_cast<size_t>(joint.second)],
                                 n_columns(j) == 0 ? named("s0_" + joint.name, vec(joint.s0))
                                                   : cols_[c0_of(j)].axis.s0));
  }
  // The wrench of a unit effort on a coordinate: a couple about its axis (rotation, helical) or
  // a force along it through the joint point (translation), as the numeric solver's.
  static Wrench unit_effort(const Column& col, const V& P) {
    if (col.axis.kind == geometry::ScrewKind::translation)
      return {col.screw.v, geometry::cross(P, col.screw.v)};
    return {V{0, 0, 0}, col.screw.w};
  }

  // The wrench the parent applies on its child through joint j: the efforts of its driven
  // coordinates (reciprocal products with their screws) and the remaining reaction.
  void joint_loads(int j, int parent, const Wrench& on_child) {
    const SpatialJoint& joint = m_.joints[static_cast<size_t>(j)];
    // The wrench of the joint's first body on its second.
    const Wrench W = joint.first == parent ? on_child : Wrench{-on_child.f, -on_child.m};
    const V P = joint_point(j);
    joint_point_[static_cast<size_t>(j)] = P;
    const auto c0 = static_cast<size_t>(g_.joint_column[static_cast<size_t>(j)]);
    const size_t n = joint.columns.size();
    std::vector<Wrench> unit_effort;  // per coordinate: the wrench of a unit effort
    for (size_t k = 0; k < n; ++k) unit_effort.push_back(this->unit_effort(cols_[c0 + k], P));
    // $_i . W = sum_k tau_k ($_i . e_k): one equation per coordinate (the reaction does no work
    // on the joint's screws). A single coordinate has $ . e = 1.
    std::vector<ex> tau(n);
    if (n == 1) {
      tau[0] = named("tau_" + cols_[c0].name, geometry::reciprocal(cols_[c0].screw, W));
    } else if (n > 1) {
      GiNaC::matrix G(static_cast<unsigned>(n), static_cast<unsigned>(n));
      GiNaC::matrix r(static_cast<unsigned>(n), 1);
      for (size_t i = 0; i < n; ++i) {
        const std::string ni = cols_[c0 + i].name;
        r(static_cast<unsigned>(i), 0) =
            named("rp_" + ni, geometry::reciprocal(cols_[c0 + i].screw, W));
        for (size_t k = 0; k < n; ++k)
          G(static_cast<unsigned>(i), static_cast<unsigned>(k)) =
              named("G_" + ni + "_" + std::to_string(k + 1),
                    geometry::reciprocal(cols_[c0 + i].screw, unit_effort[k]));
      }
      const GiNaC::matrix x = G.inverse().mul(r);
      for (size_t k = 0; k < n; ++k)
        tau[k] = named("tau_" + cols_[c0 + k].name, x(static_cast<unsigned>(k), 0));
    }
    Wrench R = W;
    for (size_t k = 0; k < n; ++k)
      R = R + Wrench{-(tau[k] * unit_effort[k].f), -(tau[k] * unit_effort[k].m)};
    for (size_t k = 0; k < n; ++k)
      if (const SpatialPrimaryInput* in = input(c0 + k))
        output(out_.dynamics, "s.drivers." + in->name + ".effort", tau[k]);
    if (joint.is_virtual) return;
    const std::string o = "s.joints." + joint.name + ".";
    output(out_.dynamics, o, {"fx", "fy", "fz"}, named("rf_" + joint.name, R.f));
    output(out_.dynamics, o, {"mx", "my", "mz"},
           named("rm_" + joint.name, R.m - geometry::cross(P, R.f)));
  }

  // The numeric solver's Newton-Euler system, from the same named screws, joint points and
  // rates of momentum (what ne_system() returns; the kernel itself solves it recursively).
  void ne_system() {
    std::vector<int> body_row(m_.bodies.size(), -1);
    int rows = 0;
    for (size_t b = 0; b < m_.bodies.size(); ++b)
      if (static_cast<int>(b) != m_.ground) body_row[b] = rows, rows += 6;
    const int column_row = rows;
    rows += g_.cols();
    const int n = 6 * static_cast<int>(m_.joints.size()) + static_cast<int>(g_.primary.size());
    std::map<int, ex> A;
    auto add = [&](int r, int c, const ex& e) { A[r * n + c] += e; };
    auto add_wrench = [&](int body, int col, const ex& sign, const Wrench& w) {
      if (body == m_.ground) return;
      for (int i = 0; i < 3; ++i) {
        add(body_row[static_cast<size_t>(body)] + i, col, sign * w.f[static_cast<size_t>(i)]);
        add(body_row[static_cast<size_t>(body)] + 3 + i, col, sign * w.m[static_cast<size_t>(i)]);
      }
    };
    const char* const components[6] = {"fx", "fy", "fz", "mx", "my", "mz"};
    for (size_t j = 0; j < m_.joints.size(); ++j) {
      const SpatialJoint& joint = m_.joints[j];
      const V& P = joint_point_[j];
      for (int k = 0; k < 6; ++k) {
        out_.ne_unknowns.push_back(joint.name + "." + components[k]);
        // Unknown k (force or moment at P) as a wrench about the ground origin.
        Wrench unit;
        if (k < 3) {
          unit.f[static_cast<size_t>(k)] = 1;
          V e{0, 0, 0};
          e[static_cast<size_t>(k)] = 1;
          unit.m = geometry::cross(P, e);
        } else {
          unit.m[static_cast<size_t>(k - 3)] = 1;
        }
        const int col = 6 * static_cast<int>(j) + k;
        add_wrench(joint.second, col, 1, unit);
        add_wrench(joint.first, col, -1, unit);
        for (size_t c = 0; c < joint.columns.size(); ++c)
          add(column_row + g_.joint_column[j] + static_cast<int>(c), col,
              geometry::reciprocal(cols_[c0_of(static_cast<int>(j)) + c].screw, unit));
      }
    }
    for (size_t k = 0; k < g_.primary.size(); ++k) {
      const SpatialColumn& sc = g_.columns[static_cast<size_t>(g_.primary[k])];
      const SpatialJoint& joint = m_.joints[static_cast<size_t>(sc.joint)];
      const Column& col = cols_[static_cast<size_t>(g_.primary[k])];
      const Wrench w = unit_effort(col, joint_point_[static_cast<size_t>(sc.joint)]);
      const int c = 6 * static_cast<int>(m_.joints.size()) + static_cast<int>(k);
      out_.ne_unknowns.push_back(input(static_cast<size_t>(g_.primary[k]))->column + ".effort");
      add_wrench(joint.second, c, 1, w);
      add_wrench(joint.first, c, -1, w);
    }
    for (const auto& [index, value] : A)
      if (!value.expand().is_zero()) out_.ne_matrix.emplace_back(index, value.expand());
    out_.ne_rhs.assign(static_cast<size_t>(rows), 0);
    for (size_t b = 0; b < m_.bodies.size(); ++b)
      for (int i = 0; body_row[b] >= 0 && i < 3; ++i) {
        out_.ne_rhs[static_cast<size_t>(body_row[b] + i)] = momentum_[b].f[static_cast<size_t>(i)];
        out_.ne_rhs[static_cast<size_t>(body_row[b] + 3 + i)] =
            momentum_[b].m[static_cast<size_t>(i)];
      }
    out_.ne_rows = rows;
  }

  size_t c0_of(int j) const { return static_cast<size_t>(g_.joint_column[static_cast<size_t>(j)]); }
  size_t n_columns(int j) const { return m_.joints[static_cast<size_t>(j)].columns.size(); }

  const SpatialModel& m_;
  const SpatialGraph& g_;
  GiNaC::exmap params_;
  std::vector<SpatialPrimaryInput> inputs_;
  std::vector<int> input_of_column_;  // per graph column: its index in inputs_, or -1
  SpatialDerivation out_;
  // Where named() puts its definitions: the program's, or the Newton step's while it is derived.
  std::vector<std::pair<symbol, ex>>* sink_ = &out_.definitions;
  std::vector<Column> cols_;
  std::vector<Pose> D_, frame_;  // per body: displacement from the reference pose; its frame
  std::vector<Twist> V_, A_;     // per body: ground-origin twist and its rate
  std::vector<V> com_, acc_;     // per body: centre of mass and its acceleration
  std::map<std::string, V> point_;
  std::vector<Wrench> momentum_;  // per body: rate of momentum minus gravity, about the origin
  std::vector<V> joint_point_;    // per joint: its current point
  // Closed chains: closure error rows, Davies' network (rows x columns), per circuit each
  // column's sign, the pivot rows in elimination order, the elimination at the closed pose and
  // d q / d q_p (columns x primaries).
  std::vector<ex> residual_;
  std::vector<std::vector<ex>> network_;
  std::vector<std::vector<int>> circuit_coef_;
  std::vector<std::vector<std::vector<double>>> samples_;  // N_s (rows x secondary) per sample
  std::vector<int>
      previous_;  // per sample: the one before it on its path (step, range walk), or -1
  spatial::SpatialState assembly_;  // the numeric solver's assembly (default parameters, t0)
  // cos q and sin q of closed-form coordinates -> their closed forms' (no trigonometry).
  std::map<ex, ex, GiNaC::ex_is_less> trig_;
  PivotOrder pivot_;  // Davies' elimination order of the whole N_s
  Lu lu_;
  std::vector<std::vector<ex>> sensitivity_;
  std::vector<std::vector<Twist>> jacobian_;  // per body, per primary: its twist Jacobian column
};

}  // namespace

GiNaC::exmap spatial_parameter_symbols(const SpatialModel& model) {
  GiNaC::exmap out;
  for (const Parameter& p : model.common.parameters) out[p.symbol] = symbol("p." + p.name);
  return out;
}

SpatialDerivation derive_spatial(const SpatialModel& model, const SpatialGraph& graph) {
  return Builder(model, graph).run();
}

}  // namespace mechgen::gen
