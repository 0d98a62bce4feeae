#include "eitbench/augment/label_transform.h"

#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace eitbench {

Eigen::VectorXd transform_image(const Eigen::VectorXd& image, const GroupElement& g, int L,
                                const PixelGrid& grid) {
  const int n = grid.size();
  if (image.size() != grid.num_pixels())
    throw std::invalid_argument("transform_image: wrong image size");
  // out(x) = in(g^-1 x). With x = -R + (j + 1/2) w and y = R - (i + 1/2) w, the map from an
  // output pixel (j, i) to its source is affine; warpAffine samples it bilinearly.
  const GroupElement inv = inverse(g, L);
  const Eigen::Vector2d origin = transform_point({0, 0}, inv, L);  // (0, 0): the centre stays
  const Eigen::Vector2d ex = transform_point({1, 0}, inv, L) - origin;
  const Eigen::Vector2d ey = transform_point({0, 1}, inv, L) - origin;
  // In pixel units about the image centre c = (n - 1) / 2, with rows pointing down (y flipped).
  const double c = 0.5 * (n - 1);
  cv::Mat M(2, 3, CV_64F);
  M.at<double>(0, 0) = ex.x();
  M.at<double>(0, 1) = -ey.x();
  M.at<double>(1, 0) = -ex.y();
  M.at<double>(1, 1) = ey.y();
  M.at<double>(0, 2) = c - ex.x() * c + ey.x() * c;
  M.at<double>(1, 2) = c + ex.y() * c - ey.y() * c;
  const Eigen::Matrix<double, Eigen::Dynamic, 1> copy = image;
  const cv::Mat source(n, n, CV_64F, const_cast<double*>(copy.data()));
  cv::Mat target;
  cv::warpAffine(source, target, M, source.size(), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                 cv::BORDER_CONSTANT, 0.0);
  Eigen::VectorXd out(grid.num_pixels());
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      out[i * n + j] = grid.mask()[i * n + j] ? target.at<double>(i, j) : 0.0;
  return out;
}

}  // namespace eitbench
