// The Python module `mechgen` (issue 23): a description, its generated kernel and the numeric
// reference solver from NumPy. Everything is the runtime's: the model readers, the kernel lookup
// of the command line (compiled in, else built on demand and cached), its sweep drivers and the
// info JSON; this file only converts arguments and results.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "cli/model_info.hpp"
#include "model/columns.hpp"
#include "model/model.hpp"
#include "model/spatial_model.hpp"
#include "model/spatial_value_checks.hpp"
#include "numeric/reference_solver.hpp"
#include "ondemand/data_paths.hpp"
#include "ondemand/kernel_resolver.hpp"
#include "spatial/driven_solve.hpp"
#include "spatial/spatial_dynamics.hpp"
#include "spatial/spatial_kernel_sweep.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"
#include "sweep/sweep.hpp"

namespace py = pybind11;

namespace mechgen::python {

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IntArray = py::array_t<int, py::array::c_style>;

// A read description, planar or spatial, shared by the kernels and solvers made from it.
struct Description {
  std::string path;
  bool spatial = false;
  Model planar;
  SpatialModel space;
  std::vector<std::string> drivers;  // the kernels' driver order (model order)
  std::vector<double> defaults;      // checked when the description was read

  const Model& common() const { return spatial ? space.common : planar; }

  // The parameters in model order: the defaults with `params` applied as `--set NAME=VALUE`
  // (the same checks, derived parameters following).
  std::vector<double> parameters(const std::map<std::string, double>& params) const {
    if (params.empty()) return defaults;  // the checks cost far more than a kernel call
    std::vector<std::string> overrides;
    for (const auto& [name, value] : params) {
      char text[40];
      std::snprintf(text, sizeof text, "%.17g", value);
      overrides.push_back(name + "=" + text);
    }
    std::vector<double> values = common().default_parameters();
    if (spatial)
      apply_overrides(space, overrides, values);
    else
      apply_overrides(planar, overrides, values);
    return values;
  }
};

// A YAML syntax error carries its place as the command line prints it: FILE:LINE:COL: error: ...
std::shared_ptr<Description> read_description(const std::string& path) {
  auto d = std::make_shared<Description>();
  d->path = path;
  try {
    d->spatial = is_spatial_description(path);
    if (d->spatial) {
      d->space = read_spatial_model(path);
      const spatial::SpatialSolver solver(d->space, {});
      for (const spatial::SpatialDriverGroup& g : spatial::spatial_driver_groups(solver))
        d->drivers.push_back(g.name);
    } else {
      d->planar = read_model(path);
      for (const Driver& driver : d->planar.drivers) d->drivers.push_back(driver.name);
    }
  } catch (const YAML::Exception& error) {
    throw ModelError(SourceLoc{path, error.mark.line + 1, error.mark.column + 1}, error.msg);
  }
  d->defaults = d->common().default_parameters();
  return d;
}

// Columns c of a (columns x n) block as a dict of 1-D views sharing the block (made directly, not
// by indexing: a kernel has hundreds of columns).
template <class Names>
py::dict column_views(const Names& names, py::array_t<double>& block) {
  py::dict out;
  const py::ssize_t n = block.shape(1);
  double* data = block.mutable_data();
  py::ssize_t c = 0;
  for (const auto& name : names) {
    out[py::str(name)] =
        py::array_t<double>({n}, {static_cast<py::ssize_t>(sizeof(double))}, data + c * n, block);
    ++c;
  }
  return out;
}

// A sweep table (rows of samples) as a dict of columns.
py::dict sweep_dict(const std::vector<std::string>& names,
                    const std::vector<std::vector<double>>& rows) {
  const auto n = static_cast<py::ssize_t>(rows.size()), m = static_cast<py::ssize_t>(names.size());
  py::array_t<double> block({m, n});
  double* out = block.mutable_data();
  for (py::ssize_t i = 0; i < n; ++i)
    for (py::ssize_t c = 0; c < m; ++c) out[c * n + i] = rows[static_cast<size_t>(i)][c];
  return column_views(names, block);
}

struct SweepRequest {
  std::optional<int> samples;
  std::optional<double> t0, t1;
  std::map<std::string, double> params;
  int threads = 0;
  bool mass_matrix = false;
};

// The sweep `mechgen sweep` runs for the same options (cmd_sweep.cpp, cmd_spatial.cpp).
py::dict run(const Description& d, const CompiledKernel* kernel, const SweepRequest& r) {
  const std::vector<double> parameters = d.parameters(r.params);
  if (r.samples && *r.samples < 1) throw py::value_error("samples must be at least 1");
  if (r.threads < 0) throw py::value_error("threads must be at least 0");
  // A sweep keeps the GIL: it evaluates the model's GiNaC expressions (its step, the numeric
  // solver, the numeric assembly a spatial kernel starts from), whose reference counts are not
  // atomic: sweeps that released it from several Python threads crashed (the threads test
  // segfaulted), so they run one at a time. evaluate() and the other batch entries release it.
  if (d.spatial) {
    spatial::SpatialSweepResult result;
    {
      spatial::SpatialSweepOptions o = spatial::default_spatial_sweep(d.space, parameters);
      o.samples = r.samples.value_or(o.samples);
      o.t0 = r.t0.value_or(o.t0);
      o.t1 = r.t1.value_or(o.t1);
      o.mass_matrix = r.mass_matrix;
      result = kernel ? spatial::run_spatial_kernel_sweep(d.space, o, *kernel)
                      : spatial::run_spatial_sweep(d.space, o);
    }
    for (const std::string& warning : result.warnings)
      PyErr_WarnEx(PyExc_RuntimeWarning, (d.path + ": " + warning).c_str(), 1);
    return sweep_dict(result.columns, result.rows);
  }
  SweepResult result;
  {
    SweepOptions o = default_sweep(d.planar, parameters);
    o.solver = kernel ? "generated" : "numeric";
    o.samples = r.samples.value_or(o.samples);
    o.t0 = r.t0.value_or(o.t0);
    o.t1 = r.t1.value_or(o.t1);
    o.threads = r.threads;
    o.mass_matrix = r.mass_matrix;
    result = run_sweep(d.planar, o);
  }
  return sweep_dict(result.columns, result.rows);
}

// An (n, width) array of doubles, or zeros when absent; ValueError for another shape.
Array samples_of(const std::optional<Array>& a, const char* name, py::ssize_t n,
                 py::ssize_t width) {
  if (!a) {
    Array zeros({n, width});
    std::fill(zeros.mutable_data(), zeros.mutable_data() + n * width, 0.0);
    return zeros;
  }
  if (a->ndim() != 2 || a->shape(0) != n || a->shape(1) != width)
    throw py::value_error(std::string(name) + " must be an array of shape (" + std::to_string(n) +
                          ", " + std::to_string(width) + ")");
  return *a;
}

// t given as one number for every sample or one per sample.
std::vector<double> times_of(const py::object& t, py::ssize_t n) {
  if (t.is_none()) return std::vector<double>(static_cast<size_t>(n), 0.0);
  if (py::isinstance<py::float_>(t) || py::isinstance<py::int_>(t))
    return std::vector<double>(static_cast<size_t>(n), t.cast<double>());
  const Array a = t.cast<Array>();
  if (a.ndim() != 1 || a.shape(0) != n)
    throw py::value_error("t must be a number or an array of " + std::to_string(n) + " times");
  return {a.data(), a.data() + n};
}

py::ssize_t rows_of(const Array& q, py::ssize_t width) {
  if (q.ndim() != 2 || q.shape(1) != width)
    throw py::value_error("q must be an array of shape (N, " + std::to_string(width) + ")");
  return q.shape(0);
}

// f(i, drivers) for every sample i, drivers holding (q, qd, qdd) per driver as the kernel's
// driven entries read them; a null qdd is zeros.
template <class F>
void each_sample(const double* q, const double* qd, const double* qdd, py::ssize_t n, py::ssize_t w,
                 F&& f) {
  std::vector<double> drivers(static_cast<size_t>(3 * w), 0.0);
  for (py::ssize_t i = 0; i < n; ++i) {
    for (py::ssize_t k = 0; k < w; ++k) {
      drivers[static_cast<size_t>(3 * k)] = q[i * w + k];
      drivers[static_cast<size_t>(3 * k + 1)] = qd[i * w + k];
      drivers[static_cast<size_t>(3 * k + 2)] = qdd ? qdd[i * w + k] : 0.0;
    }
    f(i, drivers.data());
  }
}

// (N, total rows x w) Jacobians, one after the other per sample, as (bodies, points, status):
// dicts name -> (N, rows, w) views, bodies those of 6 rows.
py::tuple split_jacobians(const std::vector<std::pair<std::string, int>>& names,
                          py::array_t<double> block, py::ssize_t w, const py::object& status) {
  py::dict bodies, points;
  const py::ssize_t n = block.shape(0), stride = block.shape(1);
  const auto d = static_cast<py::ssize_t>(sizeof(double));
  py::ssize_t offset = 0;
  for (const auto& [name, rows] : names) {
    py::array_t<double> view({n, py::ssize_t{rows}, w}, {stride * d, w * d, d},
                             block.mutable_data() + offset, block);
    (rows == 6 ? bodies : points)[py::str(name)] = view;
    offset += rows * w;
  }
  return py::make_tuple(bodies, points, status);
}

class Kernel {
 public:
  Kernel(std::shared_ptr<const Description> d, const CompiledKernel& k)
      : d_(std::move(d)), k_(k), names_(k.column_names, k.column_names + k.column_count) {}

