// The generated single-support kernels of the Bioloid (issue 13 item 2; model/support_model.hpp,
// spatial/support_kernel.hpp): along the walking gait, both supports, the generated joint torques
// and floor wrench equal the numeric tree dynamics (floating_base.hpp); the floor wrench equals
// the momentum rate of all bodies minus gravity summed from the kernel's own body outputs; the
// exact ZMP from the kernel equals the numeric one; the placement's heading turns the floor force
// and leaves the torques; an edited description or another support gets another fingerprint.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include "model/support_model.hpp"
#include "ondemand/kernel_resolver.hpp"
#include "spatial/floating_base.hpp"
#include "spatial/humanoid_gait.hpp"
#include "spatial/spatial_mass_matrix.hpp"
#include "spatial/support_kernel.hpp"

namespace mechgen::spatial {
namespace {

struct Walk {
  SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/bioloid.yaml");
  SpatialSolver solver{model, {}};
  HumanoidGait gait{solver, gait_settings(solver)};
  std::vector<double> times(int per_step) const {
    std::vector<double> t;
    const double T = gait.settings().step_time;
    for (int k = 0; k < gait.settings().steps; ++k)
      for (int i = 0; i < per_step; ++i) t.push_back(k * T + T * (i + 0.5) / per_step);
    return t;
  }
  int foot(int side) const {
    return model.pose_drivers[static_cast<size_t>(gait.foot_driver(side))].second;
  }
  const std::string& name(int side) const {
    return model.bodies[static_cast<size_t>(foot(side))].name;
  }
};

double largest(const V3& a, const V3& b) {
  return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
}

TEST(SupportKernel, BothFeetAreCompiledInAndCurrent) {
  const Walk w;
  for (int side = 0; side < 2; ++side) {
    const SpatialModel welded = weld_support(w.model, w.name(side));
    EXPECT_EQ(welded.common.name, "bioloid_support_" + w.name(side));
    EXPECT_NE(ondemand::current_compiled_kernel(welded), nullptr) << welded.common.name;
    // Every real joint driven, one weld, no virtual chain.
    EXPECT_EQ(welded.drivers.size(), 24u);
    EXPECT_TRUE(welded.pose_drivers.empty());
  }
}

TEST(SupportKernel, TorquesFloorWrenchAndZmpEqualTheNumericTreeDynamicsAlongTheGait) {
  const Walk w;
  std::vector<SpatialModel> welded;
  std::vector<SupportKernel> kernels;
  welded.reserve(2);
  for (int side = 0; side < 2; ++side) {
    welded.push_back(weld_support(w.model, w.name(side)));
    kernels.emplace_back(w.solver, welded.back(), w.foot(side),
                         ondemand::kernel_for(welded.back(), w.name(side)));
  }
  SpatialState s;
  double worst_tau = 0, worst_f = 0, worst_m = 0, worst_zmp = 0, largest_tau = 0;
  int samples[2] = {0, 0};
  for (const double t : w.times(8)) {
    w.gait.solve(t, s);
    const int side = w.gait.support(t);
    ++samples[side];
    const FloatingBaseLoads numeric = single_support_dynamics(w.solver, s, w.foot(side));
    const SupportKernelLoads generated = kernels[static_cast<size_t>(side)].loads(s);
    ASSERT_EQ(generated.torque.size(), numeric.torque.size());
    for (size_t j = 0; j < numeric.torque.size(); ++j) {
      worst_tau = std::max(worst_tau, std::abs(generated.torque[j] - numeric.torque[j]));
      largest_tau = std::max(largest_tau, std::abs(numeric.torque[j]));
    }
    worst_f = std::max(worst_f, largest(generated.floor.f, numeric.floor.f));
    worst_m = std::max(worst_m, largest(generated.floor.m, numeric.floor.m));
    const V3 a = zmp_of(generated.floor), b = zmp_of(numeric.floor);
    worst_zmp = std::max({worst_zmp, std::abs(a[0] - b[0]), std::abs(a[1] - b[1])});
  }
  EXPECT_GT(samples[0], 0);
  EXPECT_GT(samples[1], 0);
  std::cout << "generated - numeric over " << samples[0] + samples[1] << " samples: torques "
            << worst_tau << " N m (largest torque " << largest_tau << "), floor force " << worst_f
            << " N, moment " << worst_m << " N m, ZMP " << worst_zmp << " m\n";
  EXPECT_GT(largest_tau, 0.05);  // the comparison is not of zeros
  EXPECT_LT(worst_tau, 1e-9);
  EXPECT_LT(worst_f, 1e-9);
  EXPECT_LT(worst_m, 1e-9);
  EXPECT_LT(worst_zmp, 1e-9);
}

// The kernel's row at a gait state, its placement and its welded model's numeric instance.
struct KernelRow {
  std::vector<double> row;
  std::vector<std::string> names;
  double at(const std::string& column) const {
    for (size_t c = 0; c < names.size(); ++c)
      if (names[c] == column) return row[c];
    ADD_FAILURE() << "no column " << column;
    return 0;
  }
};

KernelRow kernel_row(const Walk& w, const SpatialModel& welded, const CompiledKernel& kernel,
                     const SpatialState& s, const double placement[4]) {
  std::vector<double> params = w.solver.parameters();
  params.insert(params.end(), placement, placement + 4);
  std::vector<double> drivers;
  for (const SpatialDriver& d : welded.drivers) {
    const int j = w.model.joint_index(welded.joints[static_cast<size_t>(d.joint)].name);
    const int c = w.solver.graph().joint_column[static_cast<size_t>(j)] + d.column;
    drivers.insert(drivers.end(), {s.q[c], s.qd[c], s.qdd[c]});
  }
  KernelRow out;
  out.row.resize(static_cast<size_t>(kernel.column_count));
  for (int c = 0; c < kernel.column_count; ++c) out.names.push_back(kernel.column_names[c]);
  int group = -1;
  EXPECT_EQ(
      kernel.evaluate_driven_double(params.data(), s.t, drivers.data(), out.row.data(), &group), 0);
  return out;
}

TEST(SupportKernel, FloorWrenchIsTheMomentumRateOfAllBodiesMinusGravity) {
  const Walk w;
  SpatialState s;
  double worst_f = 0, worst_m = 0;
  std::vector<SpatialModel> welded;
  for (int side = 0; side < 2; ++side) welded.push_back(weld_support(w.model, w.name(side)));
  int samples[2] = {0, 0};
  // In time order: the whole-body solve starts from the previous sample.
  for (const double t : w.times(3)) {
    w.gait.solve(t, s);
    const int side = w.gait.support(t);
    ++samples[side];
    const CompiledKernel& kernel = ondemand::kernel_for(welded[side], w.name(side));
    const std::string weld = support_weld_name(w.name(side));
    // Placed away from the origin and turned: the wrench balance holds in any placement.
    const double placement[4] = {0.3, -0.2, 0.0, 0.7};
    const KernelRow r = kernel_row(w, welded[side], kernel, s, placement);
    std::vector<double> params = w.solver.parameters();
    params.insert(params.end(), placement, placement + 4);
    const SpatialSolver placed(welded[side], params);
    const SpatialInstance& in = placed.instance();
    V3 f{0, 0, 0}, m{0, 0, 0};
    for (size_t b = 0; b < welded[side].bodies.size(); ++b) {
      if (welded[side].bodies[b].ground) continue;
      const std::string& n = welded[side].bodies[b].name;
      const V3 c{r.at(n + ".x"), r.at(n + ".y"), r.at(n + ".z")};
      const V3 a{r.at(n + ".ax"), r.at(n + ".ay"), r.at(n + ".az")};
      const V3 om{r.at(n + ".wx"), r.at(n + ".wy"), r.at(n + ".wz")};
      const V3 al{r.at(n + ".alx"), r.at(n + ".aly"), r.at(n + ".alz")};
      const double qw = r.at(n + ".qw"), qx = r.at(n + ".qx"), qy = r.at(n + ".qy"),
                   qz = r.at(n + ".qz");
      M3 R;
      R.m = {1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qw * qz),     2 * (qx * qz + qw * qy),
             2 * (qx * qy + qw * qz),     1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qw * qx),
             2 * (qx * qz - qw * qy),     2 * (qy * qz + qw * qx),     1 - 2 * (qx * qx + qy * qy)};
      const M3 I = R * in.inertia[b] * geometry::transpose(R);
      const V3 F = in.mass[b] * (a - in.gravity);
      f = f + F;
      m = m + I * al + geometry::cross(om, I * om) + geometry::cross(c, F);
    }
    const V3 floor_f{r.at(weld + ".fx"), r.at(weld + ".fy"), r.at(weld + ".fz")};
    const V3 floor_m = V3{r.at(weld + ".mx"), r.at(weld + ".my"), r.at(weld + ".mz")} +
                       geometry::cross(V3{placement[0], placement[1], placement[2]}, floor_f);
    worst_f = std::max(worst_f, largest(floor_f, f));
    worst_m = std::max(worst_m, largest(floor_m, m));
  }
  std::cout << "floor wrench - momentum rate of all bodies: force " << worst_f << " N, moment "
            << worst_m << " N m\n";
  EXPECT_GT(samples[0], 0);
  EXPECT_GT(samples[1], 0);
  EXPECT_LT(worst_f, 1e-10);
  EXPECT_LT(worst_m, 1e-10);
}

