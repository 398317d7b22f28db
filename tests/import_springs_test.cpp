// mechgen import --springs (issue 21): an MJCF joint with stiffness becomes a passive driver, held
// at its spring's rest by kinematic commands, free under `simulate` with its spring and damping as
// its effort. Checked against MuJoCo's own forward dynamics on a tree (where MuJoCo is exact: no
// soft constraint), against the rigid import on a Cassie-style leg with loops (the same pose and
// motor efforts at the rest), and by the energy balance and the tracking of the active motors
// when the spring moves.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "analysis/simulate.hpp"
#include "import/import_tree.hpp"
#include "import/model_export.hpp"
#include "model/spatial_model.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"

namespace {

using namespace mechgen;
using Eigen::VectorXd;

SpatialModel import_mjcf(const std::string& path, bool springs) {
  // As `mechgen import [--springs]`.
  import::Tree tree = import::read_mjcf(path, springs);
  import::AssemblyReport report;
  import::TreePose pose = import::assemble(tree, report);
  import::hold_free_joints(tree, pose);
  return read_spatial_model_text(import::write_model(import::describe(tree, pose)),
                                 path + (springs ? ".springs.yaml" : ".yaml"));
}

// A hip motor and a sprung, damped knee whose rest (springref) is not qpos0: a tree, so that
// MuJoCo's forward dynamics is exact.
const char* const kSprungPendulum = R"(<mujoco model="sprung_pendulum">
  <compiler angle="radian"/>
  <option gravity="0 0 -9.81"><flag contact="disable"/></option>
  <worldbody>
    <body name="thigh" pos="0 0 1">
      <joint name="hip" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.1 0 -0.4" size="0.02" mass="2"/>
      <body name="shin" pos="0.1 0 -0.4" euler="0.3 0 0.2">
        <joint name="knee" type="hinge" axis="0.2 1 0.1" stiffness="80" damping="1.5"
               springref="0.4"/>
        <geom type="capsule" fromto="0 0 0 -0.05 0.02 -0.35" size="0.015" mass="0.7"/>
      </body>
    </body>
  </worldbody>
  <actuator><motor name="hip_motor" joint="hip"/></actuator>
</mujoco>
)";

TEST(ImportSprings, APassiveSpringAcceleratesAsInMuJoCo) {
  const std::string path = testing::TempDir() + "sprung_pendulum.xml";
  std::ofstream(path) << kSprungPendulum;
  const SpatialModel model = import_mjcf(path, true);
  ASSERT_EQ(model.drivers.size(), 2u);
  const SpatialDriver& spring = model.drivers[1];
  EXPECT_TRUE(spring.passive);
  EXPECT_FALSE(model.drivers[0].passive);
  const std::vector<double> parameters = model.common.default_parameters();
  const std::unique_ptr<sim::Plant> plant = sim::spatial_plant(model, parameters);
  // The motor's effort is 0 (MuJoCo's ctrl = 0); the spring's is its law.
  const sim::EffortFunction effort =
      sim::model_effort_laws(model, parameters, {model.drivers[0].name});

  char error[1000] = "";
  const std::unique_ptr<mjModel, void (*)(mjModel*)> m(
      mj_loadXML(path.c_str(), nullptr, error, sizeof error), mj_deleteModel);
  ASSERT_TRUE(m) << error;
  const std::unique_ptr<mjData, void (*)(mjData*)> data(mj_makeData(m.get()), mj_deleteData);
  double worst = 0;
  // Our knee coordinate is measured from the spring's rest (0.4 rad from qpos0).
  ASSERT_EQ(m->qpos_spring[1], 0.4);
  for (const auto& [q, qd] : std::vector<std::pair<VectorXd, VectorXd>>{
           {VectorXd::Zero(2), VectorXd::Zero(2)},
           {(VectorXd(2) << 0.3, -0.5).finished(), (VectorXd(2) << 1.2, -2.0).finished()},
           {(VectorXd(2) << -0.8, 0.9).finished(), (VectorXd(2) << -0.4, 3.5).finished()}}) {
    numeric::MassBias mb;
    std::string why;
    ASSERT_TRUE(plant->place(0, q, qd, mb, why)) << why;
    VectorXd e, qdd;
    effort(0, q, qd, e);
    ASSERT_TRUE(numeric::forward_accelerations(mb, e, qdd));
    data->qpos[0] = q[0], data->qpos[1] = 0.4 + q[1];
    data->qvel[0] = qd[0], data->qvel[1] = qd[1];
    mj_forward(m.get(), data.get());
    for (int i = 0; i < 2; ++i) {
      EXPECT_NEAR(qdd[i], data->qacc[i], 1e-9 * std::max(1.0, std::abs(data->qacc[i])))
          << "coordinate " << i << " at q = " << q.transpose() << ", qd = " << qd.transpose();
      worst = std::max(worst, std::abs(qdd[i] - data->qacc[i]));
    }
  }
  std::cout << "sprung pendulum: q'' off MuJoCo's qacc by " << worst << " rad/s^2\n";
}

