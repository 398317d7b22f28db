// leg6/mujoco: MuJoCo (2.2, the Debian package) as a peer of leg6/kdl and leg6/generated, on the
// same 256 random samples (bench/spatial_bench.cpp, seed 3). The MJCF is the project's own export
// (import::export_mjcf, what `mechgen export models/leg6.yaml --mjcf OUT.xml` writes), compiled by
// mj_loadXML from a memory file (mjVFS): no file is written. Per sample: mj_kinematics (poses and
// sites), mj_comPos (the degrees of freedom's motion axes), mj_comVel (their velocities: mj_rne
// takes the velocity products from there), mj_jac (the foot site's translational Jacobian) and
// mj_rne with qacc set (M qacc + bias forces with gravity: the inverse dynamics torques).
//
// Checked before timing against the generated kernel's evaluate() (generated/leg6/leg6.hpp): foot
// position, foot Jacobian and the six torques, each within 1e-9 of the largest entry of that
// quantity in the sample (std::runtime_error otherwise); the largest differences are printed as a
// `sanity` line. leg6 has no massless body (the exporter's 1e-10 kg stand-in for one does not
// occur here) and no armature, damping or contact, so the two are the same rigid-body model. Over
// the 256 samples: foot position within 1.9e-16 m, Jacobian 1.9e-16 m, torques 7.0e-12 N m (the
// largest torque 0.103 N m: 7e-11 relative). The torques' 7e-12 is MuJoCo's, not rounding: its
// compiler diagonalises each fullinertia (body_inertia, body_iquat) by iterations that stop near
// 1e-7 relative (ankle_link's products of inertia, 1e-7 kg m^2, come back 2e-13 off).
#include <benchmark/benchmark.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "import/model_export.hpp"
#include "leg6/leg6.hpp"

namespace mechgen::bench {
namespace {

namespace k = gen::leg6;

using ModelPtr = std::unique_ptr<mjModel, void (*)(mjModel*)>;
using DataPtr = std::unique_ptr<mjData, void (*)(mjData*)>;

// The exported MJCF of models/NAME.yaml, compiled by MuJoCo.
ModelPtr load_exported(const std::string& name) {
  const std::string path = std::string(MECHGEN_SOURCE_DIR) + "/models/" + name + ".yaml";
  const std::string xml = import::export_mjcf(read_spatial_model(path), path);
  const std::string file = name + ".xml";
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  if (mj_makeEmptyFileVFS(&vfs, file.c_str(), static_cast<int>(xml.size())) != 0)
    throw std::runtime_error(name + ": MuJoCo's memory file system refused the MJCF");
  std::memcpy(vfs.filedata[vfs.nfile - 1], xml.data(), xml.size());
  char error[1000] = "";
  ModelPtr m(mj_loadXML(file.c_str(), &vfs, error, sizeof error), mj_deleteModel);
  mj_deleteVFS(&vfs);
  if (!m) throw std::runtime_error(name + ": mj_loadXML: " + error);
  return m;
}

int id_of(const mjModel* m, int type, const char* name) {
  const int id = mj_name2id(m, type, name);
  if (id < 0) throw std::runtime_error(std::string("MuJoCo model: no ") + name);
  return id;
}

struct Leg6Mujoco {
  ModelPtr m = load_exported("leg6");
  DataPtr d{mj_makeData(m.get()), mj_deleteData};
  int foot = id_of(m.get(), mjOBJ_SITE, "foot");
  int foot_body = m->site_bodyid[foot];
  std::vector<std::array<double, 18>> samples;  // q, qd, qdd of bench/spatial_bench.cpp (seed 3)
  std::vector<double> jacp = std::vector<double>(static_cast<size_t>(3 * m->nv));
  std::vector<double> torque = std::vector<double>(static_cast<size_t>(m->nv));

