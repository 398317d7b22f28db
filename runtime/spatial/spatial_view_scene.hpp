// A spatial model's view (report/view_scene.hpp) from a table with every real body's pose (a
// spatial sweep, or `mechgen humanoid-gait`'s gait.csv): bodies from their mass shapes (a bar as
// a cylinder of its radius, a box as itself; an explicit mass as the box with its principal
// inertias, translucent; every body also as thin lines from the joint that carries it to its
// other joints and points, which is all a massless body shows), joints by type along their axes
// (revolute and helical: a short pin; prismatic and cylindrical: a barrel on the first body and
// a rod on the second; spherical: a ball; universal: a ball and a cross of both axes; fixed: a
// cube).
#pragma once

#include "report/csv_table.hpp"
#include "report/view_scene.hpp"
#include "spatial/spatial_solver.hpp"

namespace mechgen::spatial {

// Every real moving body needs B.x, B.y, B.z, B.qw, B.qx, B.qy, B.qz. Throws std::invalid_argument
// for a missing column.
report::ViewScene spatial_view_scene(const SpatialSolver& solver, const report::CsvTable& table);

}  // namespace mechgen::spatial
