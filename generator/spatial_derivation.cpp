// Symbolic derivation of a spatial tree's kernel (spatial_derivation.hpp).
#include "spatial_derivation.hpp"

#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <stdexcept>

#include "geometry/screw.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"
#include "spatial_closed_form.hpp"

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
  Twist screw, rate;  // current unit screw and its time derivative
  std::string name;   // joint, or joint_2 for a multi-coordinate joint's second coordinate
};

class Builder {
 public:
  Builder(const SpatialModel& model, const SpatialGraph& graph)
      : m_(model), g_(graph), params_(spatial_parameter_symbols(model)) {}

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
    if (closed()) {
      closed_efforts();
    } else {
      dynamics();
      ne_system();
    }
    out_.primary_count = static_cast<int>(g_.primary.size());
    return std::move(out_);
  }

 private:
  ex param(const ex& e) const { return e.subs(params_); }
  V vec(const Vec3Expr& v) const { return {param(v.x.ex), param(v.y.ex), param(v.z.ex)}; }

  ex named(const std::string& name, const ex& e) {
    const ex x = e.expand();
    if (trivial(x)) return x;
    const symbol s(name);
    out_.definitions.emplace_back(s, x);
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
    if (!m_.pose_drivers.empty())
      throw std::runtime_error(file +
                               "spatial kernels are generated for joint drivers; pose drivers "
                               "are not generated yet (use --solver numeric)");
    for (const SpatialColumn& c : g_.columns)
      if (c.driver < 0 && !closed())
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
      if (sc.driver >= 0) {
        const SpatialDriver& d = m_.drivers[static_cast<size_t>(sc.driver)];
        col.q = symbol("in." + d.name);
        col.qd = symbol("in." + d.name + "_d");
        col.qdd = symbol("in." + d.name + "_dd");
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
      cols_.push_back(col);
    }
  }
  ex named_always(const std::string& name, const ex& e) {
    const symbol s(name);
    out_.definitions.emplace_back(s, e);
    return s;
  }

  // The motion of joint j: the product of its coordinates' displacements.
  Pose joint_motion(int j) const {
    Pose E;
    const auto c0 = static_cast<size_t>(g_.joint_column[static_cast<size_t>(j)]);
    for (size_t k = 0; k < m_.joints[static_cast<size_t>(j)].columns.size(); ++k)
      E = E * cols_[c0 + k].displacement;
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
        const Pose E = joint_motion(j);
        const SpatialJoint& joint = m_.joints[static_cast<size_t>(j)];
        const Pose D = joint.first == p ? D_[static_cast<size_t>(p)] * E
                                        : D_[static_cast<size_t>(p)] * geometry::inverse(E);
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
          vec(body.origin)};
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
        col.screw = named("sw_" + col.name, "sv_" + col.name,
                          geometry::adjoint(G, geometry::unit_twist(col.axis)));
        G = G * col.displacement;
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
    ex det = 1;
    std::string prefix;
  };
  Lu factor(std::vector<std::vector<ex>> a, const std::string& prefix) {
    const size_t n = a.size();
    Lu lu;
    lu.prefix = prefix;
    lu.f.assign(n, std::vector<ex>(n, 0));
    for (size_t k = 0; k < n; ++k) {
      const std::string sk = std::to_string(k);
      lu.det = lu.det * a[k][k];
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
      const Pose X = D_[static_cast<size_t>(joint.first)] * joint_motion(j) *
                     geometry::inverse(D_[static_cast<size_t>(joint.second)]);
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

  // Row selection and pivot order, fixed at generation time from N_s at sample configurations
  // (default parameters, kPivotSamples instants of the model's step, the numeric solver's
  // poses): greedily, the row whose entry in the next column is smallest against that column's
  // largest over the samples is avoided (a pivot through zero at a regular pose would make the
  // elimination meaningless there); rows never chosen are redundant (an overconstrained
  // circuit) and dropped.
  static constexpr int kPivotSamples = 72;
  void choose_pivots(size_t start) {
    const std::vector<double> defaults = m_.common.default_parameters();
    const spatial::SpatialSolver solver(m_, defaults);
    const spatial::SpatialSweepOptions sweep = spatial::default_spatial_sweep(m_, defaults);
    const size_t rows = network_.size(), ns = g_.secondary.size();
    std::vector<std::vector<std::vector<double>>> a;  // per sample: rows x ns
    spatial::SpatialState st, assembly;
    for (int sample = 0; sample < kPivotSamples; ++sample) {
      solver.solve(sweep.t0 + (sweep.t1 - sweep.t0) * sample / kPivotSamples, st);
      if (sample == 0) assembly = st;
      const GiNaC::exmap num = numeric_values(st, defaults, start);
      std::vector<std::vector<double>> m(rows, std::vector<double>(ns));
      for (size_t r = 0; r < rows; ++r)
        for (size_t i = 0; i < ns; ++i)
          m[r][i] = GiNaC::ex_to<GiNaC::numeric>(
                        network_[r][static_cast<size_t>(g_.secondary[i])].subs(num).evalf())
                        .to_double();
      a.push_back(m);
    }
    std::vector<bool> used(rows, false), done(ns, false);
    double det = 1, worst = 1;
    for (size_t k = 0; k < ns; ++k) {
      // Complete pivoting fixed over the samples: the (row, column) whose entry is largest
      // against the remaining block's largest in its worst sample.
      size_t best = rows, column = ns;
      double value = 0;
      std::vector<double> largest;
      for (const auto& m : a) {
        double l = 0;
        for (size_t r = 0; r < rows; ++r)
          for (size_t i = 0; i < ns; ++i)
            if (!used[r] && !done[i]) l = std::max(l, std::abs(m[r][i]));
        largest.push_back(l);
      }
      for (size_t r = 0; r < rows; ++r)
        for (size_t i = 0; i < ns; ++i) {
          if (used[r] || done[i]) continue;
          double ratio = 1;
          for (size_t sample = 0; sample < a.size(); ++sample)
            ratio = std::min(
                ratio, largest[sample] > 0 ? std::abs(a[sample][r][i]) / largest[sample] : 0.0);
          if (ratio > value) best = r, column = i, value = ratio;
        }
      if (best == rows || value <= 1e-6)
        throw std::runtime_error(m_.common.file +
                                 ": error: no pivot order fixed at generation time stays "
                                 "regular over the step (smallest pivot " +
                                 std::to_string(value) + " of its block)");
      used[best] = true;
      done[column] = true;
      worst = std::min(worst, value);
      det *= a[0][best][column];
      pivot_rows_.push_back(best);
      pivot_columns_.push_back(column);
      for (auto& m : a)
        for (size_t r = 0; r < rows; ++r)
          if (!used[r]) {
            const double f = m[r][column] / m[best][column];
            for (size_t i = 0; i < ns; ++i) m[r][i] -= f * m[best][i];
          }
    }
    for (const int c : g_.secondary)
      out_.closure_start.push_back(assembly.q[static_cast<Eigen::Index>(c)]);
    out_.closure_det = det;
    out_.groups.push_back("closure");
    std::string dropped;
    for (size_t r = 0; r < rows; ++r)
      if (!used[r])
        dropped += (dropped.empty() ? "" : ", ") + std::string(r % 6 < 3 ? "w" : "v") +
                   kAxis[r % 3] + " of circuit " + std::to_string(r / 6);
    char ratio[32];
    std::snprintf(ratio, sizeof ratio, "%.2g", worst);
    out_.plan.push_back("closure: " + std::to_string(ns) + " secondary coordinates, " +
                        std::to_string(rows) + " closure rows, pivot order from " +
                        std::to_string(kPivotSamples) + " samples (smallest pivot " + ratio +
                        " of its column)" +
                        (dropped.empty() ? "" : "; redundant rows dropped: " + dropped));
  }

  // Every parameter, coordinate and definition from `start` on at the numeric pose st.
  GiNaC::exmap numeric_values(const spatial::SpatialState& st, const std::vector<double>& defaults,
                              size_t start) const {
    GiNaC::exmap num;
    for (size_t i = 0; i < m_.common.parameters.size(); ++i)
      num[params_.at(m_.common.parameters[i].symbol)] = GiNaC::numeric(defaults[i]);
    for (size_t c = 0; c < cols_.size(); ++c)
      num[cols_[c].q] = GiNaC::numeric(st.q[static_cast<Eigen::Index>(c)]);
    for (size_t k = start; k < out_.definitions.size(); ++k)
      num[out_.definitions[k].first] = out_.definitions[k].second.subs(num).evalf();
    return num;
  }

  // The closed-form pre-pass (spatial_closed_form.hpp): its groups when they define every
  // secondary coordinate, else none (the Newton-Raphson closure then takes them all).
  std::vector<ClosedFormGroup> closed_form(size_t start) {
    const std::vector<double> defaults = m_.common.default_parameters();
    const spatial::SpatialSolver solver(m_, defaults);
    spatial::SpatialState st;
    solver.solve(spatial::default_spatial_sweep(m_, defaults).t0, st);
    ClosureContext ctx{m_, g_, {}, {}, {}, D_, {}, numeric_values(st, defaults, start), {}};
    for (size_t c = 0; c < cols_.size(); ++c) {
      ctx.axes.push_back(cols_[c].axis);
      ctx.q.push_back(cols_[c].q);
      ctx.assembly_q.push_back(st.q[static_cast<Eigen::Index>(c)]);
      ctx.known.push_back(g_.columns[c].driver >= 0);
    }
    ctx.warm.assign(cols_.size(), 0);
    for (size_t i = 0; i < g_.secondary.size(); ++i) {
      const symbol w("s.closure.q[" + std::to_string(i) + "]");
      ctx.warm[static_cast<size_t>(g_.secondary[i])] = w;
      ctx.assembly[w] = ctx.assembly_q[static_cast<size_t>(g_.secondary[i])];
    }
    std::vector<ClosedFormGroup> groups = closed_form_groups(ctx);
    for (const int c : g_.secondary)
      if (!ctx.known[static_cast<size_t>(c)]) return {};
    for (const ClosedFormGroup& group : groups) {
      out_.groups.push_back(group.name);
      out_.plan.push_back(group.plan);
    }
    return groups;
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

  // Unknown k of the elimination is secondary coordinate pivot_columns_[k].
  std::vector<ex> unpermute(const std::vector<ex>& x) const {
    std::vector<ex> y(x.size());
    for (size_t k = 0; k < x.size(); ++k) y[pivot_columns_[k]] = x[k];
    return y;
  }
  std::vector<std::vector<ex>> secondary_matrix(const GiNaC::exmap& subs) const {
    std::vector<std::vector<ex>> a;
    for (const size_t r : pivot_rows_) {
      std::vector<ex> row;
      for (const size_t i : pivot_columns_)
        row.push_back(network_[r][static_cast<size_t>(g_.secondary[i])].subs(subs));
      a.push_back(row);
    }
    return a;
  }

  // Positions of the secondary coordinates: kNewtonSteps unrolled Newton-Raphson steps on the
  // closure error from the State's warm start, each on a renamed copy of the position
  // definitions that depend on the secondary coordinates; then the definitions themselves at the
  // result.
  static constexpr int kNewtonSteps = 5;
  void close_positions(size_t start) {
    circuit_rows();
    // Before the pivot choice: the groups' names precede the "closure" group.
    const std::vector<ClosedFormGroup> groups = closed_form(start);
    choose_pivots(start);
    std::vector<std::pair<symbol, ex>> chain(
        out_.definitions.begin() + static_cast<std::ptrdiff_t>(start), out_.definitions.end());
    out_.definitions.resize(start);
    std::set<ex, GiNaC::ex_is_less> moving;
    for (const int c : g_.secondary) moving.insert(cols_[static_cast<size_t>(c)].q);
    std::vector<std::pair<symbol, ex>> dependent;
    for (const auto& [sym, value] : chain) {
      bool depends = false;
      for (auto it = value.preorder_begin(); it != value.preorder_end() && !depends; ++it)
        depends = moving.count(*it) > 0;
      if (depends) {
        moving.insert(sym);
        dependent.emplace_back(sym, value);
      } else {
        out_.definitions.emplace_back(sym, value);
      }
    }
    const size_t ns = g_.secondary.size();
    if (!groups.empty()) {
      out_.plan.push_back("closure positions: closed form in " + std::to_string(groups.size()) +
                          " groups, no Newton-Raphson");
      out_.closed_form_groups = static_cast<int>(groups.size());
      std::vector<std::pair<symbol, ex>> items;
      for (size_t k = 0; k < groups.size(); ++k) {
        items.insert(items.end(), groups[k].definitions.begin(), groups[k].definitions.end());
        for (const ex& r : groups[k].reach) {
          output(out_.kinematics,
                 "s.closure.reach[" + std::to_string(out_.reach_group.size()) + "]", r);
          out_.reach_group.push_back(static_cast<int>(out_.groups.size() - groups.size() - 1 + k));
        }
      }
      // The tree's cosines and sines of the coordinates the groups have without trigonometry.
      std::map<ex, ex, GiNaC::ex_is_less> trig;
      for (const ClosedFormGroup& group : groups)
        for (const auto& [c, cs] : group.cos_sin) {
          trig[GiNaC::cos(cols_[static_cast<size_t>(c)].q)] = cs.first;
          trig[GiNaC::sin(cols_[static_cast<size_t>(c)].q)] = cs.second;
        }
      for (const auto& [sym, value] : dependent) {
        const auto it = trig.find(value);
        items.emplace_back(sym, it == trig.end() ? value : it->second);
      }
      emit_in_dependency_order(std::move(items));
      for (size_t i = 0; i < ns; ++i)
        output(out_.kinematics, "s.closure.next[" + std::to_string(i) + "]",
               cols_[static_cast<size_t>(g_.secondary[i])].q);
      closure_residual();
      return;
    }
    out_.plan.push_back("closure positions: " + std::to_string(kNewtonSteps) +
                        " unrolled Newton-Raphson steps from the warm start");
    std::vector<ex> q(ns);
    for (size_t i = 0; i < ns; ++i) q[i] = symbol("s.closure.q[" + std::to_string(i) + "]");
    for (int step = 0; step < kNewtonSteps; ++step) {
      const std::string suffix = "_n" + std::to_string(step);
      GiNaC::exmap subs;
      for (size_t i = 0; i < ns; ++i) subs[cols_[static_cast<size_t>(g_.secondary[i])].q] = q[i];
      for (const auto& [sym, value] : dependent) {
        const symbol copy(sym.get_name() + suffix);
        out_.definitions.emplace_back(copy, value.subs(subs));
        subs[sym] = copy;
      }
      const Lu lu = factor(secondary_matrix(subs), "n" + std::to_string(step) + "_");
      std::vector<ex> rhs;
      for (const size_t r : pivot_rows_) rhs.push_back(-residual_[r].subs(subs));
      const std::vector<ex> dq = unpermute(solve(lu, rhs, "n" + std::to_string(step) + "_"));
      for (size_t i = 0; i < ns; ++i)
        q[i] = named_always("q_" + cols_[static_cast<size_t>(g_.secondary[i])].name + suffix,
                            q[i] + dq[i]);
    }
    for (size_t i = 0; i < ns; ++i) {
      out_.definitions.emplace_back(
          GiNaC::ex_to<symbol>(cols_[static_cast<size_t>(g_.secondary[i])].q), q[i]);
      output(out_.kinematics, "s.closure.next[" + std::to_string(i) + "]",
             cols_[static_cast<size_t>(g_.secondary[i])].q);
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
      lu_ = factor(secondary_matrix({}), "lu_");
      output(out_.kinematics, "s.closure.det", named("closure_det", lu_.det));
      std::vector<ex> rhs;
      for (const size_t r : pivot_rows_) {
        ex b = 0;
        for (const int c : g_.primary)
          b -= network_[r][static_cast<size_t>(c)] * cols_[static_cast<size_t>(c)].qd;
        rhs.push_back(b);
      }
      const std::vector<ex> qd = unpermute(solve(lu_, rhs, "vel_"));
      for (size_t i = 0; i < ns; ++i) {
        Column& col = cols_[static_cast<size_t>(g_.secondary[i])];
        col.qd = named("qd_" + col.name, qd[i]);
      }
      sensitivity_.assign(g_.columns.size(), std::vector<ex>(g_.primary.size(), 0));
      for (size_t k = 0; k < g_.primary.size(); ++k) {
        sensitivity_[static_cast<size_t>(g_.primary[k])][k] = 1;
        std::vector<ex> b;
        for (const size_t r : pivot_rows_)
          b.push_back(-network_[r][static_cast<size_t>(g_.primary[k])]);
        const std::vector<ex> x = unpermute(solve(lu_, b, "sen" + std::to_string(k) + "_"));
        for (size_t i = 0; i < ns; ++i)
          sensitivity_[static_cast<size_t>(g_.secondary[i])][k] = x[i];
      }
      return;
    }
    std::vector<ex> rhs;
    for (const size_t r : pivot_rows_) {
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
    const std::vector<ex> qdd = unpermute(solve(lu_, rhs, "acc_"));
    for (size_t i = 0; i < ns; ++i) {
      Column& col = cols_[static_cast<size_t>(g_.secondary[i])];
      col.qdd = named("qdd_" + col.name, qdd[i]);
    }
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
    for (const SpatialDriver& d : m_.drivers) {
      const Column& col =
          cols_[static_cast<size_t>(g_.joint_column[static_cast<size_t>(d.joint)] + d.column)];
      const std::string o = "s.drivers." + d.name + ".";
      output(out_.kinematics, o + "q", col.q);
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
      if (body.ground || body.is_virtual) continue;
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
      if (m_.bodies[static_cast<size_t>(b)].ground) continue;
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
        if (body.is_virtual) continue;
        for (int r = 0; r < 6; ++r)
          output(out_.jacobians,
                 "s.body_jacobians." + body.name + "[" + std::to_string(r) + "][" +
                     std::to_string(k) + "]",
                 r < 3 ? J[b][k].w[static_cast<size_t>(r)] : J[b][k].v[static_cast<size_t>(r - 3)]);
      }
    }
    for (const auto& [point, b] : m_.named_points()) {
      if (m_.bodies[static_cast<size_t>(b)].ground) continue;
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
  // Jacobian (unique even where the circuits are redundant). The reactions are not generated yet:
  // NaN (`not_generated`, a local of the entry points).
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
      const SpatialDriver& d =
          m_.drivers[static_cast<size_t>(g_.columns[static_cast<size_t>(g_.primary[k])].driver)];
      output(out_.dynamics, "s.drivers." + d.name + ".effort", named("tau_" + d.name, effort[k]));
    }
    const symbol nan("not_generated");
    for (const SpatialJoint& joint : m_.joints)
      if (!joint.is_virtual)
        for (const char* f : {"fx", "fy", "fz", "mx", "my", "mz"})
          output(out_.dynamics, "s.joints." + joint.name + "." + f, nan);
  }

  // Rate of momentum minus gravity of body b, as a wrench about the ground origin.
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
    momentum_[b] = {F, Mo};
    return {F, Mo};
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

  // The wrench the parent applies on its child through joint j: the efforts of its driven
  // coordinates (reciprocal products with their screws) and the remaining reaction.
  void joint_loads(int j, int parent, const Wrench& on_child) {
    const SpatialJoint& joint = m_.joints[static_cast<size_t>(j)];
    // The wrench of the joint's first body on its second.
    const Wrench W = joint.first == parent ? on_child : Wrench{-on_child.f, -on_child.m};
    const V P = named("P_" + joint.name,
                      geometry::apply(D_[static_cast<size_t>(joint.second)],
                                      n_columns(j) == 0 ? named("s0_" + joint.name, vec(joint.s0))
                                                        : cols_[c0_of(j)].axis.s0));
    joint_point_[static_cast<size_t>(j)] = P;
    const auto c0 = static_cast<size_t>(g_.joint_column[static_cast<size_t>(j)]);
    const size_t n = joint.columns.size();
    std::vector<Wrench> unit_effort;  // per coordinate: the wrench of a unit effort
    for (size_t k = 0; k < n; ++k) {
      const Column& col = cols_[c0 + k];
      if (col.axis.kind == geometry::ScrewKind::translation)
        unit_effort.push_back({col.screw.v, geometry::cross(P, col.screw.v)});
      else
        unit_effort.push_back({V{0, 0, 0}, col.screw.w});
    }
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
    for (const SpatialDriver& d : m_.drivers)
      if (d.joint == j)
        output(out_.dynamics, "s.drivers." + d.name + ".effort",
               tau[static_cast<size_t>(d.column)]);
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
      const Wrench w =
          col.axis.kind == geometry::ScrewKind::translation
              ? Wrench{col.screw.v,
                       geometry::cross(joint_point_[static_cast<size_t>(sc.joint)], col.screw.v)}
              : Wrench{V{0, 0, 0}, col.screw.w};
      const int c = 6 * static_cast<int>(m_.joints.size()) + static_cast<int>(k);
      out_.ne_unknowns.push_back(m_.drivers[static_cast<size_t>(sc.driver)].name + ".effort");
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
  SpatialDerivation out_;
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
  std::vector<size_t> pivot_rows_, pivot_columns_;  // elimination order; unknown k is the
                                                    // secondary coordinate pivot_columns_[k]
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
