#pragma once
// One evaluation loop, shared by the benchmark run and `eitbench reconstruct`, so that both score
// and time a method the same way: quality on every frame, latency one frame at a time after a
// warm-up.
#include <string>
#include <vector>

#include "eitbench/bench/methods/metrics.h"
#include "eitbench/jacobian/pixel_grid.h"
#include "eitbench/jacobian/sample_matrix.h"
#include "eitbench/solvers/reconstructor.h"

namespace eitbench {

struct EvaluationOptions {
  // Frames reconstructed one at a time for the latency figures: the first `timed_frames` (all of
  // them when negative; none when 0).
  int timed_frames = 32;
  // Untimed single-frame calls before timing. The first calls pay one-off costs (LibTorch sets up
  // its kernels and memory pools for the batch-of-one shape) that a sensor streaming frames pays
  // once.
  int warmup_calls = 3;
  // Where the frames came from, for the messages (a file name).
  std::string source = "frames";
};

struct Evaluation {
  SampleMatrix images;  // every frame, by reconstruct_all (touches_all for a method of circles)
  std::vector<std::vector<Circle>> circles;          // per frame, when the method finds_circles()
  ScoreSummary scores;                               // against the labels; count 0 without labels
  std::vector<ImageScores> each;                     // per frame, with labels
  double latency_median_ms = 0, latency_p95_ms = 0;  // 0 when nothing was timed
  std::string settings;                              // the method's, after fitting
};

// A frame whose sum of squares is not finite makes every method's arithmetic meaningless (NaN
// images, or a Gauss-Newton that gives up with zeros): InputError(source, "frame i") naming its
// range of values. Callers check before they tune a method on the frames; evaluate checks again.
void check_frames(const SampleMatrix& frames, const std::string& source);

// Reconstructs `frames` (one a row) and scores the images against `labels` when it has a row per
// frame. InputError(options.source, "frame i") for a frame whose sum of squares is not finite,
// and for any image that is not finite, naming the method and the frame's range of values.
Evaluation evaluate(const Reconstructor& method, const SampleMatrix& frames,
                    const SampleMatrix& labels, const PixelGrid& grid,
                    const EvaluationOptions& options = {});

}  // namespace eitbench
