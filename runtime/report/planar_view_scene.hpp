// A planar model's view (view_scene.hpp) from a sweep or walk table: bodies from their mass
// shapes (a bar as a box of its width and thickness, several bars, a plate as its extruded
// polygon, any other body as lines through its points), revolute joints as pins normal to the
// plane, prismatic joints and slots as a rail on the first body and a block or pin on the second.
// Bodies lie in alternating layers along z so overlapping links stay visible.
#pragma once

#include "model/model.hpp"
#include "report/csv_table.hpp"
#include "report/view_scene.hpp"

namespace mechgen::report {

// Every moving body needs B.x, B.y, B.th; the ground body moves when the table has its columns
// (a walk), else stays at the origin. Throws std::invalid_argument for a missing column.
ViewScene planar_view_scene(const Model& model, const std::vector<double>& parameters,
                            const CsvTable& table);

}  // namespace mechgen::report
