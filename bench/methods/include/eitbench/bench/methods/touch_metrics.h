#pragma once
// Touch metrics (docs/benchmark.md#touch-metrics): found touches matched to the true ones frame by
// frame, summarised over frames as results.h's TouchScores, and the blob threshold chosen on
// validation frames. Every distance is a fraction of the sensor radius R.
//
// Both kinds of method reach the same summary: one that reconstructs images goes through
// find_touches (touches.h), one that fits circles passes them through touches_of, then
//   score_touches(found, touches_of(truth_circles, background), R, options)
// for either.
#include <utility>
#include <vector>

#include "eitbench/bench/methods/touches.h"
#include "eitbench/bench/report/results.h"

namespace eitbench {

// One frame's found touches matched to its true ones.
struct FrameMatch {
  int found = 0, truth = 0;
  std::vector<std::pair<int, int>> pairs;  // (true index, found index), by true index
  // Per pair: centre distance and |r_found - r_true|, as fractions of R.
  std::vector<double> centre_errors, radius_errors;
  std::vector<double> truth_signals;  // each true touch's Touch::signal, by true index
  int missed() const { return truth - static_cast<int>(pairs.size()); }
  int phantom() const { return found - static_cast<int>(pairs.size()); }
  bool count_correct() const { return found == truth; }
};

// The exact matching: the most pairs within options.gate x R of each other, and among those the
// least total centre distance, by enumeration (every true touch takes a found one within the gate
// or none; K true touches, K <= 8, InputError beyond). Greedy nearest matching is not optimal
// (tests/touch_metrics_test.cpp has the case).
FrameMatch match_touches(const std::vector<Touch>& found, const std::vector<Touch>& truth,
                         double radius, const TouchOptions& options = {});

// Over frames: count accuracy, the matched centre errors' median and 90th percentile and their
// quantiles for the figure, the radius errors' median, missed and phantom touches a frame (mean),
// count accuracy and centre median by the true number of touches, and, where the true touches'
// signals are known, true touches found by signal and count accuracy on the frames whose every
// touch is visible (touch_signal.h). Percentiles interpolate
// linearly between order statistics (numpy's default). threshold is left NaN.
TouchScores summarize_touches(const std::vector<FrameMatch>& frames);

// match_touches frame by frame (found and truth of the same length, InputError otherwise), then
// summarize_touches.
TouchScores score_touches(const TouchFrames& found, const TouchFrames& truth, double radius,
                          const TouchOptions& options = {});

// The threshold of options.thresholds whose touches score best on validation images: the highest
// count accuracy, ties broken by the lower median centre error (a NaN median last), then by the
// earlier candidate. `scores` holds each candidate's, in the candidates' order.
struct ThresholdChoice {
  double threshold = 0;
  std::vector<TouchScores> scores;
};
ThresholdChoice choose_touch_threshold(const SampleMatrix& images, const TouchFrames& truth,
                                       const PixelGrid& grid, const TouchOptions& options = {});

// The test images' touch scores at a threshold chosen on the validation images (same grid).
TouchScores score_touch_images(const SampleMatrix& validation_images,
                               const TouchFrames& validation_truth, const SampleMatrix& test_images,
                               const TouchFrames& test_truth, const PixelGrid& grid,
                               const TouchOptions& options = {});

}  // namespace eitbench
