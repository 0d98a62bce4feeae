#include "eitbench/augment/label_transform.h"

#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace eitbench {
namespace {

// Where each output pixel of the image moved by g samples the input: the pixel's centre moved
// back by g, in the input's (column, row) coordinates.
void sampling_maps(const GroupElement& g, int electrodes, const PixelGrid& grid,
                   std::vector<float>& mx, std::vector<float>& my) {
  const int n = grid.size();
  const double w = grid.pixel_width(), R = grid.radius();
  const GroupElement inv = inverse(g, electrodes);
  mx.resize(static_cast<std::size_t>(n) * n);
  my.resize(static_cast<std::size_t>(n) * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector2d source = transform_point(grid.center(i, j), inv, electrodes);
      mx[i * n + j] = static_cast<float>((source.x() + R) / w - 0.5);
      my[i * n + j] = static_cast<float>((R - source.y()) / w - 0.5);
    }
}

// Bilinear sampling of `image` through the maps, masked to the disk.
Eigen::VectorXd remap_image(const Eigen::VectorXd& image, const std::vector<float>& map_x,
                            const std::vector<float>& map_y, const PixelGrid& grid) {
  const int n = grid.size();
  if (image.size() != grid.num_pixels())
    throw std::invalid_argument("ImageSymmetry: wrong image size");
  const cv::Mat source(n, n, CV_64F, const_cast<double*>(image.data()));
  const cv::Mat mx(n, n, CV_32F, const_cast<float*>(map_x.data()));
  const cv::Mat my(n, n, CV_32F, const_cast<float*>(map_y.data()));
  Eigen::VectorXd out(grid.num_pixels());
  cv::Mat target(n, n, CV_64F, out.data());
  cv::remap(source, target, mx, my, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0.0);
  for (int p = 0; p < grid.num_pixels(); ++p)
    if (!grid.mask()[p]) out[p] = 0.0;
  return out;
}

}  // namespace

ImageSymmetry::ImageSymmetry(int electrodes, const PixelGrid& grid)
    : electrodes_(electrodes), grid_(grid), map_x_(2 * electrodes), map_y_(2 * electrodes) {
  for (int index = 0; index < 2 * electrodes; ++index)
    sampling_maps({index % electrodes, index >= electrodes}, electrodes, grid, map_x_[index],
                  map_y_[index]);
}

Eigen::VectorXd ImageSymmetry::apply(const GroupElement& g, const Eigen::VectorXd& image) const {
  const int index = (g.mirror ? electrodes_ : 0) + g.rotation;
  return remap_image(image, map_x_[index], map_y_[index], grid_);
}

Eigen::VectorXd moved_label(const Eigen::VectorXd& label, const std::vector<Circle>* circles,
                            double background, const GroupElement& g, int electrodes,
                            const ImageSymmetry& images) {
  if (circles)
    return circles_image(images.grid(), transform_circles(*circles, g, electrodes), background);
  return images.apply(g, label);
}

Eigen::VectorXd transform_image(const Eigen::VectorXd& image, const GroupElement& g, int electrodes,
                                const PixelGrid& grid) {
  std::vector<float> mx, my;  // only g's maps, not all 2L
  sampling_maps(g, electrodes, grid, mx, my);
  return remap_image(image, mx, my, grid);
}

}  // namespace eitbench
