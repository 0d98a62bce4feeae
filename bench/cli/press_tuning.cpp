#include "press_tuning.h"

#include <filesystem>

#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/press_touches.h"
#include "eitbench/bench/methods/press_labels.h"
#include "eitbench/jacobian/error.h"
#include "options.h"

namespace eitbench::cli {

PressTuning press_tuning(const std::string& path, const std::string& range, const Dataset& data,
                         const std::string& data_path, const std::vector<int>& scored_rows,
                         const PixelGrid& grid, double touch_threshold, bool centroid) {
  const Dataset cal = read_dataset(path);
  check_press_set(path, cal, measurement_protocol(data));
  const auto [a, b] = parse_range(range, cal.size(), "--calibration-frames");
  std::error_code same_error;
  if (std::filesystem::equivalent(path, data_path, same_error))
    for (int row : scored_rows)
      if (row >= a && row < b)
        throw InputError("--calibration-frames", "",
                         "frame " + std::to_string(row) +
                             " is also scored: nothing may be tuned on the scored presses");
  PressTuning t;
  t.frames = cal.differences.middleRows(a, b - a);
  const std::vector<std::vector<PressTouch>> touches(cal.touches.begin() + a,
                                                     cal.touches.begin() + b);
  t.labels = press_labels(touches, grid, path);
  t.score = press_score(grid, touch_threshold, centroid);
  t.truth = touches;
  return t;
}

}  // namespace eitbench::cli
