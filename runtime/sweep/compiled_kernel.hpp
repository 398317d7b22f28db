// The runtime's view of a generated kernel: names and a flat evaluation of one CSV row, in double
// or float. Each generated/<model>/<model>_entry.cpp defines one; the build lists them all.
#pragma once

#include <string>
#include <vector>

namespace mechgen {

// The layout below; a kernel built on demand (a shared library) is used only when its entry
// `extern "C" const CompiledKernel* mechgen_kernel_entry(int abi)` accepts this value. Bump it with
// any change of CompiledKernel.
inline constexpr int kCompiledKernelAbi = 5;

struct CompiledKernel {
  // Evaluates the row at time t (the model's driver motion) for parameters in model order;
  // returns 0 (ok), 1 (unreachable), 2 (singular) or 3 (a non-finite output) and the failing
  // group_names[] entry (a solve group, or the stage: inputs, positions, rates, forces).
  using RowFunction = int (*)(const double* parameters, double t, double* row, int* failed_group);
  // The row for a driver motion other than the model's own: `drivers` holds (q, qd, qdd) per
  // driver, in model order (driver_count of them); same return values.
  using DrivenRowFunction = int (*)(const double* parameters, double t, const double* drivers,
                                    double* row, int* failed_group);
  // n samples at once, vectorised (evaluate_batch): column c of sample i to out[c * n + i];
  // status[i] and group[i] as RowFunction returns them (a failed sample's columns are garbage).
  using BatchFunction = void (*)(const double* parameters, const double* t, long n, double* out,
                                 int* status, int* group);

  const char* model;
  int parameter_count;
  const char* const* parameter_names;
  int column_count;
  const char* const* column_names;
  int group_count;
  const char* const* group_names;
  RowFunction evaluate_double;
  RowFunction evaluate_float;
  int driver_count;
  DrivenRowFunction evaluate_driven_double;
  BatchFunction evaluate_batch_double;
  // What the kernel was generated from (generator/kernel_fingerprint.hpp): run it only for a
  // description with this fingerprint.
  unsigned long long fingerprint;
  // Forward dynamics in the drivers' coordinates (issue 22), effort = M qdd + h, at the drivers'
  // (q, qd) given as (q, qd, qdd) per driver in model order (`drivers`, qdd not used), or at the
  // model's own driver motion at t when `drivers` is null. mass_bias: M (driver_count^2,
  // row-major, symmetric) and h (driver_count); forward_dynamics: qdd (driver_count) under
  // `effort` (driver_count); 2 (singular) also for an M that is not positive definite. Return
  // values and failed_group as RowFunction's; qdd is written only on 0.
  using MassBiasFunction = int (*)(const double* parameters, double t, const double* drivers,
                                   double* M, double* h, int* failed_group);
  using ForwardDynamicsFunction = int (*)(const double* parameters, double t, const double* drivers,
                                          const double* effort, double* qdd, int* failed_group);
  MassBiasFunction mass_bias_double = nullptr;
  ForwardDynamicsFunction forward_dynamics_double = nullptr;
  // Spatial kernels: the named points' positions alone (point_positions: no rates, Jacobians or
  // forces) for n samples of the drivers' coordinates, driver k of sample i at q[k * n + i];
  // point c's axis a to out[(3 c + a) n + i]; status[i] as RowFunction returns it. Null in planar
  // kernels.
  using PointsBatchFunction = void (*)(const double* parameters, const double* q, long n,
                                       double* out, int* status);
  int point_count = 0;
  const char* const* point_names = nullptr;
  PointsBatchFunction point_positions_batch_double = nullptr;
  // Spatial closed chains: the warm start's entries (Newton coordinates, then closed-form angles)
  // as columns of the spatial graph (the numeric solver's SpatialState::q), and the function that
  // makes the next sweep on the calling thread start from values[k] for them, or from the
  // kernel's defaults again for null. The branch of every closed form is the one nearest the warm
  // start, so a sweep started from the numeric solver's assembly at its own parameters takes the
  // numeric solver's branch (issue 28). 0 and null elsewhere.
  using SeedFunction = void (*)(const double* values);
  int start_count = 0;
  const int* start_columns = nullptr;
  SeedFunction seed_start = nullptr;
  // The Newton-Euler system A x = b of the header's ne_system() (ne_rows x ne_size, A row-major,
  // unknowns ne_unknowns[]) at the drivers' (q, qd, qdd) per driver in model order (`drivers`),
  // or at the model's own driver motion at t when `drivers` is null; A and b are zero unless it
  // returns 0 (return values and failed_group as RowFunction's; planar kernels give -1 for the
  // group). A spatial closed chain closes its circuits from the warm start of
  // evaluate_driven_double, which it carries on, as a driven row does.
  using NeSystemFunction = int (*)(const double* parameters, double t, const double* drivers,
                                   double* A, double* b, int* failed_group);
  int ne_rows = 0;
  int ne_size = 0;
  const char* const* ne_unknowns = nullptr;
  NeSystemFunction ne_system_double = nullptr;
  // Spatial kernels: the screw Jacobians the header's State holds (all of them, or those that
  // `kernel: {jacobians: [...]}` names): jacobian_count of them, jacobian_names[] with
  // jacobian_rows[] rows each (6: a body's twist, rows wx, wy, wz, then the velocity of the body
  // point at the ground origin; 3: a named point's velocity; bodies first) by jacobian_columns
  // columns (the driven coordinates' rates in model order), row-major, one after the other in J.
  // At drivers or the model's motion at t as ne_system_double, and with the same warm start; J is
  // written only on 0. Null and 0 in planar kernels.
  using JacobiansFunction = int (*)(const double* parameters, double t, const double* drivers,
                                    double* J, int* failed_group);
  int jacobian_count = 0;
  const char* const* jacobian_names = nullptr;
  const int* jacobian_rows = nullptr;
  int jacobian_columns = 0;
  JacobiansFunction jacobians_double = nullptr;
  // Planar kernels: evaluate_batch_double at driver motions instead of the model's own, as
  // vectorised: (q, qd, qdd) of driver d for sample i at drivers[(3 d + k) n + i] (k = 0, 1, 2),
  // times t[0..n); out, status and group as BatchFunction's. Null in spatial kernels (their batch
  // entry is a loop over the scalar row: the driven row's loop is as fast).
  using DrivenBatchFunction = void (*)(const double* parameters, const double* t,
                                       const double* drivers, long n, double* out, int* status,
                                       int* group);
  DrivenBatchFunction evaluate_driven_batch_double = nullptr;
};

// The kernel compiled into this binary for `model`, or nullptr, whatever its fingerprint (the
// checked lookup is runtime/ondemand/kernel_resolver.hpp's).
const CompiledKernel* find_compiled_kernel(const std::string& model);
std::vector<std::string> compiled_kernel_models();

}  // namespace mechgen
