// Closed-form groups of binary links with a universal and a spherical end (issue 11 item 1b): a
// link (one body, or a cylinder's barrel and rod joined by a known prismatic along the line of
// its end centres) joins a known body X to a body Y turned by one unknown revolute from a known
// body K. The distance between the end centres is the link's length (constant, or the
// cylinder's), which gives A cos q + B sin q = C for the revolute; then the universal end's two
// angles from the link's direction (two rotations about crossed axes) and the spherical end's
// three from the remaining relative rotation (x-y-z angles). rsur's RSUR loop and every circuit
// of quadruped_leg (cylinders l3, l2, l1 on the swing, the crank and the hip, then the coupler
// on the knee) are such groups. Branches from the assembly; angles unwound to the warm start.
#pragma once

#include <vector>

#include "spatial_closed_form.hpp"

namespace mechgen::gen {

bool link_loop_groups(ClosureContext& ctx, std::vector<ClosedFormGroup>& groups);

}  // namespace mechgen::gen
