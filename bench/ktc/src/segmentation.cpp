#include "eitbench/bench/ktc/segmentation.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "eitbench/jacobian/error.h"

namespace eitbench {

Eigen::Vector2d KtcOrientation::to_model(const Eigen::Vector2d& p) const {
  // Image angle phi holds model angle (phi - theta_1) counter-clockwise, (theta_1 - phi) clockwise.
  const double a = clockwise ? first_electrode_angle : -first_electrode_angle;
  const Eigen::Vector2d q(p.x(), clockwise ? -p.y() : p.y());
  return {std::cos(a) * q.x() - std::sin(a) * q.y(), std::sin(a) * q.x() + std::cos(a) * q.y()};
}

Eigen::Vector2d KtcOrientation::to_image(const Eigen::Vector2d& p) const {
  // to_model rotates by a after the mirror: turn back by a, then mirror again.
  const double a = clockwise ? first_electrode_angle : -first_electrode_angle;
  const Eigen::Vector2d q(std::cos(a) * p.x() + std::sin(a) * p.y(),
                          -std::sin(a) * p.x() + std::cos(a) * p.y());
  return {q.x(), clockwise ? -q.y() : q.y()};
}

Eigen::MatrixXd to_ktc_grid(const Eigen::VectorXd& image, const PixelGrid& grid,
                            const KtcOrientation& orientation) {
  if (image.size() != grid.num_pixels())
    throw std::invalid_argument("to_ktc_grid: one value a pixel of the grid");
  const int n = grid.size();
  const double R = grid.radius(), w = grid.pixel_width(), kw = 2 * R / kKtcImageSize;
  const auto& inside = grid.mask();
  Eigen::MatrixXd out(kKtcImageSize, kKtcImageSize);
  for (int i = 0; i < kKtcImageSize; ++i)
    for (int j = 0; j < kKtcImageSize; ++j) {
      const Eigen::Vector2d p(-R + (j + 0.5) * kw, R - (i + 0.5) * kw);
      if (p.norm() > R) {
        out(i, j) = std::numeric_limits<double>::quiet_NaN();
        continue;
      }
      const Eigen::Vector2d q = orientation.to_model(p);
      // Fractional column and row of q among the grid's pixel centres.
      const double c = (q.x() - grid.left()) / w - 0.5, r = (grid.top() - q.y()) / w - 0.5;
      const int c0 = static_cast<int>(std::floor(c)), r0 = static_cast<int>(std::floor(r));
      double sum = 0, weight = 0;
      for (int dr = 0; dr <= 1; ++dr)
        for (int dc = 0; dc <= 1; ++dc) {
          const int rr = r0 + dr, cc = c0 + dc;
          if (rr < 0 || rr >= n || cc < 0 || cc >= n || !inside[rr * n + cc]) continue;
          const double k = (dr ? r - r0 : 1 - (r - r0)) * (dc ? c - c0 : 1 - (c - c0));
          sum += k * image[rr * n + cc];
          weight += k;
        }
      out(i, j) = weight > 0 ? sum / weight : 0.0;
    }
  return out;
}

SegmentationKind parse_segmentation(const std::string& name) {
  if (name == "otsu") return SegmentationKind::otsu;
  if (name == "levels") return SegmentationKind::levels;
  throw InputError("SegmentationKind", "name",
                   "unknown segmentation '" + name + "' (otsu, levels)");
}

std::string to_string(SegmentationKind kind) {
  return kind == SegmentationKind::otsu ? "otsu" : "levels";
}

void SegmentationRule::validate() const {
  for (const auto& [field, v] : {std::pair<const char*, double>{"resistive", resistive},
                                 std::pair<const char*, double>{"conductive", conductive}})
    if (!(v > 0 && v <= 1)) throw InputError("SegmentationRule", field, "must lie in (0, 1]");
}

std::string SegmentationRule::to_string() const {
  if (kind == SegmentationKind::otsu) return "otsu";
  char text[64];
  std::snprintf(text, sizeof text, "levels r=%.3g c=%.3g", resistive, conductive);
  return text;
}

std::pair<double, double> otsu3_thresholds(const Eigen::VectorXd& values, int bins) {
  if (bins < 3) throw std::invalid_argument("otsu3_thresholds: at least 3 bins");
  double lo = INFINITY, hi = -INFINITY;
  for (double v : values)
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (!(hi > lo)) return {lo, lo};
  const double width = (hi - lo) / bins;
  Eigen::VectorXd count = Eigen::VectorXd::Zero(bins), centre(bins);
  for (int b = 0; b < bins; ++b) centre[b] = lo + (b + 0.5) * width;
  for (double v : values)
    if (std::isfinite(v)) count[std::min(bins - 1, static_cast<int>((v - lo) / width))] += 1;
  // Prefix sums of counts and first moments: each class's weight and mean in O(1).
  Eigen::VectorXd n(bins + 1), s(bins + 1);
  n[0] = s[0] = 0;
  for (int b = 0; b < bins; ++b) n[b + 1] = n[b] + count[b], s[b + 1] = s[b] + count[b] * centre[b];
  const double mean = s[bins] / n[bins];
  auto term = [&](int from, int to) {  // weight * (class mean - mean)^2 over bins [from, to)
    const double w = n[to] - n[from];
    if (w == 0) return 0.0;
    const double d = (s[to] - s[from]) / w - mean;
    return w * d * d;
  };
  double best = -1;
  int bi = 1, bj = 2;
  for (int i = 1; i < bins - 1; ++i)
    for (int j = i + 1; j < bins; ++j) {
      const double v = term(0, i) + term(i, j) + term(j, bins);
      if (v > best) best = v, bi = i, bj = j;
    }
  return {lo + bi * width, lo + bj * width};
}

ClassImage segment(const Eigen::MatrixXd& x, const SegmentationRule& rule) {
  rule.validate();
  ClassImage out = ClassImage::Zero(x.rows(), x.cols());
  if (rule.kind == SegmentationKind::levels) {
    double largest = 0;
    for (Eigen::Index k = 0; k < x.size(); ++k)
      if (std::isfinite(x.data()[k])) largest = std::max(largest, std::abs(x.data()[k]));
    if (largest == 0) return out;
    for (Eigen::Index i = 0; i < x.rows(); ++i)
      for (Eigen::Index j = 0; j < x.cols(); ++j) {
        const double v = x(i, j);
        if (v >= rule.resistive * largest)
          out(i, j) = 1;
        else if (v <= -rule.conductive * largest)
          out(i, j) = 2;
      }
    return out;
  }
  // Otsu on the conductivity change (-x), as KTC's baseline: classes low, middle and high; the
  // largest is water, the others resistive below it and conductive above.
  const Eigen::VectorXd delta = -Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
  const auto [t1, t2] = otsu3_thresholds(delta);
  if (!(t2 > t1)) return out;
  Eigen::Vector3i size = Eigen::Vector3i::Zero();
  auto cls = [&](double d) { return d < t1 ? 0 : (d < t2 ? 1 : 2); };
  for (Eigen::Index k = 0; k < delta.size(); ++k)
    if (std::isfinite(delta[k])) ++size[cls(delta[k])];
  Eigen::Index water = 0;
  size.maxCoeff(&water);
  static constexpr std::uint8_t kClassOf[3][3] = {
      {0, 2, 2},  // water the lowest: both others conductive
      {1, 0, 2},  // water the middle
      {1, 1, 0},  // water the highest: both others resistive
  };
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    for (Eigen::Index j = 0; j < x.cols(); ++j)
      if (std::isfinite(x(i, j))) out(i, j) = kClassOf[water][cls(-x(i, j))];
  return out;
}

}  // namespace eitbench
