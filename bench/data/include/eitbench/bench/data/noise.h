#pragma once
// Additive white Gaussian noise at a signal-to-noise ratio (docs/conventions.md): for each frame,
// the noise variance is the mean power of that frame's values divided by 10^(SNR/10).
#include <cstdint>

#include "eitbench/jacobian/sample_matrix.h"

namespace eitbench {

// Adds noise to every row; row i draws from a generator seeded by (seed, i), so the result does
// not depend on threads or on which other rows are present. An infinite SNR adds nothing.
void add_noise(SampleMatrix& frames, double snr_db, std::uint64_t seed);

// 10 log10 (sum of signal power / sum of noise power) over all rows.
double measured_snr_db(const SampleMatrix& clean, const SampleMatrix& noisy);

}  // namespace eitbench
