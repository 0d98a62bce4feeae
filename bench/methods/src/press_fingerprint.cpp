#include "eitbench/bench/methods/press_fingerprint.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include "eitbench/jacobian/error.h"

namespace eitbench {

PressFingerprint::PressFingerprint(SampleMatrix frames, Eigen::MatrixX2d positions,
                                   const FingerprintOptions& options)
    : frames_(std::move(frames)), positions_(std::move(positions)) {
  const Eigen::Index n = frames_.rows();
  if (n < 2) throw InputError("fingerprint", "frames", "needs at least 2 labelled presses");
  if (positions_.rows() != n)
    throw InputError("fingerprint", "positions", "must hold one position a frame");
  double best = std::numeric_limits<double>::infinity();
  for (int k : options.neighbours) {
    if (k < 1 || k >= n) continue;
    double sum = 0;
    for (Eigen::Index i = 0; i < n; ++i)
      sum += (mean_of_nearest(frames_.row(i).transpose(), k, static_cast<int>(i)) -
              positions_.row(i).transpose())
                 .norm();
    if (sum / double(n) < best) best = sum / double(n), k_ = k;
  }
  loo_error_ = best;
}

Eigen::Vector2d PressFingerprint::mean_of_nearest(const Eigen::VectorXd& frame, int k,
                                                  int skip) const {
  const Eigen::VectorXd d = (frames_.rowwise() - frame.transpose()).rowwise().squaredNorm();
  std::vector<int> order;
  for (int i = 0; i < static_cast<int>(d.size()); ++i)
    if (i != skip) order.push_back(i);
  k = std::min<int>(k, static_cast<int>(order.size()));
  std::partial_sort(order.begin(), order.begin() + k, order.end(),
                    [&d](int a, int b) { return d[a] < d[b] || (d[a] == d[b] && a < b); });
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (int j = 0; j < k; ++j) sum += positions_.row(order[j]).transpose();
  return sum / double(k);
}

Eigen::Vector2d PressFingerprint::locate(const Eigen::VectorXd& frame) const {
  if (frame.size() != frames_.cols())
    throw InputError("fingerprint", "frame",
                     "has " + std::to_string(frame.size()) + " values, the labelled frames " +
                         std::to_string(frames_.cols()));
  return mean_of_nearest(frame, k_, -1);
}

}  // namespace eitbench
