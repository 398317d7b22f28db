// leg6/simbody: Simbody (3.7, the Debian package) as a peer of leg6/kdl and leg6/generated, on the
// same 256 random samples (bench/spatial_bench.cpp, seed 3). The chain is built from the numeric
// solver's geometry as tests/kdl_model.hpp builds KDL's: every body frame is the ground frame at
// the reference pose, each joint a MobilizedBody::Pin whose F and M frames sit on the joint's
// point s0 with their Z axis along the screw axis s (a pin turns about Z), each body's mass,
// centre of mass and inertia its reference-pose ones. Gravity is a Force::Gravity element, whose
// body forces are handed to the inverse dynamics. Per sample: set Q and U, realize Velocity, the
// foot's station location in ground, its station Jacobian (calcStationJacobian) and the torques
// (calcResidualForceIgnoringConstraints with the gravity forces and the given udot).
//
// Checked before timing against the generated kernel's evaluate() (generated/leg6/leg6.hpp): foot
// position, foot Jacobian and the six torques, each within 1e-9 of the largest entry of that
// quantity in the sample (std::runtime_error otherwise); the largest differences are printed as a
// `sanity` line. Over the 256 samples: foot position within 9.7e-17 m, Jacobian 1.1e-16 m, torques
// 6.9e-17 N m (the largest torque 0.103 N m): the same model to rounding.
//
// rsur/simbody (below, RsurSimbody): the closed RSUR loop, its spherical joint a hard constraint,
// the crank's angle prescribed; checked equal to the generated rsur kernel's crank torque and
// force at jB over the walk of rsur/generated: within 1.6e-17 N m (largest 1.05e-3 N m) and
// 1.3e-15 N (largest 0.137 N).
//
// Built as C++17 without NDEBUG (bench/CMakeLists.txt): Simbody 3.7's headers do not compile as
// C++20, and Debian builds the library without NDEBUG, which changes the layout of its classes
// (StateImpl's cache entries keep debug version counters): a file built with NDEBUG crashes in the
// library. So Simbody is timed as Debian ships it, its internal consistency checks included.
#include <Simbody.h>
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "leg6/leg6.hpp"
#include "rsur/rsur.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"

namespace mechgen::bench {
namespace {

namespace k = gen::leg6;

SimTK::Vec3 vec(const spatial::V3& v) {
  return SimTK::Vec3(v[0], v[1], v[2]);
}

// Body b's mass properties in its Simbody frame, which is the ground frame at the reference pose.
SimTK::MassProperties mass_of(const spatial::SpatialSolver& solver, size_t b) {
  const spatial::SpatialInstance& in = solver.instance();
  const spatial::Pose& frame = in.body_frame[b];
  const spatial::M3 I = frame.R * in.inertia[b] * geometry::transpose(frame.R);
  const SimTK::Vec3 com = vec(geometry::apply(frame, in.com[b]));
  const SimTK::Inertia about_com(I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2));
  return SimTK::MassProperties(in.mass[b], com, about_com.shiftFromMassCenter(com, in.mass[b]));
}

// A tree of pins from a spatial model whose joints are revolutes, in model order (each joint's
// first body placed before it).
struct SimbodyTree {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::GeneralForceSubsystem forces{system};
  SimTK::Force::Gravity gravity;
  std::vector<SimTK::MobilizedBody> body;  // per model body (the ground: matter's Ground)
  SimTK::State state;

  explicit SimbodyTree(const spatial::SpatialSolver& solver) {
    const SpatialModel& m = solver.model();
    const spatial::SpatialInstance& in = solver.instance();
    body.resize(m.bodies.size());
    body[static_cast<size_t>(m.ground)] = matter.updGround();
    for (size_t j = 0; j < m.joints.size(); ++j) {
      const SpatialJoint& joint = m.joints[j];
      if (joint.type != SpatialJointType::revolute)
        throw std::invalid_argument("Simbody tree: revolute joints only");
      const auto& axis =
          in.axes[static_cast<size_t>(solver.graph().joint_column[static_cast<size_t>(j)])];
      const auto b = static_cast<size_t>(joint.second);
      const SimTK::Transform on_axis(SimTK::Rotation(SimTK::UnitVec3(vec(axis.s)), SimTK::ZAxis),
                                     vec(axis.s0));
      body[b] = SimTK::MobilizedBody::Pin(body[static_cast<size_t>(joint.first)], on_axis,
                                          SimTK::Body::Rigid(mass_of(solver, b)), on_axis);
    }
    gravity = SimTK::Force::Gravity(forces, matter, vec(in.gravity));
    state = system.realizeTopology();
  }
};

struct Leg6Simbody {
  SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/leg6.yaml");
  spatial::SpatialSolver solver{model, {}};
  SimbodyTree tree{solver};
  int foot_body = model.body_index("foot_link");
  SimTK::MobilizedBodyIndex foot_index =
      tree.body[static_cast<size_t>(foot_body)].getMobilizedBodyIndex();
  SimTK::Vec3 foot_station =
      vec(geometry::apply(solver.instance().body_frame[static_cast<size_t>(foot_body)],
                          solver.instance().points[static_cast<size_t>(foot_body)][0]));
  std::vector<SimTK::Vector> q, u, udot;  // bench/spatial_bench.cpp's samples (seed 3)
  SimTK::Vec3 x;                          // results of the last sample
  SimTK::Matrix J;
  SimTK::Vector torque, no_mobility_forces;