TEST(SupportKernel, TheHeadingTurnsTheFloorWrenchAndLeavesTheTorques) {
  const Walk w;
  const SpatialModel welded = weld_support(w.model, w.name(0));
  const CompiledKernel& kernel = ondemand::kernel_for(welded, w.name(0));
  const std::string weld = support_weld_name(w.name(0));
  SpatialState s;
  w.gait.solve(0.3 * w.gait.settings().step_time, s);
  ASSERT_EQ(w.gait.support(s.t), 0);
  const double psi = 1.1, c = std::cos(psi), sn = std::sin(psi);
  const double straight[4] = {0.0, -0.037, 0.0, 0.0}, turned[4] = {0.5, 0.25, 0.0, psi};
  const KernelRow a = kernel_row(w, welded, kernel, s, straight);
  const KernelRow b = kernel_row(w, welded, kernel, s, turned);
  double worst_tau = 0, worst_w = 0;
  for (const SpatialDriver& d : welded.drivers)
    worst_tau = std::max(worst_tau, std::abs(a.at(d.name + ".effort") - b.at(d.name + ".effort")));
  for (const char* k : {"f", "m"}) {
    const std::string x = weld + "." + k + "x", y = weld + "." + k + "y", z = weld + "." + k + "z";
    worst_w =
        std::max({worst_w, std::abs(c * a.at(x) - sn * a.at(y) - b.at(x)),
                  std::abs(sn * a.at(x) + c * a.at(y) - b.at(y)), std::abs(a.at(z) - b.at(z))});
  }
  std::cout << "turned by " << psi << " rad: torques " << worst_tau << " N m, wrench " << worst_w
            << "\n";
  EXPECT_GT(std::abs(a.at(weld + ".fx")) + std::abs(a.at(weld + ".mx")), 1e-3);
  EXPECT_LT(worst_tau, 1e-10);
  EXPECT_LT(worst_w, 1e-10);
  // The placement puts the foot's point where it says.
  EXPECT_NEAR(b.at("RF.x"), 0.5, 1e-12);
  EXPECT_NEAR(b.at("RF.y"), 0.25, 1e-12);
}