// Cassie-style leg (tests/data): the knee spring rigid by default, a passive driver with
// --springs; both imports assemble to the same pose, and at the spring's rest the motors need
// the same efforts (the spring's effort is then the torque the rigid joint's reaction carries).
TEST(ImportSprings, TheSpringAtRestIsTheRigidImport) {
  const std::string path = std::string(MECHGEN_SOURCE_DIR) + "/tests/data/mjcf_cassie_leg.xml";
  const SpatialModel rigid = import_mjcf(path, false);
  const SpatialModel sprung = import_mjcf(path, true);
  ASSERT_EQ(rigid.drivers.size() + 1, sprung.drivers.size());
  const SpatialDriver& spring = sprung.drivers.back();
  EXPECT_TRUE(spring.passive);
  EXPECT_EQ(sprung.joints[static_cast<size_t>(spring.joint)].name, "knee_spring");
  const std::vector<double> p = sprung.common.default_parameters();
  EXPECT_EQ(p[static_cast<size_t>(sprung.common.parameter_index("k_" + spring.name))], 1500);
  EXPECT_EQ(p[static_cast<size_t>(sprung.common.parameter_index("c_" + spring.name))], 0.1);

  const spatial::SpatialSolver a(rigid, {}), b(sprung, {});
  spatial::SpatialState sa, sb;
  for (const double t : {0.0, 0.13, 0.61}) {
    a.solve(t, sa);
    b.solve(t, sb);
    for (const SpatialBody& body : rigid.bodies) {
      const int ib = sprung.body_index(body.name);
      ASSERT_GE(ib, 0) << body.name;
      const spatial::Pose& x = sa.D[static_cast<size_t>(rigid.body_index(body.name))];
      const spatial::Pose& y = sb.D[static_cast<size_t>(ib)];
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(x.p[static_cast<size_t>(i)], y.p[static_cast<size_t>(i)], 1e-12) << body.name;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(x.R(i, k), y.R(i, k), 1e-12) << body.name;
      }
    }
    // Efforts in each solver's primary order (by joint): matched by driver name.
    const VectorXd ea = spatial::inverse_dynamics(a, sa).effort;
    const VectorXd eb = spatial::inverse_dynamics(b, sb).effort;
    auto effort_of = [](const spatial::SpatialSolver& s, const VectorXd& e,
                        const std::string& name) {
      for (const spatial::SpatialDriverGroup& g : spatial::spatial_driver_groups(s))
        if (g.name == name) return e[g.primary];
      ADD_FAILURE() << "no driver " << name;
      return 0.0;
    };
    for (const SpatialDriver& d : rigid.drivers) {
      const double x = effort_of(a, ea, d.name), y = effort_of(b, eb, d.name);
      EXPECT_NEAR(x, y, 1e-9 * std::max(1.0, std::abs(x))) << d.name << " t = " << t;
    }
  }
  // At rest, each driver's effort is the gradient of the gravity potential along its coordinate
  // (virtual work, the others held): the spring's torque, by central differences of the bodies'
  // potential energy.
  const std::unique_ptr<sim::Plant> plant = sim::spatial_plant(sprung, p);
  const auto n = static_cast<Eigen::Index>(plant->drivers().size());
  for (const double t : {0.0, 0.13, 0.61}) {
    VectorXd q, qd;
    plant->motion(t, q, qd);
    const VectorXd zero = VectorXd::Zero(n);
    auto potential = [&](const VectorXd& at, numeric::MassBias& mb) {
      std::string why;
      EXPECT_TRUE(plant->place(t, at, zero, mb, why)) << why;
      std::vector<double> row;
      double kinetic = 0, v = 0;
      EXPECT_TRUE(plant->row(t, at, zero, zero, row, kinetic, v, why)) << why;
      return v;
    };
    numeric::MassBias statics, unused;
    potential(q, statics);
    const double step = 1e-5;
    for (Eigen::Index d = 0; d < n; ++d) {
      const VectorXd e = VectorXd::Unit(n, d) * step;
      const double gradient = (potential(q + e, unused) - potential(q - e, unused)) / (2 * step);
      EXPECT_NEAR(statics.h[d], gradient, 1e-6 * std::max(1.0, std::abs(gradient)))
          << plant->drivers()[static_cast<size_t>(d)] << " t = " << t;
    }
    EXPECT_GT(std::abs(statics.h[n - 1]), 0.05) << "the spring carries part of the leg's weight";
  }
}

