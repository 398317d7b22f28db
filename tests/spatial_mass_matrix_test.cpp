// The spatial reference solver's mass matrix and bias (runtime/spatial/spatial_mass_matrix.hpp)
// on the closed-chain test models and leg6: symmetric positive definite, effort = M qdd + h equals
// the inverse dynamics of the model's own motion, 1/2 qd^T M qd equals the kinetic energy summed
// over bodies, and the forward accelerations recover the model's qdd.
#include <gtest/gtest.h>

#include "model/spatial_model.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_mass_matrix.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"
#include "spatial_test_models.hpp"

namespace mechgen::spatial {
namespace {

TEST(SpatialMassMatrix, MatchesInverseDynamicsAndKineticEnergy) {
  std::vector<Case> cases = closed_chains();
  cases.push_back({"leg6", text_of(MECHGEN_SOURCE_DIR "/models/leg6.yaml")});
  for (const auto& [name, text] : cases) {
    SCOPED_TRACE(name);
    const SpatialModel model = read_spatial_model_text(text, name + ".yaml");
    const SpatialSolver solver(model, {});
    const SpatialSweepOptions o = default_spatial_sweep(model);
    SpatialState s;
    double worst_effort = 0, worst_energy = 0, worst_qdd = 0, effort_scale = 0, peak_kinetic = 0;
    for (int i = 0; i <= 10; ++i) {
      const double t = o.t0 + (o.t1 - o.t0) * i / 10;
      solver.solve(t, s);
      Eigen::VectorXd qp, qpd, qpdd;
      solver.primary_motion(t, qp, qpd, qpdd);
      const MassBias mb = mass_matrix_bias(solver, s, qpd);
      ASSERT_EQ(mb.M.rows(), qp.size());
      EXPECT_EQ((mb.M - mb.M.transpose()).cwiseAbs().maxCoeff(), 0.0);
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(mb.M);
      EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0);
      const Eigen::VectorXd effort = inverse_dynamics(solver, s).effort;
      effort_scale = std::max(effort_scale, effort.cwiseAbs().maxCoeff());
      worst_effort = std::max(worst_effort, (mb.M * qpdd + mb.h - effort).cwiseAbs().maxCoeff());
      const double kinetic = energy(solver, s).kinetic;
      const double quadratic = 0.5 * qpd.dot(mb.M * qpd);
      peak_kinetic = std::max(peak_kinetic, kinetic);
      worst_energy = std::max(worst_energy, std::abs(quadratic - kinetic));
      Eigen::VectorXd qdd;
      ASSERT_TRUE(forward_accelerations(mb, effort, qdd));
      worst_qdd = std::max(worst_qdd, (qdd - qpdd).cwiseAbs().maxCoeff() /
                                          std::max(1.0, qpdd.cwiseAbs().maxCoeff()));
    }
    EXPECT_LT(worst_effort, 1e-10 * std::max(1.0, effort_scale));
    // Relative to the sweep's peak: near rest both sides are round-off of larger terms.
    ASSERT_GT(peak_kinetic, 0);
    worst_energy /= peak_kinetic;
    EXPECT_LT(worst_energy, 1e-12);
    EXPECT_LT(worst_qdd, 1e-9);
    std::cout << name << ": |M qdd + h - effort| " << worst_effort << ", kinetic energy rel. "
              << worst_energy << ", qdd " << worst_qdd << "\n";
  }
}

TEST(SpatialMassMatrix, ForwardAccelerationsRefuseASingularMatrix) {
  MassBias mb;
  mb.M = Eigen::MatrixXd::Ones(2, 2);  // rank 1: a loop at a singular configuration
  mb.h = Eigen::VectorXd::Zero(2);
  Eigen::VectorXd qdd = Eigen::VectorXd::Constant(2, 7.0);
  EXPECT_FALSE(forward_accelerations(mb, Eigen::VectorXd::Ones(2), qdd));
  EXPECT_EQ(qdd, Eigen::VectorXd::Constant(2, 7.0));
}

}  // namespace
}  // namespace mechgen::spatial