  Leg6Simbody() {
    if (model.bodies[static_cast<size_t>(foot_body)].points[0].name != "foot")
      throw std::runtime_error("leg6/simbody: the foot is not foot_link's first point");
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> r(-1, 1);
    for (int i = 0; i < 256; ++i) {
      SimTK::Vector a(6), b(6), c(6);
      for (int j = 0; j < 6; ++j) a[j] = 1.5 * r(rng), b[j] = 2 * r(rng), c[j] = 5 * r(rng);
      q.push_back(a), u.push_back(b), udot.push_back(c);
    }
  }
  void sample(size_t i) {
    SimTK::State& s = tree.state;
    s.updQ() = q[i];
    s.updU() = u[i];
    tree.system.realize(s, SimTK::Stage::Velocity);
    x = tree.body[static_cast<size_t>(foot_body)].findStationLocationInGround(s, foot_station);
    tree.matter.calcStationJacobian(s, foot_index, foot_station, J);
    tree.matter.calcResidualForceIgnoringConstraints(
        s, no_mobility_forces, tree.gravity.getBodyForces(s), udot[i], torque);
  }
};

// Largest |a - b| over n entries, and the check against 1e-9 of the reference's largest entry.
double check(const char* what, const double* a, const double* b, int n) {
  double diff = 0, scale = 0;
  for (int i = 0; i < n; ++i)
    diff = std::max(diff, std::abs(a[i] - b[i])), scale = std::max(scale, std::abs(b[i]));
  if (!(diff <= 1e-9 * scale)) {
    char message[160];
    std::snprintf(message, sizeof message,
                  "%s differs from the generated kernel's by %.3g (on %.3g)", what, diff, scale);
    throw std::runtime_error(message);
  }
  return diff;
}

void check_against_kernel(Leg6Simbody& leg) {
  const k::Params<double> params;
  double dx = 0, dj = 0, dt = 0, tmax = 0;
  for (size_t i = 0; i < leg.q.size(); ++i) {
    const SimTK::Vector &q = leg.q[i], &qd = leg.u[i], &qdd = leg.udot[i];
    k::Inputs<double> in;
    in.q1 = q[0], in.q2 = q[1], in.q3 = q[2], in.q4 = q[3], in.q5 = q[4], in.q6 = q[5];
    in.q1_d = qd[0], in.q2_d = qd[1], in.q3_d = qd[2], in.q4_d = qd[3], in.q5_d = qd[4];
    in.q6_d = qd[5];
    in.q1_dd = qdd[0], in.q2_dd = qdd[1], in.q3_dd = qdd[2], in.q4_dd = qdd[3], in.q5_dd = qdd[4];
    in.q6_dd = qdd[5];
    k::State<double> s;
    if (k::evaluate(params, in, s) != k::Status::ok)
      throw std::runtime_error("leg6/simbody: the generated kernel failed");
    leg.sample(i);
    const double x[] = {s.points.foot.x, s.points.foot.y, s.points.foot.z};
    const double effort[] = {s.drivers.q1.effort, s.drivers.q2.effort, s.drivers.q3.effort,
                             s.drivers.q4.effort, s.drivers.q5.effort, s.drivers.q6.effort};
    const double sx[] = {leg.x[0], leg.x[1], leg.x[2]};
    double sj[18];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 6; ++c) sj[6 * r + c] = leg.J(r, c);
    double st[6];
    for (int c = 0; c < 6; ++c) st[c] = leg.torque[c];
    dx = std::max(dx, check("leg6/simbody: foot position", sx, x, 3));
    dj = std::max(dj, check("leg6/simbody: foot Jacobian", sj, &s.point_jacobians.foot[0][0], 18));
    dt = std::max(dt, check("leg6/simbody: torques", st, effort, 6));
    for (const double e : effort) tmax = std::max(tmax, std::abs(e));
  }
  std::fprintf(stderr,
               "sanity leg6/simbody: equals generated over %zu samples: foot position within "
               "%.1e m, Jacobian %.1e m, torques %.1e N m (largest torque %.3g N m)\n",
               leg.q.size(), dx, dj, dt, tmax);
}

