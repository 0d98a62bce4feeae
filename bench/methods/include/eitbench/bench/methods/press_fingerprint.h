#pragma once
// The nearest-neighbour fingerprint: the floor that labelled presses set without any model. A
// frame's press is put at the mean position of the k labelled frames nearest to it (Euclidean
// distance between frames), k chosen by leave-one-out error on the labelled frames themselves.
#include <Eigen/Core>
#include <vector>

#include "eitbench/jacobian/sample_matrix.h"

namespace eitbench {

struct FingerprintOptions {
  std::vector<int> neighbours{1, 2, 3, 5, 8, 13};  // the k tried (those below the frame count)
};

class PressFingerprint {
 public:
  // frames: N x inputs, positions: N x 2 (x, y of each frame's press). InputError("fingerprint",
  // ...) when N < 2 or the sizes disagree.
  PressFingerprint(SampleMatrix frames, Eigen::MatrixX2d positions,
                   const FingerprintOptions& options = {});
  int neighbours() const { return k_; }
  double leave_one_out_error() const { return loo_error_; }  // mean centre error at the chosen k
  Eigen::Vector2d locate(const Eigen::VectorXd& frame) const;

 private:
  // The mean position of the k nearest frames to `frame`, skipping frame `skip` (-1: none); ties
  // go to the lower index, so the result does not depend on the order of evaluation.
  Eigen::Vector2d mean_of_nearest(const Eigen::VectorXd& frame, int k, int skip) const;

  SampleMatrix frames_;
  Eigen::MatrixX2d positions_;
  int k_ = 1;
  double loo_error_ = 0;
};

}  // namespace eitbench
