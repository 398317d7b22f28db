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
#include "ondemand/kernel_resolver.hpp"
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
    {
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

  const Description& description() const { return *d_; }
  const CompiledKernel& compiled() const { return k_; }

 private:
  std::shared_ptr<const Description> d_;
  const CompiledKernel& k_;
  std::vector<std::string> names_;  // column_names
};

class Solver {
 public:
  explicit Solver(std::shared_ptr<const Description> d) : d_(std::move(d)) {}
  py::dict sweep(const SweepRequest& r) const { return run(*d_, nullptr, r); }
  const Description& description() const { return *d_; }

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
      .def("forward_dynamics", &Kernel::forward_dynamics, py::arg("q"), py::arg("effort"),
           py::arg("qd") = py::none(), py::arg("t") = py::none(),
           py::arg("params") = std::map<std::string, double>{}, "(qdd N x n, status)");
  add_sweep(kernel, "the sweep of `mechgen sweep` as a dict column -> array");

  py::class_<Solver> solver(m, "Solver", "A model's numeric reference solver");
  solver.def_property_readonly("model", [](const Solver& s) { return s.description().path; });
  add_sweep(solver, "the sweep of `mechgen sweep --solver numeric` as a dict column -> array");
}