// Under simulate the spring moves: computed torque on the three motors holds their motion to the
// integration error (the passive coordinate's coupling included: collocated partial feedback),
// the spring deflects by about its load over its stiffness, and the energy balance (kinetic +
// gravity - the work of every effort, the spring's and damper's included) stays constant.
TEST(ImportSprings, TheSpringMovesUnderSimulateAndTheEnergyBalanceHolds) {
  const SpatialModel model =
      import_mjcf(std::string(MECHGEN_SOURCE_DIR) + "/tests/data/mjcf_cassie_leg.xml", true);
  const std::vector<double> parameters = model.common.default_parameters();
  std::shared_ptr<sim::Plant> plant = sim::spatial_plant(model, parameters);
  std::shared_ptr<sim::Plant> controller = sim::spatial_plant(model, parameters);
  const size_t n = model.drivers.size();
  std::vector<bool> passive(n, false);
  std::vector<std::string> motors;
  for (size_t d = 0; d < n; ++d) {
    passive[d] = model.drivers[d].passive;
    if (!passive[d]) motors.push_back(model.drivers[d].name);
  }
  const sim::EffortFunction laws = sim::model_effort_laws(model, parameters, motors);
  sim::SimulationOptions options;
  options.t1 = 0.3;
  options.dt = 1e-3;
  const sim::SimulationResult result = sim::simulate(
      *plant,
      sim::tracking_controller(controller, sim::Control::computed_torque, 400, 40,
                               VectorXd::Ones(static_cast<Eigen::Index>(n)), passive, laws),
      options);
  ASSERT_TRUE(result.error.empty()) << result.error;
  double worst_tracking = 0, largest_deflection = 0;
  for (const std::vector<double>& row : result.rows) {
    VectorXd qr, qdr;
    plant->motion(row.front(), qr, qdr);
    for (size_t d = 0; d < n; ++d) {
      size_t c = 0;
      while (result.columns[c] != model.drivers[d].name + ".q") ++c;
      if (passive[d])
        largest_deflection = std::max(largest_deflection, std::abs(row[c]));
      else
        worst_tracking = std::max(worst_tracking, std::abs(row[c] - qr[static_cast<long>(d)]));
    }
  }
  const double drift = result.rows.back().back() - result.rows.front().back();
  EXPECT_LT(worst_tracking, 1e-8);
  EXPECT_GT(largest_deflection, 1e-3) << "the spring deflects under the shin's load";
  EXPECT_LT(largest_deflection, 0.05) << "a 1500 N m/rad spring under a few N m";
  EXPECT_LT(std::abs(drift), 1e-7);
  std::cout << "cassie leg, spring free: motors tracked to " << worst_tracking
            << " rad, spring deflection up to " << largest_deflection << " rad, energy drift "
            << drift << " J\n";
}

// Export keeps the spring: MJCF's joint stiffness, damping and springref, the driver named back
// by a custom text. Imported again with --springs, the model has the same drivers, passive
// flags, laws and dynamics (M, h and the efforts at any state) as the original.
TEST(ImportSprings, ExportWritesTheSpringAndImportReadsItBack) {
  const SpatialModel original =
      import_mjcf(std::string(MECHGEN_SOURCE_DIR) + "/tests/data/mjcf_cassie_leg.xml", true);
  const std::string xml = import::export_mjcf(original, "cassie");
  EXPECT_NE(xml.find("stiffness=\"1500\" damping=\"0.1\" springref=\"0\""), std::string::npos)
      << xml;
  const std::string path = testing::TempDir() + "cassie_springs_export.xml";
  std::ofstream(path) << xml;
  const SpatialModel back = import_mjcf(path, true);
  ASSERT_EQ(back.drivers.size(), original.drivers.size());
  std::vector<std::string> motors;
  for (size_t d = 0; d < original.drivers.size(); ++d) {
    EXPECT_EQ(back.drivers[d].name, original.drivers[d].name);
    EXPECT_EQ(back.drivers[d].passive, original.drivers[d].passive);
    if (!original.drivers[d].passive) motors.push_back(original.drivers[d].name);
  }
  const std::vector<double> pa = original.common.default_parameters();
  const std::vector<double> pb = back.common.default_parameters();
  const std::unique_ptr<sim::Plant> a = sim::spatial_plant(original, pa);
  const std::unique_ptr<sim::Plant> b = sim::spatial_plant(back, pb);
  const sim::EffortFunction la = sim::model_effort_laws(original, pa, motors);
  const sim::EffortFunction lb = sim::model_effort_laws(back, pb, motors);
  double worst = 0;
  for (const double t : {0.0, 0.2, 0.45}) {
    VectorXd q, qd;
    a->motion(t, q, qd);
    q[static_cast<long>(q.size()) - 1] = 0.01;  // the spring off its rest, moving
    qd[static_cast<long>(qd.size()) - 1] = -0.3;
    numeric::MassBias ma, mb;
    std::string why;
    ASSERT_TRUE(a->place(t, q, qd, ma, why)) << why;
    ASSERT_TRUE(b->place(t, q, qd, mb, why)) << why;
    VectorXd ea, eb;
    la(t, q, qd, ea);
    lb(t, q, qd, eb);
    worst = std::max({worst, (ma.M - mb.M).cwiseAbs().maxCoeff(),
                      (ma.h - mb.h).cwiseAbs().maxCoeff(), (ea - eb).cwiseAbs().maxCoeff()});
    EXPECT_NE(ea[static_cast<long>(ea.size()) - 1], 0) << "the spring's law at work";
  }
  EXPECT_LT(worst, 1e-12);
  std::cout << "cassie leg with its spring, MJCF round trip: M, h and the laws within " << worst
            << "\n";
}

}  // namespace
