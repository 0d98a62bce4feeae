#pragma once
// reconstruct --calibration CAL.h5: a press set whose presses choose a method's hyperparameter by
// where the method puts them, never the presses it is scored on.
#include <string>
#include <utility>
#include <vector>

#include "eitbench/bench/data/dataset.h"
#include "eitbench/jacobian/pixel_grid.h"
#include "eitbench/solvers/reconstructor.h"

namespace eitbench::cli {

struct PressTuning {
  SampleMatrix frames, labels;  // labels: a disc of 0.1 R at each press, where the score finds it
  ScoreFn score;                // minus the centre error of the image's strongest blob
  std::vector<std::vector<PressTouch>> truth;  // each frame's press
};

// The presses of `path` (frames `range`, "A:B" or all), checked against the scored set `data`:
// the same protocol and magnitude, and when it is the same file, frames that do not overlap
// `scored_rows`.
PressTuning press_tuning(const std::string& path, const std::string& range, const Dataset& data,
                         const std::string& data_path, const std::vector<int>& scored_rows,
                         const PixelGrid& grid, double touch_threshold, bool centroid = false);

}  // namespace eitbench::cli
