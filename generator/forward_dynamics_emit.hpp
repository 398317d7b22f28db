// The forward-dynamics entries of every generated kernel (issue 22), planar and spatial:
// mass_bias / mass_matrix / bias / mass_solve / forward_dynamics in <model>.hpp through
// templates/forward_dynamics.hpp.in, and the runtime's CompiledKernel::mass_bias_double and
// forward_dynamics_double in <model>_entry.cpp through templates/forward_dynamics_entry.cpp.in.
//
// M and h come from the kernel's own inverse dynamics (evaluate()), which is linear in the driver
// accelerations: h is the efforts at q'' = 0, column b of M the efforts at q'' = e_b minus h, at
// the same q, q' and t. So they are exact to rounding, whatever the kernel's closed forms, and cost
// no new derivation. q'' = M^-1 (effort - h) is a fixed-order LDL^T written out as straight-line
// code (no pivoting at run time).
#pragma once

#include <string>
#include <vector>

namespace mechgen::gen {

// The driver coordinates in model order: `in.<name>_dd` is the acceleration input and
// `s.drivers.<name>.effort` the effort output of coordinate <name>.
struct ForwardDynamicsText {
  std::string header;  // the value of {{forward_dynamics}} in kernel.hpp.in / spatial_kernel.hpp.in
  std::string entry;   // the value of {{forward_dynamics_entry}} in the entry templates
};

// `driven_inputs`: the entry's lines that read (q, qd, qdd) per coordinate from `drivers[]`
// into `in`; `entry_state`: the entry's declaration of `State<double> s` (the warm start a
// closed chain's evaluation starts from).
ForwardDynamicsText emit_forward_dynamics(const std::string& templates_dir,
                                          const std::vector<std::string>& coordinates,
                                          const std::string& driven_inputs,
                                          const std::string& entry_state);

}  // namespace mechgen::gen
