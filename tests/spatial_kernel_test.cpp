// The generated spatial kernel of leg6 (generated/leg6/leg6.hpp) against the numeric reference
// solver (every output, Jacobians and loads included, on random configurations at default and
// changed parameters; every sweep column) and against Orocos KDL (FK, Jacobian, RNE to 1e-12).
#include <gtest/gtest.h>

#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <map>
#include <random>

#include "kdl_model.hpp"
#include "leg6/leg6.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_kernel_sweep.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"

namespace mechgen::spatial {
namespace {

namespace k = gen::leg6;

struct Sample {
  Eigen::VectorXd q, qd, qdd;
};

Sample random_sample(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Sample s{Eigen::VectorXd(6), Eigen::VectorXd(6), Eigen::VectorXd(6)};
  for (int i = 0; i < 6; ++i) s.q[i] = 1.5 * u(rng), s.qd[i] = 2 * u(rng), s.qdd[i] = 5 * u(rng);
  return s;
}

template <class T>
k::Inputs<T> inputs(const Sample& x) {
  k::Inputs<T> in;
  T* q[] = {&in.q1, &in.q2, &in.q3, &in.q4, &in.q5, &in.q6};
  T* qd[] = {&in.q1_d, &in.q2_d, &in.q3_d, &in.q4_d, &in.q5_d, &in.q6_d};
  T* qdd[] = {&in.q1_dd, &in.q2_dd, &in.q3_dd, &in.q4_dd, &in.q5_dd, &in.q6_dd};
  for (int i = 0; i < 6; ++i)
    *q[i] = static_cast<T>(x.q[i]), *qd[i] = static_cast<T>(x.qd[i]),
    *qdd[i] = static_cast<T>(x.qdd[i]);
  return in;
}

template <class T>
k::Params<T> params(const std::vector<double>& values) {
  k::Params<T> p;
  std::vector<T> v(values.begin(), values.end());
  k::set_parameters(p, v.data());
  return p;
}

// Worst relative difference, each quantity against max(|expected|, floor).
struct Worst {
  double floor, value = 0;
  void operator()(double got, double expected) {
    value = std::max(value, std::abs(got - expected) / std::max(std::abs(expected), floor));
  }
  void operator()(const double* got, const V3& expected) {
    for (int i = 0; i < 3; ++i) (*this)(got[i], expected[static_cast<size_t>(i)]);
  }
};

// Every kernel output against the solver at one configuration.
void compare(const SpatialModel& model, const SpatialSolver& solver, const Sample& x,
             Worst& worst) {
  SpatialState s;
  s.q = x.q;
  solver.place(s);
  solver.rates(s, x.qd, x.qdd);
  const SpatialLoads loads = inverse_dynamics(solver, s);
  const SpatialInstance& in = solver.instance();

  k::State<double> out;
  ASSERT_EQ(k::evaluate(params<double>(solver.parameters()), inputs<double>(x), out),
            k::Status::ok);
  const k::BodyState<double>* bodies[] = {&out.bodies.hip_yaw_link, &out.bodies.hip_roll_link,
                                          &out.bodies.thigh,        &out.bodies.calf,
                                          &out.bodies.ankle_link,   &out.bodies.foot_link};
  const double(*jacobians[])[6] = {
      out.body_jacobians.hip_yaw_link, out.body_jacobians.hip_roll_link,
      out.body_jacobians.thigh,        out.body_jacobians.calf,
      out.body_jacobians.ankle_link,   out.body_jacobians.foot_link};
  for (int i = 0; i < 6; ++i) {
    const int b = model.joints[static_cast<size_t>(i)].second;  // the bodies in joint order
    const k::BodyState<double>& o = *bodies[i];
    const auto bi = static_cast<size_t>(b);
    const Pose frame = solver.body_pose(s, b);
    const double c[] = {o.x, o.y, o.z}, v[] = {o.vx, o.vy, o.vz}, a[] = {o.ax, o.ay, o.az};
    const double w[] = {o.wx, o.wy, o.wz}, al[] = {o.alx, o.aly, o.alz};
    worst(c, geometry::apply(frame, in.com[bi]));
    for (size_t e = 0; e < 9; ++e) worst(o.R[e], frame.R.m[e]);
    worst(v, solver.point_velocity(s, b, in.com[bi]));
    worst(a, solver.point_acceleration(s, b, in.com[bi]));
    worst(w, s.V[bi].w);
    worst(al, s.A[bi].w);
    const Eigen::MatrixXd J = solver.body_jacobian(s, b);
    for (int r = 0; r < 6; ++r)
      for (int col = 0; col < 6; ++col) worst(jacobians[i][r][col], J(r, col));
  }
  const int foot = model.body_index("foot_link");
  const V3 foot_point = solver.point_position(s, foot, in.points[static_cast<size_t>(foot)][0]);
  const double p[] = {out.points.foot.x, out.points.foot.y, out.points.foot.z};
  worst(p, foot_point);
  const V3 toe_local = in.points[static_cast<size_t>(foot)][1];
  const double tv[] = {out.points.toe.vx, out.points.toe.vy, out.points.toe.vz};
  const double ta[] = {out.points.toe.ax, out.points.toe.ay, out.points.toe.az};
  worst(tv, solver.point_velocity(s, foot, toe_local));
  worst(ta, solver.point_acceleration(s, foot, toe_local));
  const Eigen::MatrixXd Jp = solver.point_jacobian(s, foot, foot_point);
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 6; ++col) worst(out.point_jacobians.foot[r][col], Jp(r, col));
  const double effort[] = {out.drivers.q1.effort, out.drivers.q2.effort, out.drivers.q3.effort,
                           out.drivers.q4.effort, out.drivers.q5.effort, out.drivers.q6.effort};
  for (int i = 0; i < 6; ++i) worst(effort[i], loads.effort[i]);
  const auto& j = out.joints;
  const double* wrench[] = {&j.hip_yaw.fx, &j.hip_roll.fx,    &j.hip_pitch.fx,
                            &j.knee.fx,    &j.ankle_pitch.fx, &j.ankle_roll.fx};
  for (int i = 0; i < 6; ++i) {
    worst(wrench[i], loads.reaction[static_cast<size_t>(i)].f);
    worst(wrench[i] + 3, loads.reaction[static_cast<size_t>(i)].m);
  }
}

std::vector<double> changed_parameters(const SpatialModel& model) {
  std::vector<double> p = model.common.default_parameters();
  for (size_t i = 0; i < p.size(); ++i) p[i] *= 1.0 + 0.13 * static_cast<double>(i + 1);
  return p;
}

TEST(SpatialKernel, Leg6EqualsTheNumericSolverOnEveryOutput) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/leg6.yaml");
  std::mt19937 rng(3);
  for (const std::vector<double>& parameters :
       {model.common.default_parameters(), changed_parameters(model)}) {
    const SpatialSolver solver(model, parameters);
    Worst worst{1e-6};
    for (int trial = 0; trial < 40; ++trial) compare(model, solver, random_sample(rng), worst);
    EXPECT_LT(worst.value, 1e-9);
    std::cout << "leg6 kernel against the numeric solver, 40 samples: worst relative "
              << worst.value << "\n";
  }
}

