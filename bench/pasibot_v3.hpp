// PASIBOT's generated evaluate<double> and kinematics<double> compiled for x86-64-v3 (AVX2, FMA:
// VEX three-operand code and fused multiply-adds), as a user who builds the plain C++17 kernel
// with -march=x86-64-v3 or -march=native on such a machine gets them; mechgen_bench's
// pasibot/generated_v3, kinematics_v3 and generated_batch_v3. Only call them when available() is
// true.
#pragma once

#include <cstddef>

namespace mechgen::bench::v3 {

// True when this build compiled the x86-64-v3 kernel and the processor runs AVX2 and FMA.
bool available();

// The kernel's parameters (model order) and the sample times to cycle through.
void prepare(const double* parameters, const double* times, std::size_t count);

// The next sample through evaluate_batch, computed in blocks of batch_block samples (one block
// every batch_block calls); false when it fails.
inline constexpr std::size_t batch_block = 64;
bool next_batch();
// Output column `column` of the i-th sample of the last block next_batch computed.
double batch_output(int column, std::size_t i);

// The next sample (evaluate, or kinematics only); false when it fails. Its driver effort (after
// evaluate) goes to *effort, for the sanity check against the baseline kernel.
bool next(bool kinematics_only, double* effort);

}  // namespace mechgen::bench::v3
