#include "shape_seeds.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "eitbench/jacobian/constants.h"

namespace eitbench::detail {
namespace {

struct Peak {
  int row, col;
  float value;
};

// Pixels equal to the maximum of their 5 x 5 neighbourhood and above `floor`; of peaks closer
// than 3 pixels (a plateau) only the first in raster order counts.
std::vector<Peak> local_maxima(const cv::Mat& image, float floor) {
  cv::Mat dilated;
  cv::dilate(image, dilated, cv::Mat::ones(5, 5, CV_8U));
  std::vector<Peak> peaks;
  for (int i = 0; i < image.rows; ++i)
    for (int j = 0; j < image.cols; ++j) {
      const float v = image.at<float>(i, j);
      if (v < floor || v < dilated.at<float>(i, j)) continue;
      const bool near = std::any_of(peaks.begin(), peaks.end(), [&](const Peak& p) {
        return std::abs(p.row - i) < 3 && std::abs(p.col - j) < 3;
      });
      if (!near) peaks.push_back({i, j, v});
    }
  std::stable_sort(peaks.begin(), peaks.end(),
                   [](const Peak& a, const Peak& b) { return a.value > b.value; });
  return peaks;
}

}  // namespace

std::vector<CircleParameters> image_seeds(const Eigen::VectorXd& image, const PixelGrid& grid,
                                          double threshold, int max_seeds, double intensity) {
  const int n = grid.size();
  cv::Mat m(n, n, CV_32F);
  for (int k = 0; k < n * n; ++k) m.at<float>(k / n, k % n) = static_cast<float>(image[k]);
  double top = 0;
  cv::minMaxLoc(m, nullptr, &top);
  if (!(top > 0)) return {};
  const float floor = static_cast<float>(threshold * top);
  cv::Mat above = m >= floor, labels, stats, centroids;
  cv::connectedComponentsWithStats(above, labels, stats, centroids, 8, CV_32S);
  std::vector<Peak> peaks = local_maxima(m, floor);
  if (static_cast<int>(peaks.size()) > max_seeds) peaks.resize(static_cast<std::size_t>(max_seeds));
  std::vector<int> sharing(static_cast<std::size_t>(stats.rows), 0);
  for (const Peak& p : peaks) ++sharing[static_cast<std::size_t>(labels.at<int>(p.row, p.col))];
  const double w = grid.pixel_width();
  std::vector<CircleParameters> seeds;
  for (const Peak& p : peaks) {
    const int blob = labels.at<int>(p.row, p.col);
    const double area = stats.at<int>(blob, cv::CC_STAT_AREA) * w * w / sharing[blob];
    const Eigen::Vector2d at = grid.center(p.row, p.col);
    seeds.push_back({at.x(), at.y(), std::sqrt(area / kPi), intensity});
  }
  return seeds;
}

}  // namespace eitbench::detail
