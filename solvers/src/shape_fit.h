#pragma once
// One Levenberg-Marquardt fit of K circles to a frame with Ceres (internal to solvers/): the
// frame's values as one residual block, or a block each when a robust loss must act on each,
// sharing one evaluation of the shape model per parameter point; bounds on radius and intensity;
// and a penalty that keeps each circle inside the disk.
#include <array>
#include <vector>

#include "shape_model.h"

namespace eitbench::detail {

using CircleParameters = std::array<double, kCircleParameters>;  // cx, cy, r, c

struct FitSettings {
  bool full = false;  // the FEM re-solved at each step, or the linearisation
  double min_radius = 0, max_radius = 1, min_intensity = 0, max_intensity = 1;  // sensor units
  double robust_scale = 0;  // Huber's scale in units of the start's residual RMS; 0: none
  int max_iterations = 50;
};

struct FitOutcome {
  std::vector<CircleParameters> circles;
  double rss = 0;  // data misfit, sum of squares (without the loss or the penalty)
  int iterations = 0;
  bool converged = false;
};

FitOutcome fit_shape(const ShapeModel& model, const Eigen::VectorXd& frame,
                     std::vector<CircleParameters> start, const FitSettings& settings);

}  // namespace eitbench::detail