  Leg6Mujoco() {
    if (m->nq != 6 || m->nv != 6) throw std::runtime_error("leg6/mujoco: not six hinges");
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 256; ++i) {
      std::array<double, 18> s;
      for (size_t j = 0; j < 6; ++j)
        s[j] = 1.5 * u(rng), s[6 + j] = 2 * u(rng), s[12 + j] = 5 * u(rng);
      samples.push_back(s);
    }
  }
  // One sample: the foot's position (d->site_xpos), its Jacobian (jacp, 3 x nv row-major) and the
  // torques (torque).
  void sample(size_t i) {
    const std::array<double, 18>& s = samples[i];
    mjData* data = d.get();
    std::copy(s.begin(), s.begin() + 6, data->qpos);
    std::copy(s.begin() + 6, s.begin() + 12, data->qvel);
    std::copy(s.begin() + 12, s.end(), data->qacc);
    mj_kinematics(m.get(), data);
    mj_comPos(m.get(), data);
    mj_comVel(m.get(), data);
    mj_jac(m.get(), data, jacp.data(), nullptr, data->site_xpos + 3 * foot, foot_body);
    mj_rne(m.get(), data, 1, torque.data());
  }
};

// Largest |a - b| over n entries, and the check against 1e-9 of the reference's largest entry.
double check(const char* what, const double* a, const double* b, int n) {
  double diff = 0, scale = 0;
  for (int i = 0; i < n; ++i)
    diff = std::max(diff, std::abs(a[i] - b[i])), scale = std::max(scale, std::abs(b[i]));
  if (!(diff <= 1e-9 * scale))
    throw std::runtime_error(std::string("leg6/mujoco: ") + what +
                             " differs from the generated kernel's by " + std::to_string(diff));
  return diff;
}

void check_against_kernel(Leg6Mujoco& leg) {
  const k::Params<double> params;
  double dx = 0, dj = 0, dt = 0, tmax = 0;
  for (size_t i = 0; i < leg.samples.size(); ++i) {
    const std::array<double, 18>& v = leg.samples[i];
    k::Inputs<double> in;
    in.q1 = v[0], in.q2 = v[1], in.q3 = v[2], in.q4 = v[3], in.q5 = v[4], in.q6 = v[5];
    in.q1_d = v[6], in.q2_d = v[7], in.q3_d = v[8], in.q4_d = v[9], in.q5_d = v[10];
    in.q6_d = v[11];
    in.q1_dd = v[12], in.q2_dd = v[13], in.q3_dd = v[14], in.q4_dd = v[15], in.q5_dd = v[16];
    in.q6_dd = v[17];
    k::State<double> s;
    if (k::evaluate(params, in, s) != k::Status::ok)
      throw std::runtime_error("leg6/mujoco: the generated kernel failed");
    leg.sample(i);
    const double x[] = {s.points.foot.x, s.points.foot.y, s.points.foot.z};
    const double effort[] = {s.drivers.q1.effort, s.drivers.q2.effort, s.drivers.q3.effort,
                             s.drivers.q4.effort, s.drivers.q5.effort, s.drivers.q6.effort};
    dx = std::max(dx, check("foot position", leg.d->site_xpos + 3 * leg.foot, x, 3));
    dj = std::max(dj, check("foot Jacobian", leg.jacp.data(), &s.point_jacobians.foot[0][0], 18));
    dt = std::max(dt, check("torques", leg.torque.data(), effort, 6));
    for (const double e : effort) tmax = std::max(tmax, std::abs(e));
  }
  std::fprintf(stderr,
               "sanity leg6/mujoco: equals generated over %zu samples: foot position within "
               "%.1e m, Jacobian %.1e m, torques %.1e N m (largest torque %.3g N m)\n",
               leg.samples.size(), dx, dj, dt, tmax);
}

[[maybe_unused]] const bool registered = [] {
  auto leg = std::make_shared<Leg6Mujoco>();
  check_against_kernel(*leg);
  benchmark::RegisterBenchmark("leg6/mujoco", [leg](benchmark::State& state) {
    size_t i = 0;
    for (auto _ : state) {
      leg->sample(i);
      benchmark::DoNotOptimize(leg->d->site_xpos);
      benchmark::DoNotOptimize(leg->jacp.data());
      benchmark::DoNotOptimize(leg->torque.data());
      i = (i + 1) % leg->samples.size();
    }
  })->Unit(benchmark::kNanosecond);
  return true;
}();

}  // namespace
}  // namespace mechgen::bench
