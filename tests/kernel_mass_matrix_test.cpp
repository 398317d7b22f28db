// The generated kernels' forward-dynamics entries (issue 22 item 1: mass_bias / mass_matrix /
// bias / mass_solve / forward_dynamics, CompiledKernel::mass_bias_double and
// forward_dynamics_double) on every shipped model, planar and spatial, along a sweep: M and h equal
// the numeric solvers' (unit accelerations through their own Newton-Euler solve: planar
// ReferenceSolver::mass_matrix_bias, spatial::mass_matrix_bias) to 1e-10 of their scale, the
// generated forward_dynamics equals numeric::forward_accelerations on the numeric M and h, and
// effort = M qdd + h reproduces the kernel's own inverse dynamics. Then the header's entries
// directly, in double and float, and a singular M refused without NaN.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "leg6/leg6.hpp"
#include "model/model.hpp"
#include "model/spatial_model.hpp"
#include "numeric/mass_bias.hpp"
#include "pasibot/pasibot.hpp"
#include "spatial/spatial_kernel_sweep.hpp"
#include "spatial/spatial_sweep.hpp"
#include "sweep/compiled_kernel.hpp"
#include "sweep/sweep.hpp"

namespace mechgen {
namespace {

constexpr int kSamples = 7;

size_t column(const std::vector<std::string>& columns, const std::string& name) {
  const auto it = std::find(columns.begin(), columns.end(), name);
  EXPECT_NE(it, columns.end()) << name;
  return static_cast<size_t>(it - columns.begin());
}

// The driver coordinates of a sweep's columns, in column order (their `<a>.effort` columns).
std::vector<std::string> coordinates(const std::vector<std::string>& columns) {
  std::vector<std::string> out;
  const std::string effort = ".effort";
  for (const std::string& c : columns)
    if (c.size() > effort.size() && c.compare(c.size() - effort.size(), effort.size(), effort) == 0)
      out.push_back(c.substr(0, c.size() - effort.size()));
  return out;
}

// A row's M and h (the `M.<a>.<b>`, `h.<a>` columns).
numeric::MassBias mass_bias_of(const std::vector<std::string>& columns,
                               const std::vector<double>& row, const std::vector<std::string>& q) {
  const auto n = static_cast<Eigen::Index>(q.size());
  numeric::MassBias mb{Eigen::MatrixXd(n, n), Eigen::VectorXd(n)};
  for (Eigen::Index a = 0; a < n; ++a) {
    const auto ua = static_cast<size_t>(a);
    mb.h[a] = row[column(columns, "h." + q[ua])];
    for (Eigen::Index b = a; b < n; ++b)
      mb.M(a, b) = mb.M(b, a) =
          row[column(columns, "M." + q[ua] + "." + q[static_cast<size_t>(b)])];
  }
  return mb;
}

Eigen::VectorXd values_of(const std::vector<std::string>& columns, const std::vector<double>& row,
                          const std::vector<std::string>& q, const std::string& field) {
  Eigen::VectorXd out(static_cast<Eigen::Index>(q.size()));
  for (size_t a = 0; a < q.size(); ++a)
    out[static_cast<Eigen::Index>(a)] = row[column(columns, q[a] + "." + field)];
  return out;
}

struct Worst {
  double M = 0, h = 0, qdd = 0, effort = 0, driven = 0;
  int refused = 0;  // forward dynamics at a singular M, refused by both solvers
};

// Compares the two sweeps (same columns; `generated` from the kernel) row by row; `drivers_q`:
// the kernel's q inputs are the `<a>.q` columns (planar and joint drivers), so the driven entry
// can be checked against the model's own motion.
Worst compare(const CompiledKernel& kernel, const std::vector<double>& parameters,
              const std::vector<double>& times, const std::vector<std::string>& columns,
              const std::vector<std::vector<double>>& generated,
              const std::vector<std::vector<double>>& numeric, bool drivers_q) {
  const std::vector<std::string> q = coordinates(columns);
  EXPECT_EQ(static_cast<int>(q.size()), kernel.driver_count);
  EXPECT_EQ(generated.size(), numeric.size());
  const size_t n = q.size();
  double M_scale = 0, h_scale = 0, effort_scale = 0;
  for (const std::vector<double>& row : numeric) {
    const numeric::MassBias mb = mass_bias_of(columns, row, q);
    M_scale = std::max(M_scale, mb.M.cwiseAbs().maxCoeff());
    h_scale = std::max(h_scale, mb.h.cwiseAbs().maxCoeff());
    effort_scale =
        std::max(effort_scale, values_of(columns, row, q, "effort").cwiseAbs().maxCoeff());
  }
  Worst w;
  for (size_t i = 0; i < generated.size() && i < numeric.size(); ++i) {
    SCOPED_TRACE("sample " + std::to_string(i));
    const numeric::MassBias g = mass_bias_of(columns, generated[i], q);
    const numeric::MassBias r = mass_bias_of(columns, numeric[i], q);
    w.M = std::max(w.M, (g.M - r.M).cwiseAbs().maxCoeff() / M_scale);
    w.h = std::max(w.h, (g.h - r.h).cwiseAbs().maxCoeff() / std::max(1.0, h_scale));
    // effort = M qdd + h with the kernel's own efforts and accelerations.
    const Eigen::VectorXd effort = values_of(columns, generated[i], q, "effort");
    const Eigen::VectorXd qdd_row = values_of(columns, generated[i], q, "qdd");
    w.effort = std::max(w.effort, (g.M * qdd_row + g.h - effort).cwiseAbs().maxCoeff() /
                                      std::max(1.0, effort_scale));
    // Forward dynamics under the row's efforts and under other ones, against the numeric
    // solver's forward_accelerations on its own M and h.
    for (const double push : {0.0, 0.5}) {
      const Eigen::VectorXd e =
          effort + Eigen::VectorXd::Constant(static_cast<Eigen::Index>(n), push * effort_scale);
      Eigen::VectorXd expected;
      std::vector<double> qdd(n, 7.0);
      int group = -1;
      const bool numeric_ok = numeric::forward_accelerations(r, e, expected);
      const int status = kernel.forward_dynamics_double(parameters.data(), times[i], nullptr,
                                                        e.data(), qdd.data(), &group);
      if (!numeric_ok) {
        // A singular M (the Bioloid's massless hands on their own pose coordinates): both
        // refuse, the kernel as singular, leaving qdd untouched.
        EXPECT_EQ(status, 2);
        EXPECT_EQ(qdd, std::vector<double>(n, 7.0));
        ++w.refused;
        continue;
      }
      if (status != 0) {
        ADD_FAILURE() << "forward dynamics refused: " << status;
        return w;
      }
      const Eigen::Map<const Eigen::VectorXd> got(qdd.data(), static_cast<Eigen::Index>(n));
      w.qdd = std::max(w.qdd, (got - expected).cwiseAbs().maxCoeff() /
                                  std::max(1.0, expected.cwiseAbs().maxCoeff()));
      if (push == 0)
        w.qdd = std::max(w.qdd, (got - qdd_row).cwiseAbs().maxCoeff() /
                                    std::max(1.0, qdd_row.cwiseAbs().maxCoeff()));
    }
    if (!drivers_q) continue;
    // The driven entry at the row's (q, qd) gives the model's own motion's M and h.
    std::vector<double> drivers;
    for (const std::string& a : q)
      for (const char* f : {".q", ".qd", ".qdd"})
        drivers.push_back(generated[i][column(columns, a + f)]);
    std::vector<double> M(n * n), h(n);
    int group = -1;
    if (kernel.mass_bias_double(parameters.data(), times[i], drivers.data(), M.data(), h.data(),
                                &group) != 0) {
      ADD_FAILURE() << "driven mass_bias refused";
      return w;
    }
    for (size_t a = 0; a < n; ++a) {
      w.driven = std::max(
          w.driven, std::abs(h[a] - g.h[static_cast<Eigen::Index>(a)]) / std::max(1.0, h_scale));
      for (size_t b = 0; b < n; ++b)
        w.driven = std::max(w.driven, std::abs(M[a * n + b] - g.M(static_cast<Eigen::Index>(a),
                                                                  static_cast<Eigen::Index>(b))) /
                                          M_scale);
    }
  }
  return w;
}

void expect_close(const std::string& name, const Worst& w) {
  EXPECT_LT(w.M, 1e-10);
  EXPECT_LT(w.h, 1e-10);
  EXPECT_LT(w.qdd, 1e-9);
  EXPECT_LT(w.effort, 1e-10);
  EXPECT_LT(w.driven, 1e-12);
  std::cout << name << ": M " << w.M << ", h " << w.h << ", qdd " << w.qdd
            << ", |M qdd + h - effort| " << w.effort << ", driven " << w.driven
            << (w.refused ? ", singular (refused by both) " + std::to_string(w.refused) : "")
            << "\n";
}

TEST(KernelMassMatrix, PlanarKernelsEqualTheNumericSolver) {
  Worst all;
  for (const char* name : {"assur_triad", "chebyshev", "cylinder_leg", "inverted_slider", "leg3",
                           "pasibot", "plate_crank", "quick_return", "slider_crank"}) {
    SCOPED_TRACE(name);
    const Model model = read_model(std::string(MECHGEN_SOURCE_DIR "/models/") + name + ".yaml");
    const CompiledKernel* kernel = find_compiled_kernel(name);
    ASSERT_NE(kernel, nullptr);
    ASSERT_NE(kernel->mass_bias_double, nullptr);
    SweepOptions options = default_sweep(model);
    options.samples = kSamples;
    options.mass_matrix = true;
    options.solver = "numeric";
    const SweepResult numeric = run_sweep(model, options);
    options.solver = "generated";
    const SweepResult generated = run_sweep(model, options);
    ASSERT_EQ(generated.columns, numeric.columns);
    const Worst w =
        compare(*kernel, options.parameters, sample_times(options.t0, options.t1, options.samples),
                generated.columns, generated.rows, numeric.rows, true);
    expect_close(name, w);
    all.M = std::max(all.M, w.M);
    all.h = std::max(all.h, w.h);
    all.qdd = std::max(all.qdd, w.qdd);
  }
  std::cout << "planar, worst: M " << all.M << ", h " << all.h << ", qdd " << all.qdd << "\n";
}

TEST(KernelMassMatrix, SpatialKernelsEqualTheNumericSolver) {
  Worst all;
  for (const char* name :
       {"leg6", "lecture_leg", "rsur", "chebyshev_spatial", "quadruped_leg", "lecture_leg_ik",
        "lecture_leg_abstract", "bioloid", "quadruped_leg_swing"}) {
    SCOPED_TRACE(name);
    const SpatialModel model =
        read_spatial_model(std::string(MECHGEN_SOURCE_DIR "/models/") + name + ".yaml");
    const CompiledKernel* kernel = find_compiled_kernel(name);
    ASSERT_NE(kernel, nullptr);
    ASSERT_NE(kernel->mass_bias_double, nullptr);
    spatial::SpatialSweepOptions options = spatial::default_spatial_sweep(model);
    options.samples = kSamples;
    options.mass_matrix = true;
    const spatial::SpatialSweepResult numeric = spatial::run_spatial_sweep(model, options);
    const spatial::SpatialSweepResult generated =
        spatial::run_spatial_kernel_sweep(model, options, *kernel);
    ASSERT_EQ(generated.columns, numeric.columns);
    std::vector<double> times;
    for (int i = 0; i < options.samples; ++i)
      times.push_back(spatial::spatial_sample_time(options, i));
    // The kernel's entries at the model's own motion start from the warm start the last row
    // left on this thread (a closed chain's): each sample's row first, in time order, as the
    // sweep does.
    Worst w;
    std::vector<double> row(static_cast<size_t>(kernel->column_count));
    for (size_t i = 0; i < times.size(); ++i) {
      int group = -1;
      ASSERT_EQ(kernel->evaluate_double(options.parameters.data(), times[i], row.data(), &group),
                0);
      const Worst wi = compare(*kernel, options.parameters, {times[i]}, generated.columns,
                               {generated.rows[i]}, {numeric.rows[i]}, std::string(name) == "leg6");
      w.M = std::max(w.M, wi.M);
      w.h = std::max(w.h, wi.h);
      w.qdd = std::max(w.qdd, wi.qdd);
      w.effort = std::max(w.effort, wi.effort);
      w.driven = std::max(w.driven, wi.driven);
      w.refused += wi.refused;
    }
    // Only the Bioloid's M is singular (its hands are massless).
    EXPECT_EQ(w.refused > 0, std::string(name) == "bioloid");
    expect_close(name, w);
    all.M = std::max(all.M, w.M);
    all.h = std::max(all.h, w.h);
    all.qdd = std::max(all.qdd, w.qdd);
  }
  std::cout << "spatial, worst: M " << all.M << ", h " << all.h << ", qdd " << all.qdd << "\n";
}

// The header's own entries, templated on the scalar: mass_matrix and bias agree with mass_bias,
// forward_dynamics inverts effort = M qdd + h (double and float), mass_solve refuses a singular M.
template <class Params, class Inputs, class State, int N, class T, class Kernel>
void check_header(const Kernel& k, const Params& p, const Inputs& in, double tolerance) {
  State s;
  T M[N * N] = {}, M2[N * N] = {}, h[N] = {}, h2[N] = {}, effort[N] = {}, qdd[N] = {};
  ASSERT_EQ(k.mass_bias(p, in, s, M, h), k.ok);
  ASSERT_EQ(k.mass_matrix(p, in, s, M2), k.ok);
  ASSERT_EQ(k.bias(p, in, s, h2), k.ok);
  for (int a = 0; a < N; ++a) {
    EXPECT_EQ(h[a], h2[a]);
    for (int b = 0; b < N; ++b) {
      EXPECT_EQ(M[a * N + b], M2[a * N + b]);
      EXPECT_EQ(M[a * N + b], M[b * N + a]);  // written once per pair
    }
    effort[a] = h[a] + T(1);
  }
  ASSERT_EQ(k.forward_dynamics(p, in, effort, s, qdd), k.ok);
  for (int a = 0; a < N; ++a) {
    T sum = h[a];
    for (int b = 0; b < N; ++b) sum += M[a * N + b] * qdd[b];
    EXPECT_NEAR(static_cast<double>(sum), static_cast<double>(effort[a]), tolerance);
  }
}

// One kernel's header entries as static members (a namespace is no template argument).
#define MECHGEN_KERNEL_ENTRIES(Name, ns)       \
  struct Name {                                \
    static constexpr auto ok = ns::Status::ok; \
    template <class... A>                      \
    static auto mass_bias(A&&... a) {          \
      return ns::mass_bias(a...);              \
    }                                          \
    template <class... A>                      \
    static auto mass_matrix(A&&... a) {        \
      return ns::mass_matrix(a...);            \
    }                                          \
    template <class... A>                      \
    static auto bias(A&&... a) {               \
      return ns::bias(a...);                   \
    }                                          \
    template <class... A>                      \
    static auto forward_dynamics(A&&... a) {   \
      return ns::forward_dynamics(a...);       \
    }                                          \
  };
MECHGEN_KERNEL_ENTRIES(Pasibot, gen::pasibot)
MECHGEN_KERNEL_ENTRIES(Leg6, gen::leg6)
#undef MECHGEN_KERNEL_ENTRIES

template <class T>
void check_headers(double tolerance) {
  {
    gen::pasibot::Params<T> p;
    gen::pasibot::Inputs<T> in;
    gen::pasibot::driver_inputs(p, T(0.3), in);
    check_header<gen::pasibot::Params<T>, gen::pasibot::Inputs<T>, gen::pasibot::State<T>,
                 gen::pasibot::coordinate_count, T>(Pasibot{}, p, in, tolerance);
  }
  {
    gen::leg6::Params<T> p;
    gen::leg6::Inputs<T> in;
    gen::leg6::driver_inputs(p, T(0.4), in);
    check_header<gen::leg6::Params<T>, gen::leg6::Inputs<T>, gen::leg6::State<T>,
                 gen::leg6::coordinate_count, T>(Leg6{}, p, in, tolerance);
  }
}

TEST(KernelMassMatrix, HeaderEntriesInDoubleAndFloat) {
  check_headers<double>(1e-12);
  check_headers<float>(1e-3);
}

TEST(KernelMassMatrix, SingularMassMatrixIsRefusedWithoutNaN) {
  // Rank 1 (a loop at a singular configuration), then one with a NaN entry.
  const double singular[36] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1,
                               1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  const double h[6] = {0, 0, 0, 0, 0, 0}, effort[6] = {1, 2, 3, 4, 5, 6};
  double qdd[6] = {7, 7, 7, 7, 7, 7};
  EXPECT_EQ(gen::leg6::mass_solve(singular, h, effort, qdd), gen::leg6::Status::singular);
  double nan[36] = {};
  for (int a = 0; a < 6; ++a) nan[a * 7] = 1;
  nan[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(gen::leg6::mass_solve(nan, h, effort, qdd), gen::leg6::Status::singular);
  const float one[1] = {0.0f}, zero[1] = {0.0f}, push[1] = {1.0f};
  float x[1] = {7.0f};
  EXPECT_EQ(gen::pasibot::mass_solve(one, zero, push, x), gen::pasibot::Status::singular);
  EXPECT_EQ(x[0], 7.0f);
  for (const double v : qdd) EXPECT_EQ(v, 7.0);
}

}  // namespace
}  // namespace mechgen