// Issue 22 item 3: the welded-foot models' mass matrix and bias from the kernels' mass_bias entry
// equal the reference solver's on the same welded tree (its own way: unit accelerations through
// its Newton-Euler solve), at gait states of both supports, placed and turned on the floor.
TEST(SupportKernel, MassMatrixAndBiasEqualTheNumericTreeAlongTheGait) {
  const Walk w;
  double worst_m = 0, worst_h = 0, largest_m = 0, largest_h = 0;
  for (int side = 0; side < 2; ++side) {
    const SpatialModel welded = weld_support(w.model, w.name(side));
    const CompiledKernel& kernel = ondemand::kernel_for(welded, w.name(side));
    ASSERT_NE(kernel.mass_bias_double, nullptr);
    const double placement[4] = {0.3, -0.2, 0.0, 0.7};
    std::vector<double> params = w.solver.parameters();
    params.insert(params.end(), placement, placement + 4);
    const SpatialSolver tree(welded, params);
    const SpatialGraph& g = tree.graph();
    const size_t n = welded.drivers.size();
    ASSERT_EQ(g.primary.size(), n);
    for (const double t : w.times(3)) {
      SpatialState s;
      w.gait.solve(t, s);
      // The real joints' motion, per kernel driver (model order) and per tree primary column.
      std::vector<double> drivers;
      Eigen::VectorXd q(static_cast<Eigen::Index>(n)), qd(q.size()), qdd(q.size());
      std::vector<size_t> driver_of(n);
      for (size_t k = 0; k < n; ++k) {
        const SpatialColumn& column = g.columns[static_cast<size_t>(g.primary[k])];
        driver_of[k] = static_cast<size_t>(column.driver);
      }
      for (size_t d = 0; d < n; ++d) {
        const SpatialDriver& driver = welded.drivers[d];
        const int j = w.model.joint_index(welded.joints[static_cast<size_t>(driver.joint)].name);
        const int c = w.solver.graph().joint_column[static_cast<size_t>(j)] + driver.column;
        drivers.insert(drivers.end(), {s.q[c], s.qd[c], s.qdd[c]});
      }
      for (size_t k = 0; k < n; ++k) {
        const auto e = static_cast<Eigen::Index>(k);
        q[e] = drivers[3 * driver_of[k]], qd[e] = drivers[3 * driver_of[k] + 1];
        qdd[e] = drivers[3 * driver_of[k] + 2];
      }
      SpatialState placed;
      tree.solve(t, q, qd, qdd, placed);
      const MassBias numeric = mass_matrix_bias(tree, placed, qd);
      std::vector<double> M(n * n), h(n);
      int group = -1;
      ASSERT_EQ(
          kernel.mass_bias_double(params.data(), t, drivers.data(), M.data(), h.data(), &group), 0)
          << w.name(side) << " at t = " << t;
      for (size_t a = 0; a < n; ++a) {
        const auto ea = static_cast<Eigen::Index>(a);
        largest_h = std::max(largest_h, std::abs(numeric.h[ea]));
        worst_h = std::max(worst_h, std::abs(h[driver_of[a]] - numeric.h[ea]));
        for (size_t b = 0; b < n; ++b) {
          const double expected = numeric.M(ea, static_cast<Eigen::Index>(b));
          largest_m = std::max(largest_m, std::abs(expected));
          worst_m = std::max(worst_m, std::abs(M[driver_of[a] * n + driver_of[b]] - expected));
        }
      }
    }
  }
  std::cout << "support kernels' M " << worst_m << " of " << largest_m << " kg m^2, h " << worst_h
            << " of " << largest_h << " N m\n";
  EXPECT_GT(largest_m, 1e-4);
  EXPECT_GT(largest_h, 1e-2);
  EXPECT_LT(worst_m, 1e-11 * largest_m);
  EXPECT_LT(worst_h, 1e-11 * largest_h);
}