// The sweep through the registry's kernel and the numeric sweep: every CSV column.
TEST(SpatialKernel, Leg6SweepColumnsEqualTheNumericSweep) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/leg6.yaml");
  const CompiledKernel* kernel = find_compiled_kernel("leg6");
  ASSERT_NE(kernel, nullptr);
  for (const std::vector<double>& parameters :
       {model.common.default_parameters(), changed_parameters(model)}) {
    SpatialSweepOptions options = default_spatial_sweep(model, parameters);
    options.samples = 31;
    const SpatialSweepResult numeric = run_spatial_sweep(model, options);
    const SpatialSweepResult generated = run_spatial_kernel_sweep(model, options, *kernel);
    ASSERT_EQ(numeric.columns, generated.columns);
    ASSERT_EQ(numeric.rows.size(), generated.rows.size());
    // Relative to each column's largest magnitude over the sweep, at least 1 % of the largest of
    // its kind (the suffix: a reaction moment about the joint's own axis is zero but for
    // rounding), as tests/equivalence_test.cpp does for planar kernels.
    auto kind = [](const std::string& name) { return name.substr(name.rfind('.') + 1); };
    std::map<std::string, double> kind_scale;
    for (const auto& row : numeric.rows)
      for (size_t c = 0; c < numeric.columns.size(); ++c)
        kind_scale[kind(numeric.columns[c])] =
            std::max(kind_scale[kind(numeric.columns[c])], std::abs(row[c]));
    double worst = 0;
    std::string where;
    for (size_t c = 0; c < numeric.columns.size(); ++c) {
      double scale = std::max(1e-300, 0.01 * kind_scale[kind(numeric.columns[c])]);
      for (const auto& row : numeric.rows) scale = std::max(scale, std::abs(row[c]));
      for (size_t r = 0; r < numeric.rows.size(); ++r) {
        const double e = std::abs(generated.rows[r][c] - numeric.rows[r][c]) / scale;
        if (e > worst) worst = e, where = numeric.columns[c];
      }
    }
    EXPECT_LT(worst, 1e-9) << where;
    std::cout << "leg6 sweep, generated against numeric: worst " << worst << " (" << where << ")\n";
  }
}

