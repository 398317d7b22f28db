// Monte Carlo workspace of a spatial model (seed 002): the drivers' coordinates drawn uniformly
// from their ranges, the model solved at each draw, a named point's positions collected. Extents,
// density images of the sagittal (X-Z) and frontal (Y-Z) projections, and the seed's two
// workspace figures read off the sagittal image: the longest horizontal chord (stride) and the
// longest vertical chord (lift) through occupied cells.
// Every sample is placed by a generated kernel's positions-only batch entry (CompiledKernel::
// point_positions_batch_double: closed-form groups, no rates or forces) when one is given, else
// solved by the numeric reference solver from the model's t0 state (spatial/driven_solve.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "model/spatial_model.hpp"
#include "sweep/compiled_kernel.hpp"

namespace mechgen::analysis {

struct WorkspaceOptions {
  long samples = 100000;
  std::uint64_t seed = 1;
  int threads = 0;                 // 0: every core
  std::string point;               // empty: the model's last named point
  std::vector<double> parameters;  // empty: the defaults
  int bins = 160;                  // cells along the longer side of each image
  double chord_cell = 0.01;        // m: cells of the grid the chords are read on
  // Drivers held at one coordinate value instead of sampled (name, value).
  std::vector<std::pair<std::string, double>> fixed;
  // The model's generated kernel (its description's fingerprint): samples through its
  // positions-only batch entry. Null: the numeric solver.
  const CompiledKernel* kernel = nullptr;
};

// Occupancy of one projection: counts per cell, row-major from (h_min, v_min).
struct Projection {
  std::string h_name, v_name;  // e.g. "X", "Z"
  int h_axis = 0, v_axis = 2;  // the ground-frame axes they are (0 = X, 1 = Y, 2 = Z)
  double h_min = 0, v_min = 0, cell = 0;
  int nh = 0, nv = 0;
  std::vector<long> counts;
  // Longest run of occupied cells along h (a horizontal chord) and along v, in metres, and where,
  // on a grid of chord_cell (coarser than the image: no holes between sparse samples).
  double chord_cell = 0;
  double h_chord = 0, h_chord_at = 0, h_chord_from = 0;
  double v_chord = 0, v_chord_at = 0, v_chord_from = 0;
};

struct WorkspaceResult {
  std::string point;
  std::vector<std::string> drivers;
  std::vector<std::array<double, 2>> ranges;  // per driver: its coordinate's range
  long samples = 0, assembled = 0;
  int threads = 1;
  bool generated = false;  // placed by the generated kernel (else the numeric solver)
  double seconds = 0, cpu_seconds = 0;
  std::array<double, 3> lo{}, hi{};  // extents of the point, ground frame
  Projection sagittal, frontal;
};

// Throws ModelError (located) for a driver without a range, a pose driver or an unknown point.
WorkspaceResult run_workspace(const SpatialModel& model, const WorkspaceOptions& options);

// The mechanism drawn over a density image: its bodies as polylines (ground frame), and the pose
// they are at, for the caption ("at its reference pose, t = 0 s").
struct Outline {
  std::vector<std::vector<std::array<double, 3>>> bodies;
  std::string pose;
};

// A density image as a self-contained SVG (cells shaded by their count on a log scale, shown by
// a colour bar from 1 sample to the densest cell's count; equal scales, metres), with the
// mechanism's outline over it (clipped to the image) when `outline` has bodies.
std::string density_svg(const Projection& p, const std::string& title, const Outline& outline = {});

// The summary as CSV rows "quantity,value,unit".
std::string workspace_csv(const WorkspaceResult& r);

}  // namespace mechgen::analysis
