// Monte Carlo workspace of a spatial model (workspace.hpp).
#include "analysis/workspace.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <sstream>
#include <thread>

#include "report/svg_plot.hpp"
#include "spatial/driven_solve.hpp"
#include "spatial/spatial_solver.hpp"

namespace mechgen::analysis {

namespace {

// Counter-based uniform numbers: sample k, coordinate c gives the same draw on any thread count.
double uniform(std::uint64_t seed, std::uint64_t k, std::uint64_t c) {
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + k * 0xBF58476D1CE4E5B9ULL + c + 1;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

// The longest run of occupied cells along one direction of the grid, in cells, and where.
struct Run {
  int length = 0, line = 0, from = 0;
};
Run longest_run(const Projection& p, bool along_h) {
  Run best;
  const int lines = along_h ? p.nv : p.nh, cells = along_h ? p.nh : p.nv;
  for (int line = 0; line < lines; ++line) {
    int run = 0;
    for (int c = 0; c < cells; ++c) {
      const int h = along_h ? c : line, v = along_h ? line : c;
      run = p.counts[static_cast<size_t>(v * p.nh + h)] > 0 ? run + 1 : 0;
      if (run > best.length) best = {run, line, c - run + 1};
    }
  }
  return best;
}

Projection project(const std::vector<std::array<float, 3>>& pts, int h, int v,
                   const std::array<double, 3>& lo, const std::array<double, 3>& hi, double cell) {
  const char* names[3] = {"X", "Y", "Z"};
  Projection p;
  p.h_name = names[h], p.v_name = names[v];
  p.h_axis = h, p.v_axis = v;
  p.cell = cell;
  p.nh = std::max(1, static_cast<int>(std::ceil(
                         (hi[static_cast<size_t>(h)] - lo[static_cast<size_t>(h)]) / p.cell)));
  p.nv = std::max(1, static_cast<int>(std::ceil(
                         (hi[static_cast<size_t>(v)] - lo[static_cast<size_t>(v)]) / p.cell)));
  p.h_min = lo[static_cast<size_t>(h)], p.v_min = lo[static_cast<size_t>(v)];
  p.counts.assign(static_cast<size_t>(p.nh) * static_cast<size_t>(p.nv), 0);
  for (const auto& x : pts) {
    if (!std::isfinite(x[0])) continue;
    const int i =
        std::min(p.nh - 1, static_cast<int>((x[static_cast<size_t>(h)] - p.h_min) / p.cell));
    const int j =
        std::min(p.nv - 1, static_cast<int>((x[static_cast<size_t>(v)] - p.v_min) / p.cell));
    ++p.counts[static_cast<size_t>(j * p.nh + i)];
  }
  return p;
}

// The image at `bins` cells along its longer side; the chords on cells of chord_cell.
Projection image(const std::vector<std::array<float, 3>>& pts, int h, int v,
                 const std::array<double, 3>& lo, const std::array<double, 3>& hi, int bins,
                 double chord_cell) {
  const double span = std::max({hi[static_cast<size_t>(h)] - lo[static_cast<size_t>(h)],
                                hi[static_cast<size_t>(v)] - lo[static_cast<size_t>(v)], 1e-9});
  // Each axis spans at least a fifth of the other, centred on the samples: a leg moving in its
  // own plane (5.5e-17 m across in the frontal view) is a thin band, not a 1-cell-wide image.
  std::array<double, 3> low = lo, high = hi;
  for (const int k : {h, v}) {
    const size_t a = static_cast<size_t>(k);
    if (high[a] - low[a] >= 0.2 * span) continue;
    const double middle = 0.5 * (low[a] + high[a]);
    low[a] = middle - 0.1 * span, high[a] = middle + 0.1 * span;
  }
  Projection p = project(pts, h, v, low, high, span / bins);
  const Projection c = project(pts, h, v, low, high, chord_cell);
  const Run rh = longest_run(c, true), rv = longest_run(c, false);
  p.chord_cell = chord_cell;
  p.h_chord = rh.length * c.cell, p.h_chord_at = c.v_min + (rh.line + 0.5) * c.cell;
  p.h_chord_from = c.h_min + rh.from * c.cell;
  p.v_chord = rv.length * c.cell, p.v_chord_at = c.h_min + (rv.line + 0.5) * c.cell;
  p.v_chord_from = c.v_min + rv.from * c.cell;
  return p;
}

}  // namespace

WorkspaceResult run_workspace(const SpatialModel& model, const WorkspaceOptions& options) {
  const spatial::SpatialSolver solver(model, options.parameters);
  if (!model.pose_drivers.empty())
    throw ModelError(model.pose_drivers.front().loc,
                     "workspace samples joint drivers' ranges; pose driver '" +
                         model.pose_drivers.front().name + "' has none");
  WorkspaceResult r;
  const GiNaC::exmap subs = model.common.substitutions(solver.parameters());
  const SpatialGraph& g = solver.graph();
  std::vector<std::array<double, 2>> range(g.primary.size());
  for (size_t k = 0; k < g.primary.size(); ++k) {
    const SpatialDriver& d =
        model.drivers[static_cast<size_t>(g.columns[static_cast<size_t>(g.primary[k])].driver)];
    if (!d.range)
      throw ModelError(d.loc, "driver '" + d.name + "' has no range: give range: [min, max]");
    range[k] = {model.evaluate(d.range->at(0), subs), model.evaluate(d.range->at(1), subs)};
    for (const auto& [name, value] : options.fixed)
      if (name == d.name) range[k] = {value, value};
    r.drivers.push_back(d.name);
  }
  for (const auto& f : options.fixed)
    if (std::find(r.drivers.begin(), r.drivers.end(), f.first) == r.drivers.end())
      throw ModelError(SourceLoc{model.common.file, 0, 0}, "no driver named '" + f.first + "'");
  r.ranges = range;
  // The point: its body and body-frame position.
  const auto points = model.named_points();
  if (points.empty())
    throw ModelError(SourceLoc{model.common.file, 0, 0}, "the model names no point");
  r.point = options.point.empty() ? points.back().first : options.point;
  int body = -1;
  spatial::V3 local{};
  for (const auto& [name, b] : points)
    if (name == r.point) {
      body = b;
      const SpatialBody& sb = model.bodies[static_cast<size_t>(b)];
      for (size_t k = 0; k < sb.points.size(); ++k)
        if (sb.points[k].name == name) local = solver.instance().points[static_cast<size_t>(b)][k];
    }
  if (body < 0)
    throw ModelError(SourceLoc{model.common.file, 0, 0}, "no point named '" + r.point + "'");

  spatial::SpatialState start;
  solver.solve(model.evaluate(model.common.step.t0, subs), start);
  r.samples = std::max(0L, options.samples);
  // Single precision is plenty for the images (0.1 um at 1 m); the extents are taken in double.
  std::vector<std::array<float, 3>> pts(static_cast<size_t>(r.samples));
  const unsigned cores = std::max(1U, std::thread::hardware_concurrency());
  r.threads = options.threads > 0 ? options.threads : static_cast<int>(cores);
  std::vector<long> ok(static_cast<size_t>(r.threads), 0);
  std::vector<std::array<double, 3>> lo(static_cast<size_t>(r.threads)),
      hi(static_cast<size_t>(r.threads));
  for (int t = 0; t < r.threads; ++t) {
    lo[static_cast<size_t>(t)].fill(std::numeric_limits<double>::infinity());
    hi[static_cast<size_t>(t)].fill(-std::numeric_limits<double>::infinity());
  }
  auto keep = [&](int thread, long k, const std::array<double, 3>& x) {
    for (size_t c = 0; c < 3; ++c) {
      pts[static_cast<size_t>(k)][c] = static_cast<float>(x[c]);
      lo[static_cast<size_t>(thread)][c] = std::min(lo[static_cast<size_t>(thread)][c], x[c]);
      hi[static_cast<size_t>(thread)][c] = std::max(hi[static_cast<size_t>(thread)][c], x[c]);
    }
    ++ok[static_cast<size_t>(thread)];
  };
  auto draw = [&](long k, size_t c) {
    return range[c][0] +
           (range[c][1] - range[c][0]) * uniform(options.seed, static_cast<std::uint64_t>(k), c);
  };
  const CompiledKernel* kernel = options.kernel;
  r.generated = kernel != nullptr;
  if (kernel && !kernel->point_positions_batch_double)
    throw ModelError(SourceLoc{model.common.file, 0, 0},
                     "the generated kernel has no positions-only entry (regenerate it)");
  size_t kernel_point = 0;
  while (kernel && kernel_point < static_cast<size_t>(kernel->point_count) &&
         kernel->point_names[kernel_point] != r.point)
    ++kernel_point;
  // Blocks of samples through the generated batch entry: driver k's coordinates in q[k n + i].
  constexpr long kBlock = 1024;
  auto generated_work = [&](int thread) {
    const size_t nd = model.drivers.size();
    std::vector<double> q(nd * kBlock), out(3 * static_cast<size_t>(kernel->point_count) * kBlock);
    std::vector<int> status(kBlock);
    for (long b0 = thread * kBlock; b0 < r.samples; b0 += r.threads * kBlock) {
      const long n = std::min(kBlock, r.samples - b0);
      for (size_t c = 0; c < g.primary.size(); ++c) {
        const auto d = static_cast<size_t>(g.columns[static_cast<size_t>(g.primary[c])].driver);
        for (long i = 0; i < n; ++i)
          q[d * static_cast<size_t>(n) + static_cast<size_t>(i)] = draw(b0 + i, c);
      }
      kernel->point_positions_batch_double(solver.parameters().data(), q.data(), n, out.data(),
                                           status.data());
      for (long i = 0; i < n; ++i) {
        if (status[static_cast<size_t>(i)] != 0) {
          pts[static_cast<size_t>(b0 + i)].fill(std::numeric_limits<float>::quiet_NaN());
          continue;
        }
        std::array<double, 3> x{};
        for (size_t a = 0; a < 3; ++a)
          x[a] = out[(3 * kernel_point + a) * static_cast<size_t>(n) + static_cast<size_t>(i)];
        keep(thread, b0 + i, x);
      }
    }
  };
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t cpu0 = std::clock();
  auto numeric_work = [&](int thread) {
    Eigen::VectorXd qp(static_cast<Eigen::Index>(g.primary.size()));
    for (long k = thread; k < r.samples; k += r.threads) {
      for (size_t c = 0; c < g.primary.size(); ++c) qp[static_cast<Eigen::Index>(c)] = draw(k, c);
      spatial::SpatialState s = start;
      if (spatial::assemble_at(solver, qp, s)) {
        const spatial::V3 x = solver.point_position(s, body, local);
        keep(thread, k, {x[0], x[1], x[2]});
      } else {
        pts[static_cast<size_t>(k)].fill(std::numeric_limits<float>::quiet_NaN());
      }
    }
  };
  auto work = [&](int thread) {
    if (kernel)
      generated_work(thread);
    else
      numeric_work(thread);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < r.threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (std::thread& t : pool) t.join();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.cpu_seconds = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  for (const long n : ok) r.assembled += n;
  r.lo.fill(std::numeric_limits<double>::infinity());
  r.hi.fill(-std::numeric_limits<double>::infinity());
  for (int t = 0; t < r.threads; ++t)
    for (size_t c = 0; c < 3; ++c)
      r.lo[c] = std::min(r.lo[c], lo[static_cast<size_t>(t)][c]),
      r.hi[c] = std::max(r.hi[c], hi[static_cast<size_t>(t)][c]);
  r.sagittal = image(pts, 0, 2, r.lo, r.hi, options.bins, options.chord_cell);
  r.frontal = image(pts, 1, 2, r.lo, r.hi, options.bins, options.chord_cell);
  return r;
}

std::string density_svg(const Projection& p, const std::string& title, const Outline& outline) {
  const double scale = 560.0 / std::max(p.nh, p.nv);  // pixels per cell
  const double left = 70, top = 40, w = p.nh * scale, hgt = p.nv * scale;
  // Room for the colour bar right of the image; wide enough for the title (about 8 px a
  // character at 14 px) and the outline's caption.
  const double bar_x = left + w + 20, bar_h = std::min(hgt, 240.0);
  const std::string caption =
      outline.bodies.empty() ? "" : "grey: the mechanism " + outline.pose + " (for scale)";
  const double width = std::max({bar_x + 110, left + 8.0 * static_cast<double>(title.size()),
                                 left + 7.0 * static_cast<double>(caption.size())});
  const double height = top + hgt + 60 + (caption.empty() ? 0 : 20);
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
    << "\" viewBox=\"0 0 " << width << " " << height
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
    << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << left << "\" y=\"22\" font-size=\"14\">" << report::xml_escape(title)
    << "</text>\n";
  long most = 1;
  for (const long c : p.counts) most = std::max(most, c);
  // Shade by log count: light blue (one sample) to dark blue (the densest cell).
  const auto shade = [&](double count) {
    const double s = std::log1p(count) / std::log1p(static_cast<double>(most));
    return "rgb(" + std::to_string(static_cast<int>(200 - 190 * s)) + "," +
           std::to_string(static_cast<int>(220 - 160 * s)) + ",255)";
  };
  for (int j = 0; j < p.nv; ++j)
    for (int i = 0; i < p.nh; ++i) {
      const long c = p.counts[static_cast<size_t>(j * p.nh + i)];
      if (c == 0) continue;
      o << "<rect x=\"" << left + i * scale << "\" y=\"" << top + hgt - (j + 1) * scale
        << "\" width=\"" << scale + 0.05 << "\" height=\"" << scale + 0.05 << "\" fill=\""
        << shade(static_cast<double>(c)) << "\"/>\n";
    }
  // The colour bar: 24 bands from 1 sample (bottom) to `most` (top), log scale as the cells.
  o << "<g class=\"colour-scale\">\n";
  for (int k = 0; k < 24; ++k) {
    const double count =
        std::expm1(std::log1p(1.0) +
                   (std::log1p(static_cast<double>(most)) - std::log1p(1.0)) * (k + 0.5) / 24);
    o << "<rect x=\"" << bar_x << "\" y=\"" << top + bar_h * (1 - (k + 1) / 24.0)
      << "\" width=\"14\" height=\"" << bar_h / 24 + 0.05 << "\" fill=\"" << shade(count)
      << "\"/>\n";
  }
  o << "<rect x=\"" << bar_x << "\" y=\"" << top << "\" width=\"14\" height=\"" << bar_h
    << "\" fill=\"none\" stroke=\"black\"/>\n<text x=\"" << bar_x + 18 << "\" y=\"" << top + 10
    << "\">" << most << "</text>\n<text x=\"" << bar_x + 18 << "\" y=\"" << top + bar_h
    << "\">1</text>\n<text x=\"" << bar_x << "\" y=\"" << top + bar_h + 16
    << "\">samples</text>\n<text x=\"" << bar_x << "\" y=\"" << top + bar_h + 30
    << "\">per cell (log)</text>\n</g>\n";
  // The mechanism, clipped to the image.
  if (!outline.bodies.empty()) {
    const size_t h = static_cast<size_t>(p.h_axis), v = static_cast<size_t>(p.v_axis);
    o << "<defs><clipPath id=\"image\"><rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << w
      << "\" height=\"" << hgt << "\"/></clipPath></defs>\n<g class=\"outline\" "
      << "clip-path=\"url(#image)\" fill=\"none\" stroke=\"#555\" stroke-width=\"2\" "
      << "stroke-linejoin=\"round\">\n";
    for (const auto& body : outline.bodies) {
      o << "<polyline points=\"";
      for (size_t k = 0; k < body.size(); ++k)
        o << (k ? " " : "") << left + (body[k][h] - p.h_min) / p.cell * scale << ","
          << top + hgt - (body[k][v] - p.v_min) / p.cell * scale;
      o << "\"/>\n";
    }
    o << "</g>\n<text x=\"" << left << "\" y=\"" << top + hgt + 74 << "\" fill=\"#555\">"
      << report::xml_escape(caption) << "</text>\n";
  }
  o << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << w << "\" height=\"" << hgt
    << "\" fill=\"none\" stroke=\"black\"/>\n";
  const double h_max = p.h_min + p.nh * p.cell, v_max = p.v_min + p.nv * p.cell;
  const std::vector<double> ht = report::nice_ticks(p.h_min, h_max, 6);
  const std::vector<std::string> hl = report::tick_labels(ht);
  for (size_t k = 0; k < ht.size(); ++k) {
    const double x = left + (ht[k] - p.h_min) / p.cell * scale;
    o << "<line x1=\"" << x << "\" y1=\"" << top + hgt << "\" x2=\"" << x << "\" y2=\""
      << top + hgt + 5 << "\" stroke=\"black\"/><text x=\"" << x << "\" y=\"" << top + hgt + 18
      << "\" text-anchor=\"middle\">" << hl[k] << "</text>\n";
  }
  const std::vector<double> vt = report::nice_ticks(p.v_min, v_max, 6);
  const std::vector<std::string> vl = report::tick_labels(vt);
  for (size_t k = 0; k < vt.size(); ++k) {
    const double y = top + hgt - (vt[k] - p.v_min) / p.cell * scale;
    o << "<line x1=\"" << left - 5 << "\" y1=\"" << y << "\" x2=\"" << left << "\" y2=\"" << y
      << "\" stroke=\"black\"/><text x=\"" << left - 8 << "\" y=\"" << y + 4
      << "\" text-anchor=\"end\">" << vl[k] << "</text>\n";
  }
  o << "<text x=\"" << left + w / 2 << "\" y=\"" << top + hgt + 40 << "\" text-anchor=\"middle\">"
    << p.h_name << " [m]</text>\n<text x=\"18\" y=\"" << top + hgt / 2
    << "\" transform=\"rotate(-90 18 " << top + hgt / 2 << ")\" text-anchor=\"middle\">" << p.v_name
    << " [m]</text>\n</svg>\n";
  return o.str();
}

std::string workspace_csv(const WorkspaceResult& r) {
  std::ostringstream o;
  o.precision(9);
  o << "quantity,value,unit\n"
    << "samples," << r.samples << ",\nassembled," << r.assembled << ",\nthreads," << r.threads
    << ",\nseconds," << r.seconds << ",s\ncpu_seconds," << r.cpu_seconds << ",s\nus_per_sample,"
    << r.cpu_seconds / static_cast<double>(std::max(1L, r.samples)) * 1e6 << ",us (CPU)\n";
  for (size_t k = 0; k < r.drivers.size(); ++k)
    o << r.drivers[k] << ".min," << r.ranges[k][0] << ",\n"
      << r.drivers[k] << ".max," << r.ranges[k][1] << ",\n";
  const char* axis[3] = {"x", "y", "z"};
  for (size_t c = 0; c < 3; ++c)
    o << r.point << "." << axis[c] << ".min," << r.lo[c] << ",m\n"
      << r.point << "." << axis[c] << ".max," << r.hi[c] << ",m\n"
      << r.point << "." << axis[c] << ".extent," << r.hi[c] - r.lo[c] << ",m\n";
  const Projection& s = r.sagittal;
  o << "sagittal.chord_cell," << s.chord_cell << ",m\n"
    << "sagittal.longest_horizontal_chord," << s.h_chord << ",m\n"
    << "sagittal.longest_horizontal_chord.z," << s.h_chord_at << ",m\n"
    << "sagittal.longest_horizontal_chord.x_from," << s.h_chord_from << ",m\n"
    << "sagittal.longest_vertical_chord," << s.v_chord << ",m\n"
    << "sagittal.longest_vertical_chord.x," << s.v_chord_at << ",m\n"
    << "sagittal.longest_vertical_chord.z_from," << s.v_chord_from << ",m\n"
    << "frontal.longest_horizontal_chord," << r.frontal.h_chord << ",m\n"
    << "frontal.longest_vertical_chord," << r.frontal.v_chord << ",m\n";
  return o.str();
}

}  // namespace mechgen::analysis
