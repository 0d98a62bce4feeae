#pragma once
// The method a user without labelled presses is given (docs/real-presses.md#a-pick-without-labels):
// among the rows that used no label, the lowest median centre error in the simulation like the
// sensor. That simulation has the sensor's measured noise and channel gains, not the model's own
// error; where the real frames' misfit to the model passes kModelErrorRatio times the noise, the
// model's error dominates what the simulation leaves out, and the pick keeps to the rows whose
// hyperparameter the real frames chose (GCV on them), which carries it.
#include <vector>

#include "eitbench/bench/report/results.h"

namespace eitbench {

constexpr double kModelErrorRatio = 2.0;

struct PressPick {
  const MeasuredRow* pick = nullptr;  // null: no row without labels
  bool real_frames_only = false;      // the pick kept to the rows the real frames tuned
  double misfit_over_noise = NAN;     // the rows' (NaN when none gives it)
};

// A row without labels is one with its error in the simulation like the sensor.
PressPick pick_without_labels(const std::vector<MeasuredRow>& rows);

}  // namespace eitbench
