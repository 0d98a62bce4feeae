#pragma once
// Labelled presses as training and tuning take them: each press a disc image at its centre (the
// label a learned model is fine-tuned on, and the truth a hyperparameter search scores against),
// and a score that asks only where a method puts the press.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "eitbench/bench/data/dataset.h"
#include "eitbench/jacobian/pixel_grid.h"
#include "eitbench/jacobian/sample_matrix.h"
#include "eitbench/solvers/reconstructor.h"

namespace eitbench {

struct PressLabelOptions {
  // The disc drawn at each press, x R. A press's extent is not known from its depth; 0.1 R is about
  // a 14 mm probe on a 70 mm skin, and the scores ask only where the disc's centre lies.
  double radius = 0.1;
  // The disc's touch intensity (sigma_0 - sigma) / sigma_0, as a simulated label's: a press
  // lowers the conductivity under it. The simulated touches span (0, 1).
  double intensity = 1.0;
};

// One disc image a frame (rows: frames, n^2 pixels); InputError(source, "touches") naming a frame
// without exactly one touch.
SampleMatrix press_labels(const std::vector<std::vector<PressTouch>>& touches,
                          const PixelGrid& grid, const std::string& source,
                          const PressLabelOptions& options = {});

// The centre of a label image: its pixels' weighted centroid (the box's centre when empty).
Eigen::Vector2d label_centre(const Eigen::VectorXd& label, const PixelGrid& grid);

// Minus the distance from the press (the label's centre) to where the method puts it: its
// image's strongest blob at `threshold` x the image's maximum (or with `centroid`, the centroid of
// every pixel there: centroid_touch), or the sensor's centre.
ScoreFn press_score(const PixelGrid& grid, double threshold, bool centroid = false);

}  // namespace eitbench
