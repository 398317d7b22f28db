// The spatial benchmarks (bench/spatial_bench.cpp), registered by mechgen_bench's main.
#pragma once

namespace mechgen::bench {

// leg6/numeric and leg6/kdl: one sample = forward kinematics of the foot, its Jacobian and the
// inverse dynamics (every joint torque), at pre-drawn random configurations, velocities and
// accelerations. Aborts before timing when the two disagree on a torque by more than 1e-12.
void register_spatial_benchmarks();

}  // namespace mechgen::bench
