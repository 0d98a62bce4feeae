// The blob threshold of a method, chosen on its validation images.
#include <cmath>

#include "eitbench/bench/methods/touch_metrics.h"

namespace eitbench {
namespace {

// Higher count accuracy first, then the lower median centre error (NaN, nothing matched, last).
bool better(const TouchScores& a, const TouchScores& b) {
  if (a.count_accuracy != b.count_accuracy) return a.count_accuracy > b.count_accuracy;
  const double ea = std::isnan(a.centre_error_median) ? INFINITY : a.centre_error_median;
  const double eb = std::isnan(b.centre_error_median) ? INFINITY : b.centre_error_median;
  return ea < eb;
}

}  // namespace

ThresholdChoice choose_touch_threshold(const SampleMatrix& images, const TouchFrames& truth,
                                       const PixelGrid& grid, const TouchOptions& options) {
  options.validate();
  ThresholdChoice choice;
  std::size_t best = 0;
  for (std::size_t k = 0; k < options.thresholds.size(); ++k) {
    const double t = options.thresholds[k];
    TouchScores s =
        score_touches(touches_in_images(images, grid, t, options), truth, grid.radius(), options);
    s.threshold = t;
    choice.scores.push_back(s);
    if (k > 0 && better(s, choice.scores[best])) best = k;
  }
  choice.threshold = options.thresholds[best];
  return choice;
}

TouchScores score_touch_images(const SampleMatrix& validation_images,
                               const TouchFrames& validation_truth, const SampleMatrix& test_images,
                               const TouchFrames& test_truth, const PixelGrid& grid,
                               const TouchOptions& options) {
  const double threshold =
      choose_touch_threshold(validation_images, validation_truth, grid, options).threshold;
  TouchScores s = score_touches(touches_in_images(test_images, grid, threshold, options),
                                test_truth, grid.radius(), options);
  s.threshold = threshold;
  return s;
}

}  // namespace eitbench
