#pragma once
// Touches as a tactile-sensor user sees them: circles in sensor coordinates with a contrast, found
// in a reconstructed image by thresholding and blob detection, or taken from circles a method (or
// the data set's truth) gives directly. touch_metrics.h scores them against the truth.
#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "eitbench/jacobian/geometry.h"
#include "eitbench/jacobian/pixel_grid.h"
#include "eitbench/jacobian/sample_matrix.h"

namespace eitbench {

// One touch: centre and radius in sensor units, contrast on the label scale (sigma_0 - sigma) /
// sigma_0 (docs/conventions.md#labels): positive inside a touch.
struct Touch {
  double x = 0, y = 0, r = 0;
  double contrast = 0;
  // A true touch's share of its frame's change (touch_signal.h); NaN when not known, and for a
  // found touch.
  double signal = NAN;
};
using TouchFrames = std::vector<std::vector<Touch>>;  // one list a frame

struct TouchOptions {
  // The blob thresholds the benchmark chooses from on validation frames, each a fraction of the
  // image's in-disk maximum: a relative rule, since the methods' images differ in amplitude (their
  // priors and hyperparameters set it) more than in the shape of a blob.
  std::vector<double> thresholds{0.3, 0.4, 0.5, 0.6, 0.7};
  // Blobs below this area (x R^2) are dropped as noise: an equivalent radius of 0.04 R, about 5
  // pixels of the 64 x 64 grid. The smallest simulated touch (r = 0.05 R) covers 0.0079 R^2.
  double min_area = 0.005;
  // A found touch matches a true one only within this centre distance (x R): beyond it, it is a
  // phantom and the true touch is missed. The simulated touches' radii reach 0.25 R.
  double gate = 0.3;
  void validate() const;  // InputError("TouchOptions", field) on a value out of range
};

// The touches of one image (n^2 pixels, row-major, on the label scale): the in-disk pixels with a
// value >= threshold x the image's in-disk maximum, joined into blobs by OpenCV's connected
// components (8-connectivity); blobs under options.min_area are dropped. Each blob gives its
// intensity-weighted centroid (robust to a blob's ragged rim), the radius of the circle of its
// area, sqrt(area / pi), and its peak value as the contrast. None when the maximum is not positive.
// InputError for a threshold outside (0, 1] or an image of the wrong size.
std::vector<Touch> find_touches(const Eigen::VectorXd& image, const PixelGrid& grid,
                                double threshold, const TouchOptions& options = {});
// find_touches on each row of `images`.
TouchFrames touches_in_images(const SampleMatrix& images, const PixelGrid& grid, double threshold,
                              const TouchOptions& options = {});

// One touch for the whole image, where a single press is known to be: the intensity-weighted
// centroid of every in-disk pixel >= threshold x the in-disk maximum, whatever blob it lies in
// (pyEIT's rule for a press), the radius of the circle of their area and the maximum as the
// contrast. Where a prior leaves spikes beside the touch (the identity prior's, at the rim), the
// strongest blob may be a spike; the centroid weighs every pixel above the threshold instead. None
// when the maximum is not positive. InputError as find_touches.
std::vector<Touch> centroid_touch(const Eigen::VectorXd& image, const PixelGrid& grid,
                                  double threshold);

// Circles (the data set's truth, or a method that fits circles) as touches: the contrast from the
// conductivity, (background - sigma) / background.
std::vector<Touch> touches_of(const std::vector<Circle>& circles, double background);
TouchFrames touches_of(const std::vector<std::vector<Circle>>& circles, double background);

}  // namespace eitbench
