#pragma once
#include <Eigen/Core>

namespace eitbench {
// Samples (frames, images) one a row, row-major so that a sample is contiguous.
using SampleMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
}  // namespace eitbench
