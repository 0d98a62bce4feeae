#pragma once
// A reconstruction on KTC's terms (docs/ktc.md#segmentation): the image resampled onto KTC's
// 256 x 256 grid in KTC's orientation, then cut into three classes (0 water, 1 resistive,
// 2 conductive). Images come on eitbench's label scale, x = -dsigma / sigma_0, so a resistive
// target is positive and a conductive one negative.
#include <Eigen/Core>
#include <string>

#include "eitbench/bench/ktc/score.h"
#include "eitbench/jacobian/pixel_grid.h"

namespace eitbench {

// Where the model's electrodes lie on KTC's image. The model puts electrode e (0-based) at angle
// 2 pi e / L, counter-clockwise from +x; on KTC's image (row 0 at the top, y up, centred on the
// tank) electrode 1 sits at `first_electrode_angle` and the rest follow clockwise or not.
// The defaults are what the four training truths give (docs/ktc.md#orientation).
struct KtcOrientation {
  // Radians, counter-clockwise from +x on the image: pi / 2, electrode 1 at the top.
  double first_electrode_angle = 1.5707963267948966;
  bool clockwise = false;

  // The model's point under image point (x, y).
  Eigen::Vector2d to_model(const Eigen::Vector2d& image_point) const;
  // The image point over a model point: to_model's inverse.
  Eigen::Vector2d to_image(const Eigen::Vector2d& model_point) const;
};

// The image (grid.num_pixels() values on `grid`, a disk grid of the tank's radius R) on KTC's
// 256 x 256 grid over [-R, R]^2: bilinear between the in-disk pixel centres (masked neighbours
// left out, the weights renormalised), NaN outside the disk. Row 0 at the top.
Eigen::MatrixXd to_ktc_grid(const Eigen::VectorXd& image, const PixelGrid& grid,
                            const KtcOrientation& orientation);

enum class SegmentationKind {
  otsu,    // KTC's baseline: three-class Otsu on a 256-bin histogram, the largest class water
  levels,  // fixed fractions of the image's largest |x|, tuned on labelled samples
};
// otsu | levels; InputError("SegmentationKind", "name") otherwise.
SegmentationKind parse_segmentation(const std::string& name);
std::string to_string(SegmentationKind kind);

struct SegmentationRule {
  SegmentationKind kind = SegmentationKind::otsu;
  // levels: resistive where x >= resistive * max|x|, conductive where x <= -conductive * max|x|;
  // each in (0, 1].
  double resistive = 0.5, conductive = 0.5;

  // InputError("SegmentationRule", field) for a level out of range.
  void validate() const;
  std::string to_string() const;  // "otsu" or "levels r=0.4 c=0.6"
};

// The classes of a KTC-grid image (to_ktc_grid's: NaN outside the tank, which is water).
ClassImage segment(const Eigen::MatrixXd& ktc_image, const SegmentationRule& rule);

// The two thresholds of three-class Otsu on `values` (the finite ones, in a histogram of `bins`
// equal bins between their least and largest), as KTC's Otsu2: the bin edges t1 < t2 that
// maximise the between-class variance of the classes x < t1, t1 <= x < t2 and x >= t2.
// std::invalid_argument for fewer than 3 bins; both thresholds equal the value when all are one.
std::pair<double, double> otsu3_thresholds(const Eigen::VectorXd& values, int bins = 256);

}  // namespace eitbench
