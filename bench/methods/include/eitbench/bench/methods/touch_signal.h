#pragma once
// How visible a true touch is to a method that models the sensor: the share of its frame's change
// that the touch carries, ||v(all) - v(all but it)|| / ||v(all) - v(none)||, v the reconstruction
// model's inputs. A model explains a frame only to within its own error (the reconstruction mesh
// against the finer one that made the frames: a few per cent of a quick frame, noise-free), so a
// touch that carries less than that is one no method on this model can be expected to find; the
// touch metrics report count accuracy on the frames whose every touch carries more, beside the
// plain one (docs/benchmark.md#touch-metrics).
#include <array>
#include <vector>

#include "eitbench/bench/methods/touches.h"
#include "eitbench/jacobian/forward_model.h"

namespace eitbench {

// A touch is visible when it carries at least this share of its frame's change.
constexpr double kVisibleSignal = 0.05;
// The touch metrics count true touches found in bins of signal split at these shares.
constexpr std::array<double, 2> kSignalBinEdges{0.02, kVisibleSignal};

struct TouchVisibility {
  std::vector<std::vector<double>> signals;  // each frame's true touches' shares, in order
  // Each frame's misfit at its true circles, ||v(all) - v(none) - frame|| / ||frame||: the
  // model's own error (NaN for a frame of no change).
  std::vector<double> model_error;
};
// One FEM solve a touch and one a frame, the frames (differences of the model's inputs, one a row)
// in parallel. A single touch carries its whole frame (1); a touch of no contrast carries 0.
// InputError for a background that is not positive and finite, or frames that do not match.
TouchVisibility touch_visibility(const ForwardModel& model,
                                 const std::vector<std::vector<Circle>>& circles,
                                 const SampleMatrix& frames, double background);
// The truth with each touch's signal set (the same shapes, InputError otherwise).
TouchFrames with_signals(TouchFrames truth, const std::vector<std::vector<double>>& signals);

}  // namespace eitbench
