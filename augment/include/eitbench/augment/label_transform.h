#pragma once
// Label images under the group: exact for touches given as circles (re-rasterised), bilinear
// (OpenCV) for plain images.
#include <Eigen/Core>

#include "eitbench/augment/symmetry.h"
#include "eitbench/jacobian/pixel_grid.h"

namespace eitbench {

// The image of the touch g moves: out(x) = in(g^-1 x), by bilinear interpolation on the grid, then
// masked to the disk. Exact for the mirror and for rotations by multiples of 90 degrees (pixel
// permutations of the square grid); otherwise interpolation smooths edges: on circle touches the
// relative L2 error against exact re-rasterisation is measured in augment_test (README,
// "Augmentation").
Eigen::VectorXd transform_image(const Eigen::VectorXd& image, const GroupElement& g, int electrodes,
                                const PixelGrid& grid);

}  // namespace eitbench
