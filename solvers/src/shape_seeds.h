#pragma once
// Where the shape fit starts (internal to solvers/): the peaks of a one-step image, each with the
// radius of its share of the blob around it.
#include <Eigen/Core>
#include <vector>

#include "eitbench/jacobian/pixel_grid.h"
#include "shape_fit.h"

namespace eitbench::detail {

// Local maxima of `image` (on `grid`, row 0 at the top) of at least
// `threshold` times its maximum, strongest first, at most `max_seeds`: centre at the pixel,
// radius sqrt(area / pi) of the above-threshold blob it lies in (shared by the blob's peaks),
// intensity `intensity`. None when the image has no positive value.
std::vector<CircleParameters> image_seeds(const Eigen::VectorXd& image, const PixelGrid& grid,
                                          double threshold, int max_seeds, double intensity);

}  // namespace eitbench::detail
