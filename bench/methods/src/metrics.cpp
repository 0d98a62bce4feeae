#include "eitbench/bench/methods/metrics.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace eitbench {

double correlation(const Eigen::VectorXd& image, const Eigen::VectorXd& label,
                   const PixelGrid& grid) {
  const auto& mask = grid.mask();
  double sx = 0, sy = 0, n = 0;
  for (Eigen::Index p = 0; p < image.size(); ++p)
    if (mask[p]) sx += image[p], sy += label[p], ++n;
  const double mx = sx / n, my = sy / n;
  double xy = 0, xx = 0, yy = 0;
  for (Eigen::Index p = 0; p < image.size(); ++p)
    if (mask[p]) {
      const double a = image[p] - mx, b = label[p] - my;
      xy += a * b, xx += a * a, yy += b * b;
    }
  return xx > 0 && yy > 0 ? xy / std::sqrt(xx * yy) : 0.0;
}

ImageScores score_image(const Eigen::VectorXd& image, const Eigen::VectorXd& label,
                        const PixelGrid& grid) {
  const auto& mask = grid.mask();
  const int n = grid.size();
  ImageScores s;
  s.cc = correlation(image, label, grid);
  double diff = 0, norm = 0, count = 0;
  for (Eigen::Index p = 0; p < image.size(); ++p)
    if (mask[p]) diff += std::pow(image[p] - label[p], 2), norm += label[p] * label[p], ++count;
  s.re = norm > 0 ? std::sqrt(diff / norm) : INFINITY;
  s.mse = diff / count;
  // SSIM (Wang et al. 2004) on the whole grid, masked pixels 0, averaged over the disk.
  cv::Mat x(n, n, CV_64F), y(n, n, CV_64F);
  for (int p = 0; p < n * n; ++p)
    x.at<double>(p / n, p % n) = mask[p] ? image[p] : 0.0,
                            y.at<double>(p / n, p % n) = mask[p] ? label[p] : 0.0;
  auto blur = [](const cv::Mat& m) {
    cv::Mat out;
    cv::GaussianBlur(m, out, cv::Size(11, 11), 1.5, 1.5, cv::BORDER_REFLECT);
    return out;
  };
  const cv::Mat mx = blur(x), my = blur(y);
  const cv::Mat sxx = blur(x.mul(x)) - mx.mul(mx), syy = blur(y.mul(y)) - my.mul(my),
                sxy = blur(x.mul(y)) - mx.mul(my);
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;  // dynamic range 1: labels lie in [0, 1)
  double total = 0;
  for (int p = 0; p < n * n; ++p) {
    if (!mask[p]) continue;
    const int i = p / n, j = p % n;
    const double a = mx.at<double>(i, j), b = my.at<double>(i, j);
    total += (2 * a * b + c1) * (2 * sxy.at<double>(i, j) + c2) /
             ((a * a + b * b + c1) * (sxx.at<double>(i, j) + syy.at<double>(i, j) + c2));
  }
  s.ssim = total / count;
  return s;
}

ScoreSummary score_images(const SampleMatrix& images, const SampleMatrix& labels,
                          const PixelGrid& grid, std::vector<ImageScores>* each) {
  ScoreSummary summary;
  std::vector<ImageScores> all;
  for (Eigen::Index i = 0; i < images.rows(); ++i)
    all.push_back(score_image(images.row(i).transpose(), labels.row(i).transpose(), grid));
  summary.count = static_cast<int>(all.size());
  if (all.empty()) return summary;
  auto stats = [&](double ImageScores::*field, double& mean, double& sd) {
    double s = 0, s2 = 0;
    for (const auto& a : all) s += a.*field, s2 += (a.*field) * (a.*field);
    mean = s / all.size();
    sd = std::sqrt(std::max(0.0, s2 / all.size() - mean * mean));
  };
  stats(&ImageScores::cc, summary.mean.cc, summary.std.cc);
  stats(&ImageScores::re, summary.mean.re, summary.std.re);
  stats(&ImageScores::mse, summary.mean.mse, summary.std.mse);
  stats(&ImageScores::ssim, summary.mean.ssim, summary.std.ssim);
  if (each) *each = std::move(all);
  return summary;
}

}  // namespace eitbench