  std::vector<std::string> columns() const {
    return {k_.column_names, k_.column_names + k_.column_count};
  }
  std::vector<std::string> groups() const {
    return {k_.group_names, k_.group_names + k_.group_count};
  }
  std::vector<std::string> points() const {
    return {k_.point_names, k_.point_names + k_.point_count};
  }

  py::dict sweep(const SweepRequest& r) const { return run(*d_, &k_, r); }

  // Rows at given driver motions through the kernel's driven entry, or at the model's own motion
  // at times t through its vectorised batch entry (q absent); status per sample.
  py::tuple evaluate(const std::optional<Array>& q, const std::optional<Array>& qd,
                     const std::optional<Array>& qdd, const py::object& t,
                     const std::map<std::string, double>& params, bool as_array) const {
    const std::vector<double> p = d_->parameters(params);
    const auto m = static_cast<py::ssize_t>(k_.column_count);
    if (!q) {
      if (qd || qdd) throw py::value_error("qd and qdd need q");
      if (t.is_none()) throw py::value_error("give q (driver values) or t (the model's motion)");
      const Array times = t.cast<Array>();
      if (times.ndim() != 1) throw py::value_error("t must be a 1-D array of times");
      const py::ssize_t n = times.shape(0);
      py::array_t<double> block({m, n});
      IntArray status(n), group(n);
      {
        py::gil_scoped_release release;
        k_.evaluate_batch_double(p.data(), times.data(), static_cast<long>(n), block.mutable_data(),
                                 status.mutable_data(), group.mutable_data());
      }
      return py::make_tuple(as_array ? py::object(block) : column_views(names_, block), status);
    }
    const auto w = static_cast<py::ssize_t>(k_.driver_count);
    const py::ssize_t n = rows_of(*q, w);
    const Array a = *q, b = samples_of(qd, "qd", n, w), c = samples_of(qdd, "qdd", n, w);
    const std::vector<double> times = times_of(t, n);
    py::array_t<double> block({m, n});
    IntArray status(n);
    if (k_.evaluate_driven_batch_double) {
      // A planar kernel's vectorised driven batch: the drivers' (q, qd, qdd) as its arrays.
      py::gil_scoped_release release;
      std::vector<double> drivers(static_cast<size_t>(3 * w * n));
      for (py::ssize_t d = 0; d < w; ++d)
        for (py::ssize_t i = 0; i < n; ++i) {
          drivers[static_cast<size_t>((3 * d) * n + i)] = a.data()[i * w + d];
          drivers[static_cast<size_t>((3 * d + 1) * n + i)] = b.data()[i * w + d];
          drivers[static_cast<size_t>((3 * d + 2) * n + i)] = c.data()[i * w + d];
        }
      std::vector<int> group(static_cast<size_t>(n));
      k_.evaluate_driven_batch_double(p.data(), times.data(), drivers.data(), static_cast<long>(n),
                                      block.mutable_data(), status.mutable_data(), group.data());
    } else {
      py::gil_scoped_release release;
      double* out = block.mutable_data();
      int* s = status.mutable_data();
      std::vector<double> row(static_cast<size_t>(m));
      each_sample(a.data(), b.data(), c.data(), n, w, [&](py::ssize_t i, const double* drivers) {
        int failed = -1;
        s[i] = k_.evaluate_driven_double(p.data(), times[static_cast<size_t>(i)], drivers,
                                         row.data(), &failed);
        // After a failed sample a closed chain's next call starts from the kernel's start (the
        // entry's rule: a failed call's State is no assembly to continue from).
        for (py::ssize_t col = 0; col < m; ++col) out[col * n + i] = row[static_cast<size_t>(col)];
      });
    }
    return py::make_tuple(as_array ? py::object(block) : column_views(names_, block), status);
  }