// The registry's driven entry fed the model's own motion (q, qd, qdd per driver, read from its
// own row) gives its own row, in double and float.
TEST(SpatialKernel, Leg6DrivenEntryFedTheOwnMotionGivesTheOwnRow) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/leg6.yaml");
  const CompiledKernel* kernel = find_compiled_kernel("leg6");
  ASSERT_NE(kernel, nullptr);
  ASSERT_EQ(kernel->driver_count, 6);
  const std::vector<double> parameters = model.common.default_parameters();
  std::vector<double> own(static_cast<size_t>(kernel->column_count)), driven = own, single = own;
  for (const double t : {0.1, 0.4, 0.9}) {
    int group = -1;
    ASSERT_EQ(kernel->evaluate_double(parameters.data(), t, own.data(), &group), 0);
    std::vector<double> drivers;
    for (int d = 0; d < 6; ++d)  // columns 1 + 4 d: q, qd, qdd, effort of driver d
      for (int k = 0; k < 3; ++k) drivers.push_back(own[static_cast<size_t>(1 + 4 * d + k)]);
    ASSERT_EQ(
        kernel->evaluate_driven_double(parameters.data(), t, drivers.data(), driven.data(), &group),
        0);
    EXPECT_EQ(driven, own);
    ASSERT_EQ(kernel->evaluate_float(parameters.data(), t, single.data(), &group), 0);
    for (size_t c = 0; c < own.size(); ++c)
      EXPECT_NEAR(single[c], own[c], 1e-4 * (1 + std::abs(own[c]))) << kernel->column_names[c];
  }
  EXPECT_STREQ(kernel->column_names[1], "q1.q");
  EXPECT_STREQ(kernel->column_names[4], "q1.effort");
}

KDL::JntArray jnt(const Eigen::VectorXd& x) {
  KDL::JntArray a(static_cast<unsigned>(x.size()));
  a.data = x;
  return a;
}

TEST(SpatialKernel, Leg6EqualsKdl) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/leg6.yaml");
  const SpatialSolver solver(model, {});
  const KDL::Chain chain = kdl_model::chain(solver, "foot");
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainJntToJacSolver jac(chain);
  KDL::ChainIdSolver_RNE id(chain, kdl_model::vec(solver.instance().gravity));
  const k::Params<double> p = params<double>(solver.parameters());
  std::mt19937 rng(5);
  double worst_fk = 0, worst_jac = 0, worst_id = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const Sample x = random_sample(rng);
    k::State<double> out;
    ASSERT_EQ(k::evaluate(p, inputs<double>(x), out), k::Status::ok);
    KDL::Frame frame;
    ASSERT_GE(fk.JntToCart(jnt(x.q), frame), 0);
    const double foot[] = {out.points.foot.x, out.points.foot.y, out.points.foot.z};
    for (int i = 0; i < 3; ++i) {
      worst_fk = std::max(worst_fk, std::abs(frame.p(i) - foot[i]));
      for (int c = 0; c < 3; ++c)
        worst_fk = std::max(worst_fk, std::abs(frame.M(i, c) - out.bodies.foot_link.R[3 * i + c]));
    }
    KDL::Jacobian J(6);
    ASSERT_GE(jac.JntToJac(jnt(x.q), J), 0);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 6; ++c) {
        worst_jac = std::max(worst_jac, std::abs(J(r, c) - out.point_jacobians.foot[r][c]));
        worst_jac = std::max(worst_jac, std::abs(J(r + 3, c) - out.body_jacobians.foot_link[r][c]));
      }
    KDL::JntArray torque(6);
    KDL::Wrenches external(chain.getNrOfSegments(), KDL::Wrench::Zero());
    ASSERT_GE(id.CartToJnt(jnt(x.q), jnt(x.qd), jnt(x.qdd), external, torque), 0);
    const double effort[] = {out.drivers.q1.effort, out.drivers.q2.effort, out.drivers.q3.effort,
                             out.drivers.q4.effort, out.drivers.q5.effort, out.drivers.q6.effort};
    for (int i = 0; i < 6; ++i)
      worst_id = std::max(worst_id, std::abs(torque(static_cast<unsigned>(i)) - effort[i]));
  }
  EXPECT_LT(worst_fk, 1e-12);
  EXPECT_LT(worst_jac, 1e-12);
  EXPECT_LT(worst_id, 1e-12);
  std::cout << "leg6 kernel against KDL, 50 samples: FK " << worst_fk << ", Jacobian " << worst_jac
            << ", inverse dynamics " << worst_id << " N m\n";
}

