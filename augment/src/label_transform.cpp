#include "eitbench/augment/label_transform.h"

#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace eitbench {

ImageSymmetry::ImageSymmetry(int electrodes, const PixelGrid& grid)
    : electrodes_(electrodes), grid_(grid), map_x_(2 * electrodes), map_y_(2 * electrodes) {
  const int n = grid.size();
  const double w = grid.pixel_width(), R = grid.radius();
  for (int index = 0; index < 2 * electrodes; ++index) {
    const GroupElement inv = inverse({index % electrodes, index >= electrodes}, electrodes);
    auto& mx = map_x_[index];
    auto& my = map_y_[index];
    mx.resize(static_cast<std::size_t>(n) * n);
    my.resize(static_cast<std::size_t>(n) * n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        // The output pixel's centre, moved back by g: where in the input to sample.
        const Eigen::Vector2d source = transform_point(grid.center(i, j), inv, electrodes);
        mx[i * n + j] = static_cast<float>((source.x() + R) / w - 0.5);
        my[i * n + j] = static_cast<float>((R - source.y()) / w - 0.5);
      }
  }
}

Eigen::VectorXd ImageSymmetry::apply(const GroupElement& g, const Eigen::VectorXd& image) const {
  const int n = grid_.size();
  if (image.size() != grid_.num_pixels())
    throw std::invalid_argument("ImageSymmetry: wrong image size");
  const int index = (g.mirror ? electrodes_ : 0) + g.rotation;
  const cv::Mat source(n, n, CV_64F, const_cast<double*>(image.data()));
  const cv::Mat mx(n, n, CV_32F, const_cast<float*>(map_x_[index].data()));
  const cv::Mat my(n, n, CV_32F, const_cast<float*>(map_y_[index].data()));
  Eigen::VectorXd out(grid_.num_pixels());
  cv::Mat target(n, n, CV_64F, out.data());
  cv::remap(source, target, mx, my, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0.0);
  for (int p = 0; p < grid_.num_pixels(); ++p)
    if (!grid_.mask()[p]) out[p] = 0.0;
  return out;
}

Eigen::VectorXd transform_image(const Eigen::VectorXd& image, const GroupElement& g, int electrodes,
                                const PixelGrid& grid) {
  return ImageSymmetry(electrodes, grid).apply(g, image);
}

}  // namespace eitbench