  // Seconds the batch entry itself takes for the model's motion at `times`, into buffers allocated
  // beforehand, best of `repeats`: the C++ side of the Python overhead benchmark.
  double batch_entry_seconds(const Array& times, int repeats,
                             const std::map<std::string, double>& params) const {
    const std::vector<double> p = d_->parameters(params);
    const auto n = static_cast<size_t>(times.size());
    std::vector<double> out(n * static_cast<size_t>(k_.column_count));
    std::vector<int> status(n), group(n);
    py::gil_scoped_release release;
    double best = std::numeric_limits<double>::infinity();
    for (int r = 0; r < repeats; ++r) {
      const auto start = std::chrono::steady_clock::now();
      k_.evaluate_batch_double(p.data(), times.data(), static_cast<long>(n), out.data(),
                               status.data(), group.data());
      best = std::min(
          best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    return best;
  }

  // The named points at N samples of the drivers' coordinates: (N, points, 3) and status.
  py::tuple point_positions(const Array& q, const std::map<std::string, double>& params) const {
    if (!k_.point_positions_batch_double)
      throw py::type_error("point_positions: the kernel of '" + std::string(k_.model) +
                           "' has none (planar kernels do not)");
    const std::vector<double> p = d_->parameters(params);
    const auto w = static_cast<py::ssize_t>(k_.driver_count);
    const py::ssize_t n = rows_of(q, w);
    // The entry reads driver k of sample i at k n + i: the transpose of q.
    std::vector<double> qt(static_cast<size_t>(n * w));
    for (py::ssize_t i = 0; i < n; ++i)
      for (py::ssize_t k = 0; k < w; ++k) qt[static_cast<size_t>(k * n + i)] = q.data()[i * w + k];
    const auto points = static_cast<py::ssize_t>(k_.point_count);
    py::array_t<double> block({points, py::ssize_t{3}, n});
    IntArray status(n);
    {
      py::gil_scoped_release release;
      k_.point_positions_batch_double(p.data(), qt.data(), static_cast<long>(n),
                                      block.mutable_data(), status.mutable_data());
    }
    // (point, axis, sample) -> (sample, point, axis) as a view.
    return py::make_tuple(block.attr("transpose")(2, 0, 1), status);
  }

  // M (N, n, n) and h (N, n) in the drivers' coordinates at (q, qd), and status.
  py::tuple mass_bias(const Array& q, const std::optional<Array>& qd, const py::object& t,
                      const std::map<std::string, double>& params) const {
    if (!k_.mass_bias_double)
      throw py::type_error("the kernel of '" + std::string(k_.model) + "' has no mass_bias entry");
    const std::vector<double> p = d_->parameters(params);
    const auto w = static_cast<py::ssize_t>(k_.driver_count);
    const py::ssize_t n = rows_of(q, w);
    const Array b = samples_of(qd, "qd", n, w);
    const std::vector<double> times = times_of(t, n);
    py::array_t<double> M({n, w, w}), h({n, w});
    IntArray status(n);
    {
      py::gil_scoped_release release;
      each_sample(q.data(), b.data(), nullptr, n, w, [&](py::ssize_t i, const double* drivers) {
        int failed = -1;
        status.mutable_data()[i] =
            k_.mass_bias_double(p.data(), times[static_cast<size_t>(i)], drivers,
                                M.mutable_data() + i * w * w, h.mutable_data() + i * w, &failed);
      });
    }
    return py::make_tuple(M, h, status);
  }

  // qdd (N, n) under `effort` (N, n) at (q, qd), and status (qdd is NaN where it is not 0).
  py::tuple forward_dynamics(const Array& q, const Array& effort, const std::optional<Array>& qd,
                             const py::object& t,
                             const std::map<std::string, double>& params) const {
    if (!k_.forward_dynamics_double)
      throw py::type_error("the kernel of '" + std::string(k_.model) +
                           "' has no forward_dynamics entry");
    const std::vector<double> p = d_->parameters(params);
    const auto w = static_cast<py::ssize_t>(k_.driver_count);
    const py::ssize_t n = rows_of(q, w);
    const Array b = samples_of(qd, "qd", n, w), e = samples_of(effort, "effort", n, w);
    const std::vector<double> times = times_of(t, n);
    py::array_t<double> qdd({n, w});
    IntArray status(n);
    {
      py::gil_scoped_release release;
      each_sample(q.data(), b.data(), nullptr, n, w, [&](py::ssize_t i, const double* drivers) {
        int failed = -1;
        double* out = qdd.mutable_data() + i * w;
        const int s = k_.forward_dynamics_double(p.data(), times[static_cast<size_t>(i)], drivers,
                                                 e.data() + i * w, out, &failed);
        if (s != 0) std::fill(out, out + w, std::numeric_limits<double>::quiet_NaN());
        status.mutable_data()[i] = s;
      });
    }
    return py::make_tuple(qdd, status);
  }

  // The Newton-Euler system at N driver motions (or the model's motion at times t, q absent):
  // A (N, ne_rows, ne_size), b (N, ne_rows) and status.
  py::tuple ne_system(const std::optional<Array>& q, const std::optional<Array>& qd,
                      const std::optional<Array>& qdd, const py::object& t,
                      const std::map<std::string, double>& params) const {
    if (!k_.ne_system_double)
      throw py::type_error("the kernel of '" + std::string(k_.model) + "' has no ne_system entry");
    const auto rows = static_cast<py::ssize_t>(k_.ne_rows),
               size = static_cast<py::ssize_t>(k_.ne_size);
    return driven(
        q, qd, qdd, t, params, {rows * size, rows},
        [&](const double* p, double time, const double* drivers, double* const* out, int* failed) {
          return k_.ne_system_double(p, time, drivers, out[0], out[1], failed);
        },
        {{rows, size}, {rows}});
  }

  // The screw Jacobians at N driver coordinates (or the model's motion at times t): dicts name ->
  // (N, 6, drivers) for the bodies and (N, 3, drivers) for the named points, and status.
  py::tuple jacobians(const std::optional<Array>& q, const py::object& t,
                      const std::map<std::string, double>& params) const {
    if (!k_.jacobians_double)
      throw py::type_error("jacobians: the kernel of '" + std::string(k_.model) +
                           "' has none (planar kernels do not)");
    py::ssize_t total = 0;
    for (int j = 0; j < k_.jacobian_count; ++j) total += k_.jacobian_rows[j];
    const auto w = static_cast<py::ssize_t>(k_.jacobian_columns);
    const py::tuple r =
        driven(q, std::nullopt, std::nullopt, t, params, {std::max<py::ssize_t>(total * w, 1)},
               [&](const double* p, double time, const double* drivers, double* const* out,
                   int* failed) { return k_.jacobians_double(p, time, drivers, out[0], failed); },
               {{std::max<py::ssize_t>(total * w, 1)}});
    std::vector<std::pair<std::string, int>> names;
    for (int j = 0; j < k_.jacobian_count; ++j)
      names.emplace_back(k_.jacobian_names[j], k_.jacobian_rows[j]);
    return split_jacobians(names, r[0].cast<py::array_t<double>>(), w, r[1]);
  }

  const Description& description() const { return *d_; }
  const CompiledKernel& compiled() const { return k_; }

 private:
  // f(parameters, t, drivers, outputs, &failed) per sample, at the drivers' (q, qd, qdd) or, q
  // absent, at the model's own motion at times t (null drivers); outputs per sample of the given
  // sizes, returned as arrays of shape (N, shapes[k]...) with the status array last. A failed
  // sample's outputs are zeros. The GIL is released while it runs.
  template <class F>
  py::tuple driven(const std::optional<Array>& q, const std::optional<Array>& qd,
                   const std::optional<Array>& qdd, const py::object& t,
                   const std::map<std::string, double>& params,
                   const std::vector<py::ssize_t>& sizes, F&& f,
                   const std::vector<std::vector<py::ssize_t>>& shapes) const {
    const std::vector<double> p = d_->parameters(params);
    const auto w = static_cast<py::ssize_t>(k_.driver_count);
    py::ssize_t n = 0;
    std::optional<Array> a, b, c;
    std::vector<double> times;
    if (q) {
      n = rows_of(*q, w);
      a = *q;
      b = samples_of(qd, "qd", n, w);
      c = samples_of(qdd, "qdd", n, w);
      times = times_of(t, n);
    } else {
      if (qd || qdd) throw py::value_error("qd and qdd need q");
      if (t.is_none()) throw py::value_error("give q (driver values) or t (the model's motion)");
      const Array at = t.cast<Array>();
      if (at.ndim() != 1) throw py::value_error("t must be a 1-D array of times");
      n = at.shape(0);
      times.assign(at.data(), at.data() + n);
    }
    std::vector<py::array_t<double>> outs;
    for (const std::vector<py::ssize_t>& shape : shapes) {
      std::vector<py::ssize_t> full{n};
      full.insert(full.end(), shape.begin(), shape.end());
      outs.emplace_back(full);
    }
    IntArray status(n);
    {
      py::gil_scoped_release release;
      std::vector<double*> out(outs.size());
      const auto run_one = [&](py::ssize_t i, const double* drivers) {
        for (size_t k = 0; k < outs.size(); ++k) out[k] = outs[k].mutable_data() + i * sizes[k];
        int failed = -1;
        const int s = f(p.data(), times[static_cast<size_t>(i)], drivers, out.data(), &failed);
        if (s != 0)
          for (size_t k = 0; k < outs.size(); ++k) std::fill(out[k], out[k] + sizes[k], 0.0);
        status.mutable_data()[i] = s;
      };
      if (q)
        each_sample(a->data(), b->data(), c->data(), n, w, run_one);
      else
        for (py::ssize_t i = 0; i < n; ++i) run_one(i, nullptr);
    }
    py::tuple result(outs.size() + 1);
    for (size_t k = 0; k < outs.size(); ++k) result[k] = outs[k];
    result[outs.size()] = status;
    return result;
  }

  std::shared_ptr<const Description> d_;
  const CompiledKernel& k_;
  std::vector<std::string> names_;  // column_names
};

// The numeric reference solver at given driver motions, sample after sample as the command
// line's simulation places it (runtime/analysis/simulate.cpp): each sample continues from the
// last (the first from the assembly at the sweep's t0), the drivers walked to it in steps of at
// most 0.02; a sample the solver cannot place fails, and the next starts from the assembly.
class NumericAt {
 public:
  NumericAt(const Description& d, const std::vector<double>& parameters) : d_(d) {
    if (d.spatial) {
      space_ = std::make_unique<spatial::SpatialSolver>(d.space, parameters);
      groups_ = spatial::spatial_driver_groups(*space_);
      t0_ = spatial::default_spatial_sweep(d.space, parameters).t0;
    } else {
      planar_ = std::make_unique<numeric::ReferenceSolver>(d.planar, parameters);
      subs_ = d.planar.substitutions(parameters);
      t0_ = default_sweep(d.planar, parameters).t0;
    }
  }
  const spatial::SpatialSolver& space() const { return *space_; }
  const spatial::SpatialState& state() const { return state_; }
  const numeric::ReferenceSolver& planar() const { return *planar_; }
  const std::vector<spatial::SpatialDriverGroup>& groups() const { return groups_; }

  // True when the solver is placed at (q, qd, qdd) per driver (model order) at time t.
  bool place(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
             const Eigen::VectorXd& qdd) {
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(q.size());
    const bool first = !placed_;
    const Eigen::VectorXd from = first ? own_motion(t0_) : last_q_;
    const double walk_t = first ? t0_ : last_t_;
    const double span = q.size() ? (q - from).cwiseAbs().maxCoeff() : 0;
    const int pieces = std::max(1, static_cast<int>(std::ceil(span / 0.02)));
    if (first && !d_.spatial) {
      planar_->set_driver_motion(from, zero, zero);
      planar_->assemble(t0_);
    }
    // The drivers walked from the last sample (or the assembly) at rest, so that a far sample
    // keeps the branch; the first spatial solve is the assembly itself.
    for (int k = first && d_.spatial ? 0 : 1; k < pieces; ++k)
      if (!solve(walk_t, from + (q - from) * k / pieces, zero, zero)) return placed_ = false;
    placed_ = solve(t, q, qd, qdd);
    last_q_ = q;
    last_t_ = t;
    return placed_;
  }

  // The drivers' own motion at t (values, model order).
  Eigen::VectorXd own_motion(double t) const {
    const auto n = static_cast<Eigen::Index>(d_.drivers.size());
    Eigen::VectorXd q(n);
    if (d_.spatial) {
      Eigen::VectorXd qp, qpd, qpdd;
      space_->primary_motion(t, qp, qpd, qpdd);
      for (size_t g = 0; g < groups_.size(); ++g)
        q[static_cast<Eigen::Index>(g)] = qp[groups_[g].primary] + groups_[g].offset;
      return q;
    }
    GiNaC::exmap at = subs_;
    at[d_.planar.t] = t;
    for (Eigen::Index k = 0; k < n; ++k)
      q[k] = GiNaC::ex_to<GiNaC::numeric>(
                 GiNaC::evalf(d_.planar.drivers[static_cast<size_t>(k)].value.ex.subs(at)))
                 .to_double();
    return q;
  }

 private:
  bool solve(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
             const Eigen::VectorXd& qdd) {
    try {
      if (!d_.spatial) {
        planar_->set_driver_motion(q, qd, qdd);
        return planar_->solve(t, row_) == numeric::Status::ok;
      }
      Eigen::VectorXd qp(q.size()), qpd(q.size()), qpdd(q.size());
      for (size_t g = 0; g < groups_.size(); ++g) {
        const auto i = static_cast<Eigen::Index>(g);
        qp[groups_[g].primary] = q[i] - groups_[g].offset;
        qpd[groups_[g].primary] = qd[i];
        qpdd[groups_[g].primary] = qdd[i];
      }
      space_->solve(t, qp, qpd, qpdd, state_);
      return true;
    } catch (const std::exception&) {
      state_.assembled = false;
      return false;
    }
  }

  const Description& d_;
  std::unique_ptr<spatial::SpatialSolver> space_;
  std::vector<spatial::SpatialDriverGroup> groups_;
  spatial::SpatialState state_;
  std::unique_ptr<numeric::ReferenceSolver> planar_;
  GiNaC::exmap subs_;
  std::vector<double> row_;
  double t0_ = 0, last_t_ = 0;
  Eigen::VectorXd last_q_;
  bool placed_ = false;
};

// Driver motions (q, qd, qdd: N x drivers; absent rates zero) as f(i, q, qd, qdd) per sample.
template <class F>
void each_motion(const Description& d, const Array& q, const std::optional<Array>& qd,
                 const std::optional<Array>& qdd, F&& f) {
  const auto w = static_cast<py::ssize_t>(d.drivers.size());
  const py::ssize_t n = rows_of(q, w);
  const Array b = samples_of(qd, "qd", n, w), c = samples_of(qdd, "qdd", n, w);
  const auto row = [w](const Array& a, py::ssize_t i) {
    return Eigen::Map<const Eigen::VectorXd>(a.data() + i * w, w);
  };
  for (py::ssize_t i = 0; i < n; ++i) f(i, row(q, i), row(b, i), row(c, i));
}

class Solver {
 public:
  explicit Solver(std::shared_ptr<const Description> d) : d_(std::move(d)) {}
  py::dict sweep(const SweepRequest& r) const { return run(*d_, nullptr, r); }
  const Description& description() const { return *d_; }

  std::vector<std::string> ne_unknowns() const {
    NumericAt at(*d_, d_->defaults);
    if (!d_->spatial) return at.planar().ne_unknowns();
    // The spatial system's unknowns (spatial_dynamics.hpp): per joint its force and moment at
    // the joint point, then each driven coordinate's effort (driver order).
    std::vector<std::string> names;
    for (const SpatialJoint& j : d_->space.joints)
      if (!j.is_virtual)
        for (const char* c : {"fx", "fy", "fz", "mx", "my", "mz"})
          names.push_back(j.name + "." + c);
    for (const std::string& driver : d_->drivers) names.push_back(driver + ".effort");
    return names;
  }

  // The numeric Newton-Euler system (planar: reference_solver.hpp's, moments about the centres of
  // mass; spatial: spatial_dynamics.hpp's, the kernels' own form) at N driver motions.
  py::tuple ne_system(const Array& q, const std::optional<Array>& qd,
                      const std::optional<Array>& qdd, const py::object& t,
                      const std::map<std::string, double>& params) const {
    NumericAt at(*d_, d_->parameters(params));
    const py::ssize_t n = rows_of(q, static_cast<py::ssize_t>(d_->drivers.size()));
    const std::vector<double> times = times_of(t, n);
    std::vector<Eigen::MatrixXd> matrices(static_cast<size_t>(n));
    std::vector<Eigen::VectorXd> vectors(static_cast<size_t>(n));
    IntArray status(n);
    py::ssize_t rows = 0, size = 0;
    each_motion(*d_, q, qd, qdd, [&](py::ssize_t i, const auto& a, const auto& b, const auto& c) {
      const auto k = static_cast<size_t>(i);
      status.mutable_data()[i] = at.place(times[k], a, b, c) ? 0 : 1;
      if (status.data()[i] != 0) return;
      if (d_->spatial) {
        const spatial::NewtonEulerSystem system =
            spatial::newton_euler_system(at.space(), at.state());
        matrices[k] = system.A, vectors[k] = system.b;
      } else {
        matrices[k] = at.planar().ne_matrix(), vectors[k] = at.planar().ne_rhs();
      }
      rows = matrices[k].rows(), size = matrices[k].cols();
    });
    py::array_t<double> A({n, rows, size}), b({n, rows});
    std::fill(A.mutable_data(), A.mutable_data() + A.size(), 0.0);
    std::fill(b.mutable_data(), b.mutable_data() + b.size(), 0.0);
    for (py::ssize_t i = 0; i < n; ++i) {
      const auto k = static_cast<size_t>(i);
      if (status.data()[i] != 0 || matrices[k].rows() != rows) continue;
      for (py::ssize_t r = 0; r < rows; ++r) {
        b.mutable_data()[i * rows + r] = vectors[k][r];
        for (py::ssize_t col = 0; col < size; ++col)
          A.mutable_data()[(i * rows + r) * size + col] = matrices[k](r, col);
      }
    }
    return py::make_tuple(A, b, status);
  }

  // The screw Jacobians of the kernel's bodies and points (the same names: `kernel: {jacobians:
  // ...}`), columns in driver order, at N driver coordinates.
  py::tuple jacobians(const Array& q, const py::object& t,
                      const std::map<std::string, double>& params) const {
    if (!d_->spatial)
      throw py::type_error("jacobians: '" + d_->path + "' is planar (no screw Jacobians)");
    const SpatialModel& m = d_->space;
    NumericAt at(*d_, d_->parameters(params));
    std::vector<std::pair<std::string, int>> names;
    std::vector<int> body_of;
    std::vector<spatial::V3> local;
    for (size_t b = 0; b < m.bodies.size(); ++b)
      if (!m.bodies[b].ground && !m.bodies[b].is_virtual && m.emits_jacobian(m.bodies[b].name))
        names.emplace_back(m.bodies[b].name, 6), body_of.push_back(static_cast<int>(b)),
            local.push_back(spatial::V3{0, 0, 0});
    for (const auto& [point, body] : m.named_points()) {
      const SpatialBody& owner = m.bodies[static_cast<size_t>(body)];
      if (owner.ground || !m.emits_jacobian(point)) continue;
      names.emplace_back(point, 3), body_of.push_back(body);
      for (const SpatialPoint& p : owner.points)
        if (p.name == point)
          local.push_back(at.space().instance().points[static_cast<size_t>(
              body)][static_cast<size_t>(&p - owner.points.data())]);
    }
    const auto w = static_cast<py::ssize_t>(d_->drivers.size());
    const py::ssize_t n = rows_of(q, w);
    py::ssize_t total = 0;
    for (const auto& entry : names) total += entry.second;
    const std::vector<double> times = times_of(t, n);
    py::array_t<double> block({n, std::max<py::ssize_t>(total * w, 1)});
    std::fill(block.mutable_data(), block.mutable_data() + block.size(), 0.0);
    IntArray status(n);
    each_motion(*d_, q, std::nullopt, std::nullopt,
                [&](py::ssize_t i, const auto& a, const auto& b, const auto& c) {
                  status.mutable_data()[i] =
                      at.place(times[static_cast<size_t>(i)], a, b, c) ? 0 : 1;
                  if (status.data()[i] != 0) return;
                  double* out = block.mutable_data() + i * block.shape(1);
                  for (size_t j = 0; j < names.size(); ++j) {
                    const Eigen::MatrixXd J =
                        names[j].second == 6
                            ? at.space().body_jacobian(at.state(), body_of[j])
                            : at.space().point_jacobian(
                                  at.state(), body_of[j],
                                  at.space().point_position(at.state(), body_of[j], local[j]));
                    for (int r = 0; r < names[j].second; ++r)
                      for (py::ssize_t k = 0; k < w; ++k)
                        *out++ = J(r, at.groups()[static_cast<size_t>(k)].primary);
                  }
                });
    return split_jacobians(names, block, w, status);
  }

 private:
  std::shared_ptr<const Description> d_;
};

class PyModel {
 public:
  explicit PyModel(const std::string& path) : d_(read_description(path)) {}

  std::string info_json() const {
    if (!d_->spatial) return cli::model_info_json(d_->planar);
    const spatial::SpatialSolver solver(d_->space, {});
    return cli::spatial_model_info_json(d_->space, solver);
  }

  Kernel kernel() const {
    const CompiledKernel* k = nullptr;
    {
      py::gil_scoped_release release;  // a first use may build it (seconds)
      k = d_->spatial ? &ondemand::kernel_for(d_->space) : &generated_kernel(d_->planar);
    }
    return Kernel(d_, *k);
  }
  Solver solver() const { return Solver(d_); }

  std::vector<std::string> columns() const {
    return d_->spatial ? spatial::spatial_column_names(d_->space) : column_names(d_->planar);
  }
  py::dict parameters() const {
    py::dict out;
    for (const Parameter& p : d_->common().parameters)
      out[py::str(p.name)] =
          py::dict(py::arg("value") = p.value, py::arg("unit") = p.unit, py::arg("doc") = p.doc);
    return out;
  }
  // The `range:` of each spatial driver that has one, at the given parameters (what `mechgen
  // workspace` samples).
  py::dict driver_ranges(const std::map<std::string, double>& params) const {
    py::dict out;
    if (!d_->spatial) return out;
    const GiNaC::exmap subs = d_->space.common.substitutions(d_->parameters(params));
    for (const SpatialDriver& driver : d_->space.drivers)
      if (driver.range)
        out[py::str(driver.name)] =
            py::make_tuple(d_->space.common.evaluate(driver.range->at(0), subs),
                           d_->space.common.evaluate(driver.range->at(1), subs));
    return out;
  }
  const Description& description() const { return *d_; }

 private:
  std::shared_ptr<const Description> d_;
};

template <class T>
void add_sweep(py::class_<T>& c, const char* doc) {
  c.def(
      "sweep",
      [](const T& self, std::optional<int> samples, std::optional<double> t0,
         std::optional<double> t1, const std::map<std::string, double>& params, int threads,
         bool mass_matrix) {
        return self.sweep(SweepRequest{samples, t0, t1, params, threads, mass_matrix});
      },
      py::arg("samples") = py::none(), py::arg("t0") = py::none(), py::arg("t1") = py::none(),
      py::arg("params") = std::map<std::string, double>{}, py::arg("threads") = 0,
      py::arg("mass_matrix") = false, doc);
}

}  // namespace

}  // namespace mechgen::python

PYBIND11_MODULE(mechgen, m) {
  using namespace mechgen::python;
  namespace mg = mechgen;
  m.doc() = "mechgen: generated kinematics and dynamics kernels of mechanisms, from NumPy";
  // A description's problems as ModelError (a ValueError) whose text is FILE:LINE:COL: error: ...
  py::register_exception<mg::ModelError>(m, "ModelError", PyExc_ValueError);
  m.attr("OK") = 0;
  m.attr("UNREACHABLE") = 1;
  m.attr("SINGULAR") = 2;
  m.attr("NON_FINITE") = 3;
  m.attr("status_names") = py::make_tuple("ok", "unreachable", "singular", "non_finite");
  m.def("templates_dir", &mg::ondemand::templates_dir,
        "the templates kernels built on demand come from: <prefix>/share/mechgen/templates for an "
        "installed module, else the source tree's");

  py::class_<PyModel>(m, "Model", "A mechanism description (planar or spatial YAML)")
      .def(py::init<const std::string&>(), py::arg("path"),
           "Reads and checks the description; ModelError with FILE:LINE:COL on a problem")
      .def_property_readonly("path", [](const PyModel& s) { return s.description().path; })
      .def_property_readonly("name", [](const PyModel& s) { return s.description().common().name; })
      .def_property_readonly(
          "dimension",
          [](const PyModel& s) { return s.description().spatial ? "spatial" : "planar"; })
      .def_property_readonly("parameters", &PyModel::parameters,
                             "name -> {value (default, SI), unit, doc}")
      .def_property_readonly("drivers", [](const PyModel& s) { return s.description().drivers; })
      .def_property_readonly("columns", &PyModel::columns, "the sweep's columns")
      .def("driver_ranges", &PyModel::driver_ranges,
           py::arg("params") = std::map<std::string, double>{},
           "name -> (low, high) of the spatial drivers with a range")
      .def("info_json", &PyModel::info_json, "the text of `mechgen info --json`")
      .def(
          "info",
          [](const PyModel& s) { return py::module_::import("json").attr("loads")(s.info_json()); },
          "`mechgen info --json` as a dict")
      .def("kernel", &PyModel::kernel,
           "the generated kernel: compiled in when current, else built on demand and cached "
           "($MECHGEN_CACHE) as the command line does")
      .def("solver", &PyModel::solver, "the numeric reference solver");

  py::class_<Kernel> kernel(m, "Kernel", "A model's generated kernel");
  kernel.def_property_readonly("model", [](const Kernel& k) { return k.description().path; })
      .def_property_readonly("columns", &Kernel::columns)
      .def_property_readonly("groups", &Kernel::groups, "names of the solve groups and stages")
      .def_property_readonly("drivers", [](const Kernel& k) { return k.description().drivers; })
      .def_property_readonly("points", &Kernel::points)
      .def_property_readonly("parameter_names",
                             [](const Kernel& k) {
                               const mg::CompiledKernel& c = k.compiled();
                               return std::vector<std::string>(
                                   c.parameter_names, c.parameter_names + c.parameter_count);
                             })
      .def("evaluate", &Kernel::evaluate, py::arg("q") = py::none(), py::arg("qd") = py::none(),
           py::arg("qdd") = py::none(), py::arg("t") = py::none(),
           py::arg("params") = std::map<std::string, double>{}, py::arg("as_array") = false,
           "rows at N driver motions (q, qd, qdd: N x drivers), or at the model's motion at "
           "times t; returns (dict column -> array, status array), or with as_array the "
           "(columns x N) array itself (cheaper for a few samples)")
      .def("batch_entry_seconds", &Kernel::batch_entry_seconds, py::arg("t"),
           py::arg("repeats") = 3, py::arg("params") = std::map<std::string, double>{},
           "seconds of the C++ batch entry alone at times t (best of repeats), for benchmarks")
      .def("point_positions", &Kernel::point_positions, py::arg("q"),
           py::arg("params") = std::map<std::string, double>{},
           "named points at N x drivers coordinates: (array N x points x 3, status)")
      .def("mass_bias", &Kernel::mass_bias, py::arg("q"), py::arg("qd") = py::none(),
           py::arg("t") = py::none(), py::arg("params") = std::map<std::string, double>{},
           "effort = M qdd + h: (M N x n x n, h N x n, status)")
      .def(
          "mass_matrix",
          [](const Kernel& k, const Array& q, const std::optional<Array>& qd, const py::object& t,
             const std::map<std::string, double>& params) {
            const py::tuple r = k.mass_bias(q, qd, t, params);
            return py::make_tuple(r[0], r[2]);
          },
          py::arg("q"), py::arg("qd") = py::none(), py::arg("t") = py::none(),
          py::arg("params") = std::map<std::string, double>{}, "(M N x n x n, status)")
      .def(
          "bias",
          [](const Kernel& k, const Array& q, const std::optional<Array>& qd, const py::object& t,
             const std::map<std::string, double>& params) {
            const py::tuple r = k.mass_bias(q, qd, t, params);
            return py::make_tuple(r[1], r[2]);
          },
          py::arg("q"), py::arg("qd") = py::none(), py::arg("t") = py::none(),
          py::arg("params") = std::map<std::string, double>{}, "(h N x n, status)")
      .def_property_readonly(
          "ne_unknowns",
          [](const Kernel& k) {
            const mg::CompiledKernel& c = k.compiled();
            return std::vector<std::string>(c.ne_unknowns, c.ne_unknowns + c.ne_size);
          },
          "names of the Newton-Euler system's unknowns (ne_system's columns)")
      .def("ne_system", &Kernel::ne_system, py::arg("q") = py::none(), py::arg("qd") = py::none(),
           py::arg("qdd") = py::none(), py::arg("t") = py::none(),
           py::arg("params") = std::map<std::string, double>{},
           "the Newton-Euler system A x = b at N driver motions (q, qd, qdd: N x drivers) or at "
           "the model's motion at times t: (A N x rows x unknowns, b N x rows, status)")
      .def("jacobians", &Kernel::jacobians, py::arg("q") = py::none(), py::arg("t") = py::none(),
           py::arg("params") = std::map<std::string, double>{},
           "screw Jacobians at N x drivers coordinates or at the model's motion at times t: "
           "(bodies: name -> N x 6 x drivers, points: name -> N x 3 x drivers, status)")
      .def("forward_dynamics", &Kernel::forward_dynamics, py::arg("q"), py::arg("effort"),
           py::arg("qd") = py::none(), py::arg("t") = py::none(),
           py::arg("params") = std::map<std::string, double>{}, "(qdd N x n, status)");
  add_sweep(kernel, "the sweep of `mechgen sweep` as a dict column -> array");

  py::class_<Solver> solver(m, "Solver", "A model's numeric reference solver");
  solver.def_property_readonly("model", [](const Solver& s) { return s.description().path; })
      .def_property_readonly("ne_unknowns", &Solver::ne_unknowns,
                             "names of the Newton-Euler system's unknowns (ne_system's columns)")
      .def("ne_system", &Solver::ne_system, py::arg("q"), py::arg("qd") = py::none(),
           py::arg("qdd") = py::none(), py::arg("t") = py::none(),
           py::arg("params") = std::map<std::string, double>{},
           "the numeric Newton-Euler system A x = b at N driver motions, each sample continuing "
           "from the last: (A N x rows x unknowns, b N x rows, status)")
      .def("jacobians", &Solver::jacobians, py::arg("q"), py::arg("t") = py::none(),
           py::arg("params") = std::map<std::string, double>{},
           "screw Jacobians at N x drivers coordinates: (bodies: name -> N x 6 x drivers, "
           "points: name -> N x 3 x drivers, status)");
  add_sweep(solver, "the sweep of `mechgen sweep --solver numeric` as a dict column -> array");
}
