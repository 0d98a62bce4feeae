#pragma once
// The frame of recorded press positions: how a robot's or a probe's coordinates lie on the
// sensor's electrodes. The positions of a labelled set of presses are turned (and mirrored) until
// the changes the linear model predicts for them best match the measured ones, by the mean cosine
// between the two over the presses: a fit to the responses that needs neither the instrument's
// gain nor the touch's contrast. Part of fitting a sensor to real presses (docs/data.md).
#include <Eigen/Core>
#include <vector>

#include "eitbench/jacobian/sample_matrix.h"
#include "eitbench/solvers/linear_problem.h"

namespace eitbench {

struct PressFrameOptions {
  double step_degrees = 1;    // the turns tried: 0, step, 2 step, ... below 360
  double touch_radius = 0.1;  // each press drawn as a disc of this radius (x R), contrast 1
  void validate() const;      // InputError("PressFrameOptions", field)
};

struct PressFrame {
  // The recorded positions in the model's frame are R(rotate_degrees) M p, M the mirror y -> -y
  // when `mirror` (electrodes numbered the other way), R a counter-clockwise turn.
  double rotate_degrees = 0;
  bool mirror = false;
  double cosine = 0;  // the mean cosine at the best turn
  // The best mean cosine of the other handedness, and of turns at least 45 degrees from the best
  // (same handedness): how clearly the best stands out.
  double other_mirror_cosine = 0, other_turn_cosine = 0;
};

// differences: N x m measured changes (the problem's inputs); positions: N x 2, each press's
// recorded centre in the model's unit. A press is a conductivity decrease (positive on the label
// scale). InputError for shapes that do not match, fewer than 3 presses, or values not finite.
PressFrame fit_press_frame(const LinearProblem& problem, const SampleMatrix& differences,
                           const Eigen::MatrixX2d& positions,
                           const PressFrameOptions& options = {});

}  // namespace eitbench