// float: the same code, single precision; kinematics() alone leaves the loads untouched;
// control() gives evaluate()'s points, Jacobians and efforts; ne_system()'s A x = b holds for
// evaluate()'s reactions and efforts.
TEST(SpatialKernel, Leg6FloatAndKinematicsOnly) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/leg6.yaml");
  std::mt19937 rng(9);
  const Sample x = random_sample(rng);
  k::State<double> d;
  k::State<float> f;
  ASSERT_EQ(k::evaluate(params<double>(model.common.default_parameters()), inputs<double>(x), d),
            k::Status::ok);
  ASSERT_EQ(k::evaluate(params<float>(model.common.default_parameters()), inputs<float>(x), f),
            k::Status::ok);
  EXPECT_NEAR(f.points.foot.z, d.points.foot.z, 1e-5);
  EXPECT_NEAR(f.drivers.q4.effort, d.drivers.q4.effort,
              1e-4 * std::abs(d.drivers.q4.effort) + 1e-6);
  k::State<double> kin;
  kin.drivers.q4.effort = 123;
  ASSERT_EQ(
      k::kinematics(params<double>(model.common.default_parameters()), inputs<double>(x), kin),
      k::Status::ok);
  EXPECT_EQ(kin.drivers.q4.effort, 123);
  EXPECT_EQ(kin.points.foot.z, d.points.foot.z);
  // control(): the same points, Jacobians and efforts as evaluate(); structural zeros stay zero.
  k::State<double> c;
  ASSERT_EQ(k::control(params<double>(model.common.default_parameters()), inputs<double>(x), c),
            k::Status::ok);
  for (int r = 0; r < 6; ++r)
    for (int col = 0; col < 6; ++col) {
      EXPECT_NEAR(c.body_jacobians.foot_link[r][col], d.body_jacobians.foot_link[r][col], 1e-14);
      EXPECT_EQ(c.body_jacobians.hip_yaw_link[r][col],
                col == 0 ? d.body_jacobians.hip_yaw_link[r][col] : 0.0);
    }
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 6; ++col)
      EXPECT_NEAR(c.point_jacobians.toe[r][col], d.point_jacobians.toe[r][col], 1e-14);
  EXPECT_NEAR(c.points.toe.x, d.points.toe.x, 1e-15);
  EXPECT_NEAR(c.drivers.q2.effort, d.drivers.q2.effort, 1e-12 * std::abs(d.drivers.q2.effort));
  // ne_system(): the kernel's own reactions and efforts solve A x = b.
  static_assert(k::ne_rows == 42 && k::ne_size == 42);
  std::vector<double> A(k::ne_rows * k::ne_size), b(k::ne_rows), xs;
  ASSERT_EQ(k::ne_system(params<double>(model.common.default_parameters()), inputs<double>(x),
                         A.data(), b.data()),
            k::Status::ok);
  for (const double* w : {&d.joints.hip_yaw.fx, &d.joints.hip_roll.fx, &d.joints.hip_pitch.fx,
                          &d.joints.knee.fx, &d.joints.ankle_pitch.fx, &d.joints.ankle_roll.fx})
    xs.insert(xs.end(), w, w + 6);
  for (const auto* dr :
       {&d.drivers.q1, &d.drivers.q2, &d.drivers.q3, &d.drivers.q4, &d.drivers.q5, &d.drivers.q6})
    xs.push_back(dr->effort);
  double residual = 0, scale = 0;
  for (int r = 0; r < k::ne_rows; ++r) {
    double sum = -b[static_cast<size_t>(r)];
    for (int c = 0; c < k::ne_size; ++c)
      sum += A[static_cast<size_t>(r * k::ne_size + c)] * xs[static_cast<size_t>(c)];
    residual = std::max(residual, std::abs(sum));
    scale = std::max(scale, std::abs(b[static_cast<size_t>(r)]));
  }
  EXPECT_GT(scale, 1e-3);
  EXPECT_LT(residual, 1e-13 * scale);
  EXPECT_STREQ(k::ne_unknowns[0], "hip_yaw.fx");
  Sample bad = x;
  bad.qd[2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(k::evaluate(params<double>(model.common.default_parameters()), inputs<double>(bad), d),
            k::Status::unreachable);
}

}  // namespace
}  // namespace mechgen::spatial
