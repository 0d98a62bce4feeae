#pragma once
// The image grid: size x size square pixels over a square box, [-R, R]^2 for the disk
// (docs/conventions.md) or the box around a sensor of any shape (docs/sensors.md), pixels outside
// the sensor masked; and the exact area overlaps between its pixels and a mesh's triangles.
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

#include "eitbench/jacobian/geometry.h"
#include "eitbench/jacobian/mesh.h"

namespace eitbench {

class PixelGrid {
 public:
  // The disk's grid over [-radius, radius]^2, pixels inside the disk of that radius about the
  // origin. size >= 1 and radius positive and finite (a data set's or a user's);
  // InputError("PixelGrid", field) otherwise.
  explicit PixelGrid(int size = 64, double radius = 1.0);

  // A sensor of any shape: the square box centred on the mesh's bounding box, its half-side the
  // larger half-extent (so the box is the disk's [-R, R]^2 for a disk about the origin), a pixel
  // inside when its centre lies in one of the mesh's triangles. Rows and columns stay equal, so
  // the learned decoder's square output and every image figure serve any sensor; a 2:1 sensor
  // leaves half the pixels masked. InputError("PixelGrid", field) as above, or for an empty mesh.
  static PixelGrid covering(const Mesh& mesh, int size = 64);

  int size() const { return size_; }
  int num_pixels() const { return size_ * size_; }
  // Half the box's side: the sensor's length scale R (touch errors are fractions of it).
  double radius() const { return radius_; }
  // The box's centre: the origin for the disk's grid.
  const Eigen::Vector2d& box_centre() const { return centre_; }
  double pixel_width() const { return 2.0 * radius_ / size_; }
  double left() const { return centre_.x() - radius_; }  // x of column 0's left edge
  double top() const { return centre_.y() + radius_; }   // y of row 0's top edge
  // Pixel (i, j) -> index i * size + j; row 0 at the top, y up.
  Eigen::Vector2d center(int i, int j) const;
  // True for pixels whose centre lies inside the sensor; the others are masked and hold 0.
  const Eigen::Array<bool, Eigen::Dynamic, 1>& mask() const { return mask_; }
  int num_inside() const;
  // Whether this is the disk's grid (the constructor above) rather than covering()'s.
  bool is_disk() const { return disk_; }

 private:
  PixelGrid(int size, double radius, const Eigen::Vector2d& centre);
  int size_;
  double radius_;
  Eigen::Vector2d centre_ = Eigen::Vector2d::Zero();
  bool disk_ = true;
  Eigen::Array<bool, Eigen::Dynamic, 1> mask_;
};

// Exact area of triangle t intersected with pixel p, as a triangles x pixels sparse matrix.
Eigen::SparseMatrix<double, Eigen::RowMajor> pixel_overlap(const Mesh& mesh, const PixelGrid& grid);

// P (triangles x pixels): each element's conductivity as the area-weighted mean of the in-disk
// pixels over it, so sigma_elem = P sigma_pix and J_pix = J_elem P. Rows sum to 1. A boundary
// triangle that covers only masked pixels takes the in-disk pixel nearest its centroid.
Eigen::SparseMatrix<double, Eigen::RowMajor> pixel_to_element(const Mesh& mesh,
                                                              const PixelGrid& grid);
// The same from overlaps already computed by pixel_overlap(mesh, grid).
Eigen::SparseMatrix<double, Eigen::RowMajor> pixel_to_element(
    const Mesh& mesh, const PixelGrid& grid,
    const Eigen::SparseMatrix<double, Eigen::RowMajor>& overlap);

// Q (pixels x triangles): each in-disk pixel's value as the area-weighted mean of the elements over
// it (images of element data); masked pixels get an empty row and hold 0.
Eigen::SparseMatrix<double, Eigen::RowMajor> element_to_pixel(const Mesh& mesh,
                                                              const PixelGrid& grid);

// The label image of circular inclusions (docs/conventions.md): per pixel, the touch intensity
// (sigma_0 - sigma) / sigma_0 weighted by the exact fraction of the pixel each circle covers.
// Masked pixels hold 0. One value per pixel, row-major (index i * size + j).
Eigen::VectorXd circles_image(const PixelGrid& grid, const std::vector<Circle>& circles,
                              double background);

}  // namespace eitbench
