// Mass shorthands for links that are not one bar: several bars between the body's points (a
// ternary link built from bars), or a flat polygonal plate between them. Mass, centre of mass and
// inertia about it are expressions of the points and the section, so they follow --set of a
// length, a thickness or a density.
#pragma once

#include <ginac/ginac.h>

#include <vector>

namespace mechgen {

struct PlanarMass {
  GiNaC::ex mass, com_x, com_y, inertia;  // inertia about the centre of mass, normal to the plane
};

struct PointEx {
  GiNaC::ex x, y;
};

// Bars between the given pairs of points, each of width w (in the plane), thickness t and
// density rho: each bar m = rho w t L, I = m (L^2 + w^2) / 12 about its middle; combined by the
// parallel-axis theorem.
PlanarMass bars_mass(const std::vector<std::pair<PointEx, PointEx>>& bars, const GiNaC::ex& width,
                     const GiNaC::ex& thickness, const GiNaC::ex& density);

// A plate of thickness t and density rho bounded by the polygon through `vertices` in order
// (either orientation, not self-intersecting): area, centroid and polar second moment from the
// shoelace sums. `orientation` is +1 for counter-clockwise vertices, -1 for clockwise ones (the
// sign of the signed area at the default parameters).
PlanarMass plate_mass(const std::vector<PointEx>& vertices, const GiNaC::ex& thickness,
                      const GiNaC::ex& density, int orientation);

// The signed area of the polygon (positive when counter-clockwise).
GiNaC::ex signed_area(const std::vector<PointEx>& vertices);

}  // namespace mechgen
