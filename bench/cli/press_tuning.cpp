#include "press_tuning.h"

#include <filesystem>

#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/methods/press_scores.h"
#include "eitbench/jacobian/error.h"

namespace eitbench::cli {

namespace {

constexpr double kLabelRadius = 0.1;  // x R: the disc that carries a press's centre to the score

// The centre of a label's disc: its pixels' centroid.
Eigen::Vector2d label_centre(const Eigen::VectorXd& label, const PixelGrid& grid) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double weight = 0;
  const int n = grid.size();
  for (int k = 0; k < label.size(); ++k)
    if (label[k] > 0) sum += label[k] * grid.center(k / n, k % n), weight += label[k];
  return weight > 0 ? Eigen::Vector2d(sum / weight) : grid.box_centre();
}

void check_same_sensor(const Dataset& cal, const std::string& path, const Dataset& data) {
  if (measurement_protocol(cal).channels() != measurement_protocol(data).channels() ||
      cal.magnitude != data.magnitude)
    throw InputError(path, "protocol", "differs from the scored set's: tune on the same board");
  if (cal.touches.empty())
    throw InputError(path, "touches", "is not a press set (import --touches makes one)");
}

}  // namespace

PressTuning press_tuning(const std::string& path, const std::string& range, const Dataset& data,
                         const std::string& data_path, const std::vector<int>& scored_rows,
                         const PixelGrid& grid, double touch_threshold) {
  const Dataset cal = read_dataset(path);
  check_same_sensor(cal, path, data);
  const auto [a, b] = parse_range(range, cal.size());
  std::error_code same_error;
  if (std::filesystem::equivalent(path, data_path, same_error))
    for (int row : scored_rows)
      if (row >= a && row < b)
        throw InputError("--calibration-frames", "",
                         "frame " + std::to_string(row) +
                             " is also scored: nothing may be tuned on the scored presses");
  PressTuning t;
  t.frames = cal.differences.middleRows(a, b - a);
  t.labels.resize(b - a, grid.num_pixels());
  for (int i = a; i < b; ++i) {
    const auto& list = cal.touches[static_cast<std::size_t>(i)];
    if (list.size() != 1)
      throw InputError(path, "touches",
                       "frame " + std::to_string(i) + " has " + std::to_string(list.size()) +
                           " touches; one a frame");
    const Circle disc{list[0].x, list[0].y, kLabelRadius * grid.radius(), 0.0};
    t.labels.row(i - a) = circles_image(grid, {disc}, 1.0).transpose();
  }
  t.score = [grid, touch_threshold](const Eigen::VectorXd& image, const Eigen::VectorXd& label) {
    const Eigen::Vector2d at =
        located_press(find_touches(image, grid, touch_threshold), grid.box_centre());
    return -(at - label_centre(label, grid)).norm();
  };
  return t;
}

}  // namespace eitbench::cli
