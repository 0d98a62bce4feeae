#pragma once
// The 64x64 image grid over [-R, R]^2 (docs/conventions.md) and the exact area overlaps between its
// pixels and a mesh's triangles.
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

#include "eitbench/jacobian/geometry.h"
#include "eitbench/jacobian/mesh.h"

namespace eitbench {

class PixelGrid {
 public:
  // size >= 1 and radius positive and finite (a data set's or a user's); InputError("PixelGrid",
  // field) otherwise.
  explicit PixelGrid(int size = 64, double radius = 1.0);

  int size() const { return size_; }
  int num_pixels() const { return size_ * size_; }
  double radius() const { return radius_; }
  double pixel_width() const { return 2.0 * radius_ / size_; }
  // Pixel (i, j) -> index i * size + j; row 0 at the top, y up.
  Eigen::Vector2d center(int i, int j) const;
  // True for pixels whose centre lies inside the disk; the others are masked and hold 0.
  const Eigen::Array<bool, Eigen::Dynamic, 1>& mask() const { return mask_; }
  int num_inside() const;

 private:
  int size_;
  double radius_;
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
