#include "eitbench/bench/data/noise.h"

#include <cmath>

#include "eitbench/jacobian/random.h"

namespace eitbench {

void add_noise(SampleMatrix& frames, double snr_db, std::uint64_t seed) {
  if (std::isinf(snr_db) && snr_db > 0) return;
  for (Eigen::Index i = 0; i < frames.rows(); ++i) {
    RandomStream rng(seed, static_cast<std::uint64_t>(i));
    const double power = frames.row(i).squaredNorm() / static_cast<double>(frames.cols());
    const double sigma = std::sqrt(power / std::pow(10.0, snr_db / 10.0));
    for (Eigen::Index j = 0; j < frames.cols(); ++j) frames(i, j) += sigma * rng.normal();
  }
}

double measured_snr_db(const SampleMatrix& clean, const SampleMatrix& noisy) {
  return 10.0 * std::log10(clean.squaredNorm() / (noisy - clean).squaredNorm());
}

}  // namespace eitbench
