#include "eitbench/solvers/reconstructor.h"

namespace eitbench {

void Reconstructor::fit(const SampleMatrix&, const SampleMatrix&, const ScoreFn&) {}

SampleMatrix Reconstructor::reconstruct_all(const SampleMatrix& frames) const {
  SampleMatrix images;
  for (Eigen::Index i = 0; i < frames.rows(); ++i) {
    const Eigen::VectorXd image = reconstruct(frames.row(i).transpose());
    if (i == 0) images.resize(frames.rows(), image.size());
    images.row(i) = image.transpose();
  }
  return images;
}

}  // namespace eitbench
