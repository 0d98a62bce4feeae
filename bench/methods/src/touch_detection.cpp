// Touches from images (thresholding, OpenCV's connected components) and from circles.
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "eitbench/bench/methods/touches.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

// The in-disk pixels at or above threshold x the in-disk maximum, as an 8-bit n x n mask.
cv::Mat touch_pixels(const Eigen::VectorXd& image, const PixelGrid& grid, double threshold) {
  const int n = grid.size();
  const auto& inside = grid.mask();
  double peak = 0;
  for (Eigen::Index p = 0; p < image.size(); ++p)
    if (inside[p] && image[p] > peak) peak = image[p];
  cv::Mat pixels(n, n, CV_8U, cv::Scalar(0));
  if (!(peak > 0)) return pixels;  // no positive value: nothing is touched
  for (int p = 0; p < n * n; ++p)
    if (inside[p] && image[p] >= threshold * peak) pixels.at<unsigned char>(p / n, p % n) = 1;
  return pixels;
}

// Sums over one blob's pixels, for its weighted centroid and peak.
struct BlobSums {
  double weight = 0, x = 0, y = 0, peak = 0;
  void add(double v, const Eigen::Vector2d& c) {
    weight += v, x += v * c.x(), y += v * c.y(), peak = std::max(peak, v);
  }
  // The touch at the weighted centroid, a circle of the pixels' `area`, the peak its contrast.
  Touch touch(double area) const { return {x / weight, y / weight, std::sqrt(area / M_PI), peak}; }
};

}  // namespace

void TouchOptions::validate() const {
  if (thresholds.empty()) throw InputError("TouchOptions", "thresholds", "must not be empty");
  for (double t : thresholds)
    if (!(t > 0 && t <= 1))
      throw InputError("TouchOptions", "thresholds", "each must lie in (0, 1]");
  if (!(min_area >= 0 && std::isfinite(min_area)))
    throw InputError("TouchOptions", "min_area", "must be finite and not negative");
  if (!(gate > 0 && std::isfinite(gate)))
    throw InputError("TouchOptions", "gate", "must be positive and finite");
}

std::vector<Touch> find_touches(const Eigen::VectorXd& image, const PixelGrid& grid,
                                double threshold, const TouchOptions& options) {
  options.validate();
  if (!(threshold > 0 && threshold <= 1))
    throw InputError("find_touches", "threshold", "must lie in (0, 1]");
  if (image.size() != grid.num_pixels())
    throw InputError("find_touches", "image", "must have the grid's n^2 pixels");
  const int n = grid.size();
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(touch_pixels(image, grid, threshold), labels,
                                                     stats, centroids, 8, CV_32S);
  std::vector<BlobSums> sums(static_cast<std::size_t>(count));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int blob = labels.at<int>(i, j);
      if (blob == 0) continue;  // the background
      sums[static_cast<std::size_t>(blob)].add(image[i * n + j], grid.center(i, j));
    }
  const double pixel_area = grid.pixel_width() * grid.pixel_width();
  const double min_area = options.min_area * grid.radius() * grid.radius();
  std::vector<Touch> touches;
  for (int blob = 1; blob < count; ++blob) {
    const double area = stats.at<int>(blob, cv::CC_STAT_AREA) * pixel_area;
    if (area < min_area) continue;
    touches.push_back(sums[static_cast<std::size_t>(blob)].touch(area));
  }
  return touches;
}

std::vector<Touch> centroid_touch(const Eigen::VectorXd& image, const PixelGrid& grid,
                                  double threshold) {
  if (!(threshold > 0 && threshold <= 1))
    throw InputError("centroid_touch", "threshold", "must lie in (0, 1]");
  if (image.size() != grid.num_pixels())
    throw InputError("centroid_touch", "image", "must have the grid's n^2 pixels");
  const cv::Mat pixels = touch_pixels(image, grid, threshold);
  const int n = grid.size();
  BlobSums s;
  int count = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (!pixels.at<unsigned char>(i, j)) continue;
      s.add(image[i * n + j], grid.center(i, j)), ++count;
    }
  if (count == 0) return {};
  return {s.touch(count * grid.pixel_width() * grid.pixel_width())};
}

TouchFrames touches_in_images(const SampleMatrix& images, const PixelGrid& grid, double threshold,
                              const TouchOptions& options) {
  TouchFrames frames;
  for (Eigen::Index i = 0; i < images.rows(); ++i)
    frames.push_back(find_touches(images.row(i).transpose(), grid, threshold, options));
  return frames;
}

std::vector<Touch> touches_of(const std::vector<Circle>& circles, double background) {
  if (!(background > 0 && std::isfinite(background)))
    throw InputError("touches_of", "background", "must be positive and finite");
  std::vector<Touch> touches;
  for (const Circle& c : circles)
    touches.push_back({c.x, c.y, c.r, (background - c.conductivity) / background});
  return touches;
}

TouchFrames touches_of(const std::vector<std::vector<Circle>>& circles, double background) {
  TouchFrames frames;
  for (const auto& list : circles) frames.push_back(touches_of(list, background));
  return frames;
}

}  // namespace eitbench
