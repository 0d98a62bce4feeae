#pragma once
// Label images under the group: exact for touches given as circles (re-rasterise the moved
// circles with circles_image), bilinear through a per-element stencil for plain images.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "eitbench/augment/sensor_group.h"
#include "eitbench/augment/symmetry.h"
#include "eitbench/jacobian/pixel_grid.h"

namespace eitbench {

// Moves images by group elements: out(x) = in(g^-1 x), sampled bilinearly, then masked to the disk.
// Each element's action is a precomputed table (a stencil: four source pixels and weights for every
// output pixel), so moving an image is one gather. Exact for the mirror and for rotations by
// multiples of 90 degrees, which permute the square grid's pixels; otherwise interpolation smooths
// edges: on circle touches the relative L2 error against exact re-rasterisation is 8 % on average
// (augment_test, docs/augmentation.md).
//
// On a sensor of another shape (ShapedSensor) the same, with the sensor's isometries on its own
// grid: the rotations by 90 degrees and the mirrors of a square or an ellipse centred in the grid's
// box permute its pixels, so their stencils are exact too.
class ImageSymmetry {
 public:
  // The disk: D_L's maps about the origin (transform_point).
  ImageSymmetry(int electrodes, const PixelGrid& grid);
  // A sensor of any shape: its group's elements only (InputError naming the element for others).
  explicit ImageSymmetry(std::shared_ptr<const ShapedSensor> sensor);
  Eigen::VectorXd apply(const GroupElement& g, const Eigen::VectorXd& image) const;
  const PixelGrid& grid() const { return grid_; }
  // g's action on points and on touches.
  Eigen::Vector2d move(const Eigen::Vector2d& x, const GroupElement& g) const;
  std::vector<Circle> move(const std::vector<Circle>& circles, const GroupElement& g) const;

  // out[p] = sum_k weight[4p + k] image[index[4p + k]].
  struct Stencil {
    std::vector<int> index;
    std::vector<double> weight;
  };
  const Stencil& stencil(const GroupElement& g) const;
  static Stencil stencil(const GroupElement& g, int electrodes, const PixelGrid& grid);
  static Eigen::VectorXd gather(const Stencil& stencil, const Eigen::VectorXd& image);

 private:
  int electrodes_;
  PixelGrid grid_;
  std::shared_ptr<const ShapedSensor> sensor_;  // null: the disk
  std::vector<Stencil> stencils_;  // per element index: rotations, then mirrors (empty: lacking)
};

// A sample's label under g: exact, by re-rasterising its moved circles, when `circles` is given
// (touch intensity against `background`); bilinear from `label` otherwise.
Eigen::VectorXd moved_label(const Eigen::VectorXd& label, const std::vector<Circle>* circles,
                            double background, const GroupElement& g, const ImageSymmetry& images);

// One-off: the same as ImageSymmetry(electrodes, grid).apply(g, image), computing g's stencil only.
Eigen::VectorXd transform_image(const Eigen::VectorXd& image, const GroupElement& g, int electrodes,
                                const PixelGrid& grid);

}  // namespace eitbench
