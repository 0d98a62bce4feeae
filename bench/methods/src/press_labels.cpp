#include "eitbench/bench/methods/press_labels.h"

#include "eitbench/bench/methods/press_scores.h"
#include "eitbench/bench/methods/touches.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

SampleMatrix press_labels(const std::vector<std::vector<PressTouch>>& touches,
                          const PixelGrid& grid, const std::string& source,
                          const PressLabelOptions& options) {
  SampleMatrix labels(static_cast<Eigen::Index>(touches.size()), grid.num_pixels());
  for (std::size_t i = 0; i < touches.size(); ++i) {
    if (touches[i].size() != 1)
      throw InputError(source, "touches",
                       "frame " + std::to_string(i) + " has " + std::to_string(touches[i].size()) +
                           " touches; one a frame");
    // circles_image draws (sigma_0 - sigma) / sigma_0: sigma_0 = 1, sigma = 1 - intensity.
    const Circle disc{touches[i][0].x, touches[i][0].y, options.radius * grid.radius(),
                      1.0 - options.intensity};
    labels.row(static_cast<Eigen::Index>(i)) = circles_image(grid, {disc}, 1.0).transpose();
  }
  return labels;
}

Eigen::Vector2d label_centre(const Eigen::VectorXd& label, const PixelGrid& grid) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double weight = 0;
  const int n = grid.size();
  for (int k = 0; k < label.size(); ++k)
    if (label[k] > 0) sum += label[k] * grid.center(k / n, k % n), weight += label[k];
  return weight > 0 ? Eigen::Vector2d(sum / weight) : grid.box_centre();
}

ScoreFn press_score(const PixelGrid& grid, double threshold, bool centroid) {
  return [grid, threshold, centroid](const Eigen::VectorXd& image, const Eigen::VectorXd& label) {
    const Eigen::Vector2d at =
        located_press(press_touches(image, grid, {centroid, threshold}), grid.box_centre());
    return -(at - label_centre(label, grid)).norm();
  };
}

}  // namespace eitbench