namespace r = gen::rsur;

// The rsur kernel's driver law (theta = w t) as a Simbody position-level Motion of the crank.
class CrankLaw : public SimTK::Motion::Custom::Implementation {
 public:
  Implementation* clone() const override { return new CrankLaw(*this); }
  SimTK::Motion::Level getLevel(const SimTK::State&) const override {
    return SimTK::Motion::Position;
  }
  void calcPrescribedPosition(const SimTK::State& s, int, SimTK::Real* q) const override {
    *q = law(s).theta;
  }
  void calcPrescribedPositionDot(const SimTK::State& s, int, SimTK::Real* qd) const override {
    *qd = law(s).theta_d;
  }
  void calcPrescribedPositionDotDot(const SimTK::State& s, int, SimTK::Real* qdd) const override {
    *qdd = law(s).theta_dd;
  }

 private:
  static r::Inputs<double> law(const SimTK::State& s) {
    r::Inputs<double> in;
    r::driver_inputs(r::Params<double>(), s.getTime(), in);
    return in;
  }
};

// rsur/simbody: the RSUR loop in Simbody. Tree: crank (pin jA) and rocker (pin jD) from the
// ground, the coupler on the rocker through the universal jC (Simbody's Universal turns about F's
// x, fixed in the parent, then about M's y, fixed in the child: F's x is s2, the axis the model
// fixes in the rocker, and M's y is s, the one fixed in the coupler, as the exporter's cut link
// has them); the loop cut at the spherical joint jB by a Constraint::Ball (a hard constraint,
// three Lagrange multipliers); the crank's angle prescribed by CrankLaw. Per sample: set the time,
// projectQ (Newton on the ball's three position rows from the previous sample, the crank's q
// prescribed), projectU, realize Acceleration (constrained forward dynamics with prescribed
// motion); the outputs are the crank's prescribed-motion force (getOneTau: the driver's effort)
// and the ball's force on the coupler (the kernel's jB force, first body on second). Simbody gives
// both with the sign of its multipliers (M udot + ~G lambda + tau = f): the forces applied are
// their negatives. Checked once with Simbody alone: its calcResidualForceIgnoringConstraints at
// the realized udot (the generalized forces the constraint and the motion must apply) equals, at
// the rocker's coordinate, the moment about jD of minus getBallReactionForceOnBody2, and is zero
// at the crank's, where minus getOneTau balances that force's moment about jA.
struct RsurSimbody {
  SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/rsur.yaml");
  spatial::SpatialSolver solver{model, {}};
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::GeneralForceSubsystem forces{system};
  SimTK::Force::Gravity gravity;
  SimTK::MobilizedBody crank, rocker, coupler;
  SimTK::Constraint::Ball ball;
  SimTK::State state;
  std::vector<double> times;  // the model's step forth and back, as rsur/generated walks it
  double tolerance = 1e-13;   // projection accuracy (m, m/s): Newton to rounding
  double tau = 0;             // the last sample's outputs
  SimTK::Vec3 ball_force;

