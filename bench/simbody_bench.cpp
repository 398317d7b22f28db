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
#include "spatial/spatial_solver.hpp"

namespace mechgen::bench {
namespace {

namespace k = gen::leg6;

SimTK::Vec3 vec(const spatial::V3& v) {
  return SimTK::Vec3(v[0], v[1], v[2]);
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
      const spatial::Pose& frame = in.body_frame[b];
      const spatial::M3 I = frame.R * in.inertia[b] * geometry::transpose(frame.R);
      const SimTK::Vec3 com = vec(geometry::apply(frame, in.com[b]));
      const SimTK::Inertia about_com(I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2));
      const SimTK::MassProperties mass(in.mass[b], com,
                                       about_com.shiftFromMassCenter(com, in.mass[b]));
      const SimTK::Transform on_axis(SimTK::Rotation(SimTK::UnitVec3(vec(axis.s)), SimTK::ZAxis),
                                     vec(axis.s0));
      body[b] = SimTK::MobilizedBody::Pin(body[static_cast<size_t>(joint.first)], on_axis,
                                          SimTK::Body::Rigid(mass), on_axis);
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
  if (!(diff <= 1e-9 * scale))
    throw std::runtime_error(std::string("leg6/simbody: ") + what +
                             " differs from the generated kernel's by " + std::to_string(diff));
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
    dx = std::max(dx, check("foot position", sx, x, 3));
    dj = std::max(dj, check("foot Jacobian", sj, &s.point_jacobians.foot[0][0], 18));
    dt = std::max(dt, check("torques", st, effort, 6));
    for (const double e : effort) tmax = std::max(tmax, std::abs(e));
  }
  std::fprintf(stderr,
               "sanity leg6/simbody: equals generated over %zu samples: foot position within "
               "%.1e m, Jacobian %.1e m, torques %.1e N m (largest torque %.3g N m)\n",
               leg.q.size(), dx, dj, dt, tmax);
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
  return true;
}();

}  // namespace
}  // namespace mechgen::bench