std::string bioloid_text() {
  std::ifstream in(MECHGEN_SOURCE_DIR "/models/bioloid.yaml");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(SupportKernel, AnEditedDescriptionOrAnotherSupportGetsAnotherFingerprint) {
  const std::string text = bioloid_text();
  const SpatialModel model = read_spatial_model_text(text, "models/bioloid.yaml");
  std::string edited_text = text;
  const std::string from = "m_foot: {value: 0.06,", to = "m_foot: {value: 0.061,";
  ASSERT_NE(edited_text.find(from), std::string::npos);
  edited_text.replace(edited_text.find(from), from.size(), to);
  const SpatialModel edited = read_spatial_model_text(edited_text, "models/bioloid.yaml");
  const auto right = ondemand::expected_fingerprint(weld_support(model, "r_foot"));
  EXPECT_NE(right, ondemand::expected_fingerprint(weld_support(edited, "r_foot")));
  EXPECT_NE(right, ondemand::expected_fingerprint(weld_support(model, "l_foot")));
  EXPECT_NE(right, ondemand::expected_fingerprint(model));
  // The compiled-in kernel is current for the description as shipped, never for the edited one.
  EXPECT_NE(ondemand::current_compiled_kernel(weld_support(model, "r_foot")), nullptr);
  EXPECT_EQ(ondemand::current_compiled_kernel(weld_support(edited, "r_foot")), nullptr);
}

TEST(SupportKernel, BadSupportsAreNamedErrors) {
  const SpatialModel model = read_spatial_model(MECHGEN_SOURCE_DIR "/models/bioloid.yaml");
  for (const char* body : {"world", "nowhere", "r_calf"}) {
    try {
      weld_support(model, body);
      ADD_FAILURE() << body << " was accepted";
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find("bioloid.yaml: error: support '" + std::string(body)),
                std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace mechgen::spatial