  RsurSimbody() {
    const spatial::SpatialInstance& in = solver.instance();
    const auto joint = [&](const char* name) {
      for (size_t j = 0; j < model.joints.size(); ++j)
        if (model.joints[j].name == name) return j;
      throw std::runtime_error(std::string("rsur/simbody: no joint ") + name);
    };
    const auto axis = [&](size_t j, int k) {
      return in.axes[static_cast<size_t>(solver.graph().joint_column[j] + k)];
    };
    const size_t jA = joint("jA"), jB = joint("jB"), jC = joint("jC"), jD = joint("jD");
    const auto pin_frame = [&](size_t j) {
      return SimTK::Transform(SimTK::Rotation(SimTK::UnitVec3(vec(axis(j, 0).s)), SimTK::ZAxis),
                              vec(axis(j, 0).s0));
    };
    const SimTK::Transform cross(SimTK::Rotation(SimTK::UnitVec3(vec(axis(jC, 1).s)), SimTK::XAxis,
                                                 vec(axis(jC, 0).s), SimTK::YAxis),
                                 vec(axis(jC, 0).s0));
    crank = SimTK::MobilizedBody::Pin(matter.updGround(), pin_frame(jA),
                                      SimTK::Body::Rigid(mass_of(solver, 1)), pin_frame(jA));
    rocker = SimTK::MobilizedBody::Pin(matter.updGround(), pin_frame(jD),
                                       SimTK::Body::Rigid(mass_of(solver, 3)), pin_frame(jD));
    coupler = SimTK::MobilizedBody::Universal(rocker, cross, SimTK::Body::Rigid(mass_of(solver, 2)),
                                              cross);
    const SimTK::Vec3 B = vec(in.joint_point[jB]);
    ball = SimTK::Constraint::Ball(crank, B, coupler, B);
    SimTK::Motion::Custom(crank, new CrankLaw);
    gravity = SimTK::Force::Gravity(forces, matter, vec(in.gravity));
    if (model.bodies[1].name != "crank" || model.bodies[2].name != "coupler" ||
        model.bodies[3].name != "rocker" ||
        std::abs(SimTK::dot(vec(axis(jC, 0).s), vec(axis(jC, 1).s))) > 1e-15)
      throw std::runtime_error("rsur/simbody: not the RSUR of models/rsur.yaml");
    state = system.realizeTopology();
    const spatial::SpatialSweepOptions step = spatial::default_spatial_sweep(model);
    for (int i = 0; i < step.samples; ++i)
      times.push_back(step.t0 + (step.t1 - step.t0) * i / (step.samples - 1));
    for (int i = step.samples - 2; i > 0; --i) times.push_back(times[static_cast<size_t>(i)]);
  }
  void sample(size_t i) {
    state.setTime(times[i]);
    system.projectQ(state, tolerance);
    system.projectU(state, tolerance);
    system.realize(state, SimTK::Stage::Acceleration);
    tau = -crank.getOneTau(state, SimTK::MobilizerUIndex(0));
    ball_force = -(coupler.getBodyRotation(state) * ball.getBallReactionForceOnBody2(state));
  }
};

// The crank torque and the force at jB along the walk, each within 1e-9 of its largest value over
// the walk (both pass through zero).
void check_rsur(RsurSimbody& rsur) {
  const r::Params<double> params;
  std::vector<std::array<double, 4>> kernel, simbody;  // torque, force at jB
  for (size_t i = 0; i < rsur.times.size(); ++i) {
    r::Inputs<double> in;
    r::driver_inputs(params, rsur.times[i], in);
    r::State<double> s;
    if (r::evaluate(params, in, s) != r::Status::ok)
      throw std::runtime_error("rsur/simbody: the generated kernel failed");
    rsur.sample(i);
    kernel.push_back({s.drivers.theta.effort, s.joints.jB.fx, s.joints.jB.fy, s.joints.jB.fz});
    simbody.push_back({rsur.tau, rsur.ball_force[0], rsur.ball_force[1], rsur.ball_force[2]});
  }
  double dt = 0, df = 0, tmax = 0, fmax = 0;
  for (size_t i = 0; i < kernel.size(); ++i) {
    dt = std::max(dt, std::abs(kernel[i][0] - simbody[i][0]));
    tmax = std::max(tmax, std::abs(kernel[i][0]));
    for (size_t c = 1; c < 4; ++c)
      df = std::max(df, std::abs(kernel[i][c] - simbody[i][c])),
      fmax = std::max(fmax, std::abs(kernel[i][c]));
  }
  std::fprintf(stderr,
               "sanity rsur/simbody: equals generated over %zu samples: crank torque within %.1e "
               "N m (largest %.3g N m), force at jB within %.1e N (largest %.3g N)\n",
               kernel.size(), dt, tmax, df, fmax);
  if (!(dt <= 1e-9 * tmax && df <= 1e-9 * fmax))
    throw std::runtime_error("rsur/simbody: crank torque or jB force differ from the generated");
}

[[maybe_unused]] const bool registered = [] {
  auto leg = std::make_shared<Leg6Simbody>();
  check_against_kernel(*leg);
  benchmark::RegisterBenchmark("leg6/simbody", [leg](benchmark::State& state) {
    size_t i = 0;
    for (auto _ : state) {
      leg->sample(i);
      benchmark::DoNotOptimize(&leg->x);
      benchmark::DoNotOptimize(&leg->J(0, 0));
      benchmark::DoNotOptimize(&leg->torque[0]);
      i = (i + 1) % leg->q.size();
    }
  })->Unit(benchmark::kNanosecond);
  auto rsur = std::make_shared<RsurSimbody>();
  check_rsur(*rsur);
  benchmark::RegisterBenchmark("rsur/simbody", [rsur](benchmark::State& state) {
    size_t i = 0;
    for (auto _ : state) {
      rsur->sample(i);
      benchmark::DoNotOptimize(&rsur->tau);
      benchmark::DoNotOptimize(&rsur->ball_force);
      i = (i + 1) % rsur->times.size();
    }
  })->Unit(benchmark::kNanosecond);
  return true;
}();

}  // namespace
}  // namespace mechgen::bench
