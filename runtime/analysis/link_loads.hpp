// Axial force N, shear force V and bending moment M along every bar of a mechanism, and the
// stresses they cause in its cross-section (the seed's "strain-stress data in all links").
//
// Rules (docs/link_loads.md):
//  - Axis. A body whose mass is a bar (`mass: {bar: [P, Q], ...}`) is a beam along P -> Q; any
//    other body along the two of its points farthest apart (the first such pair in file order). s
//    runs from the first axis point; e the unit axis, n = e turned +90 degrees.
//  - Loads. Every load of the body's free body (analysis/free_body.hpp) is projected onto the
//    axis at s = (p - a).e; a point off the axis (ternary links with a bend) adds the couple of its
//    force about its projection, as a rigid arm would. A driver's torque and a prismatic joint's
//    moment act at the joint point; a torque element at the centre of mass.
//  - Weight and inertia. For a bar mass (centre of mass at the middle of the axis) they are
//    distributed along [0, L]: uniform m (g - a_G) / L, plus the linear loads of the rotation, the
//    centripetal m w^2 (s - L/2) / L along e and -12 I al (s - L/2) / L^3 along n (whose moment
//    is exactly -I al). Any other body carries them lumped at its centre of mass's projection.
//  - Sign convention at a cut s, for the part [s_min, s] and the loads on it: N = -(their axial
//    sum) (tension positive), V = their transverse sum, M = sum of (s - s_i) F_t,i - C_i, so that
//    dM/ds = V and a simply supported bar under its weight has M > 0 (sagging).
//  - Stresses. sigma = |N| / A + |M| c / I at the extreme fibre; tau = k |V| / A with k = 1.5 at
//    the neutral axis of a rectangle, 1 (the mean) for a general section. The safety factor is
//    yield / max(sigma, sqrt(3) tau) (von Mises with the larger of the two alone, as they peak
//    at different fibres).
//  - Buckling. Euler's load of a pinned-pinned bar over its axis length L (the end pins; a
//    ternary link's middle pin is not counted as a support), P_cr = pi^2 E I_min / L^2 with the
//    smaller second moment of the section (a rectangle w x t: min(t w^3, w t^3) / 12, out of the
//    plane for a thin bar; a general section: its given I, the only one known). Its safety factor
//    is P_cr over the largest compression anywhere along the bar over the run (conservative:
//    the axial force varies along a bar under its weight and inertia).
#pragma once

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

#include "analysis/free_body.hpp"
#include "model/model.hpp"

namespace mechgen::analysis {

struct SectionProperties {
  std::string text;             // "rectangle 20 x 5 mm (bar mass)", for reports
  double area = 0;              // m^2
  double inertia = 0;           // m^4, about the axis normal to the plane
  double fibre = 0;             // m, neutral axis to the extreme fibre
  double shear_peak = 1;        // tau_max = shear_peak * V / A
  double yield = 0;             // Pa; NaN when the model gives none
  double buckling_inertia = 0;  // m^4, the smaller second moment (see Buckling above)
  double modulus = 0;           // Pa, Young's modulus; NaN when the model gives none
};

// One bar's axis and how its mass is treated.
struct BarAxis {
  int body = -1;
  std::string from, to;      // axis points
  bool distributed = false;  // weight and inertia as line loads (bar mass) or lumped
};

// The axis rule above; nullopt for a body without two distinct points (or a zero-length bar).
std::optional<BarAxis> bar_axis(const Model& model, int body, const GiNaC::exmap& subs);

// The section of a body: its `section:`, else its bar mass's width x thickness; nullopt when it
// has neither. `yield_override` (Pa, when given) replaces the model's material yield strength.
// Young's modulus: the section's own, else the model's material's, else NaN.
std::optional<SectionProperties> section_properties(const Model& model, int body,
                                                    const GiNaC::exmap& subs,
                                                    std::optional<double> yield_override = {});

struct BeamStation {
  double s = 0;                       // m from the first axis point
  double n = 0, v = 0, m = 0;         // N, N, N m at the cut just past s (loads at s included)
  double n_before = 0, v_before = 0;  // just before s (the jump of a concentrated load)
};

struct BeamLoads {
  double length = 0;                  // |a b|
  double s_min = 0, s_max = 0;        // extent of the loads (a point beyond an axis end widens it)
  std::vector<BeamStation> stations;  // ascending s: a uniform grid and every load point
  // What is left at the far end past every load: (N, V, M) must vanish for a body in equilibrium.
  double end_n = 0, end_v = 0, end_m = 0;
};

// N, V, M along the bar with `intervals` uniform intervals plus the load points. `a`, `b`: the
// axis points in the ground frame at this sample.
BeamLoads beam_loads(const FreeBody& body, const BarAxis& axis, const Eigen::Vector2d& a,
                     const Eigen::Vector2d& b, const Eigen::Vector2d& gravity, int intervals = 64);

// The largest magnitudes over a bar and a run, with where and when.
struct Peak {
  double value = 0;  // signed value of largest magnitude (stresses: >= 0)
  double t = 0, s = 0;
};

struct LinkResult {
  int body = -1;
  std::string name;
  BarAxis axis;
  SectionProperties section;
  double length = 0;
  Peak n, v, m, sigma, tau;
  double safety = 0;           // yield / max(sigma, sqrt(3) tau); NaN without a yield strength
  Peak compression;            // the largest compression (N <= 0) along the bar over the run
  double buckling_load = 0;    // N, Euler's P_cr; NaN without Young's modulus
  double buckling_safety = 0;  // P_cr / |compression|; infinite when never compressed
  // Per sample: the largest |N|, |V|, |M| and sigma over the bar (for plots over time).
  std::vector<double> n_t, v_t, m_t, sigma_t;
};

struct LinkLoadReport {
  std::vector<double> t;
  std::vector<LinkResult> links;     // bodies with an axis and a section, body order
  std::vector<std::string> skipped;  // "l13: no section (...)"
  int critical = -1;                 // index into links: lowest safety factor (or
                                     // highest sigma without yield strengths)
  double largest_end_residual = 0;   // max over bars and samples of |end N|, |end V|
                                     // (N) and |end M| / length (N): equilibrium check
};

struct LinkLoadOptions {
  std::optional<double> yield_override;  // Pa
  int intervals = 64;
};

// N, V, M along one bar at one row of a sweep table (the diagrams of a beam). Throws
// std::invalid_argument when `link` is not a moving body with an axis.
BeamLoads link_diagram(const Model& model, const std::vector<double>& parameters,
                       const std::vector<std::string>& columns, const std::vector<double>& row,
                       const std::string& link, int intervals = 64);

// Over every row of a sweep table of `model` (columns as DESIGN.md's CSV).
LinkLoadReport link_loads(const Model& model, const std::vector<double>& parameters,
                          const std::vector<std::string>& columns,
                          const std::vector<std::vector<double>>& rows,
                          const LinkLoadOptions& options = {});

}  // namespace mechgen::analysis
