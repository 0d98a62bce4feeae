#include "eitbench/jacobian/pixel_grid.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/geometry.h"

namespace eitbench {

PixelGrid::PixelGrid(int size, double radius, const Eigen::Vector2d& centre)
    : size_(size), radius_(radius), centre_(centre) {
  if (size < 1)
    throw InputError("PixelGrid", "size", "must be positive, not " + std::to_string(size));
  if (!(radius > 0) || !std::isfinite(radius))
    throw InputError("PixelGrid", "radius", "must be positive and finite");
  if (!centre.allFinite()) throw InputError("PixelGrid", "centre", "must be finite");
  mask_.resize(num_pixels());
}

PixelGrid::PixelGrid(int size, double radius) : PixelGrid(size, radius, Eigen::Vector2d::Zero()) {
  for (int i = 0; i < size_; ++i)
    for (int j = 0; j < size_; ++j) mask_[i * size_ + j] = center(i, j).norm() < radius_;
}

PixelGrid PixelGrid::covering(const Mesh& mesh, int size) {
  if (mesh.num_nodes() == 0 || mesh.num_triangles() == 0)
    throw InputError("PixelGrid", "mesh", "has no triangles to cover");
  const Eigen::Vector2d lo = mesh.nodes.colwise().minCoeff(), hi = mesh.nodes.colwise().maxCoeff();
  PixelGrid grid(size, 0.5 * (hi - lo).maxCoeff(), 0.5 * (lo + hi));
  grid.disk_ = false;
  grid.mask_.setConstant(false);
  // Each triangle marks the pixel centres it holds: only those in its bounding box are tried, one
  // more on each side, so that rounding cannot drop a centre on the box's edge.
  const double w = grid.pixel_width();
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector2d a = mesh.nodes.row(mesh.triangles(t, 0)),
                          b = mesh.nodes.row(mesh.triangles(t, 1)),
                          c = mesh.nodes.row(mesh.triangles(t, 2));
    const Eigen::Vector2d tlo = a.cwiseMin(b).cwiseMin(c), thi = a.cwiseMax(b).cwiseMax(c);
    const int j0 = std::max(0, static_cast<int>(std::floor((tlo.x() - grid.left()) / w - 0.5)));
    const int j1 =
        std::min(size - 1, static_cast<int>(std::ceil((thi.x() - grid.left()) / w - 0.5)));
    const int i0 = std::max(0, static_cast<int>(std::floor((grid.top() - thi.y()) / w - 0.5)));
    const int i1 =
        std::min(size - 1, static_cast<int>(std::ceil((grid.top() - tlo.y()) / w - 0.5)));
    for (int i = i0; i <= i1; ++i)
      for (int j = j0; j <= j1; ++j)
        if (point_in_triangle(grid.center(i, j), a, b, c)) grid.mask_[i * size + j] = true;
  }
  if (!grid.mask_.any())
    throw InputError("PixelGrid", "size", "no pixel centre falls inside the mesh");
  return grid;
}

Eigen::Vector2d PixelGrid::center(int i, int j) const {
  const double w = pixel_width();
  return {left() + (j + 0.5) * w, top() - (i + 0.5) * w};
}

int PixelGrid::num_inside() const {
  return static_cast<int>(mask_.count());
}

Eigen::SparseMatrix<double, Eigen::RowMajor> pixel_overlap(const Mesh& mesh,
                                                           const PixelGrid& grid) {
  const double w = grid.pixel_width(), X0 = grid.left(), Y0 = grid.top();
  const int n = grid.size();
  std::vector<Eigen::Triplet<double>> entries;
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector2d a = mesh.nodes.row(mesh.triangles(t, 0)),
                          b = mesh.nodes.row(mesh.triangles(t, 1)),
                          c = mesh.nodes.row(mesh.triangles(t, 2));
    const Eigen::Vector2d lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
    // Columns j cover x in [X0 + j w, X0 + (j+1) w]; rows i cover y in [Y0 - (i+1) w, Y0 - i w].
    const int j0 = std::max(0, static_cast<int>(std::floor((lo.x() - X0) / w)));
    const int j1 = std::min(n - 1, static_cast<int>(std::floor((hi.x() - X0) / w)));
    const int i0 = std::max(0, static_cast<int>(std::floor((Y0 - hi.y()) / w)));
    const int i1 = std::min(n - 1, static_cast<int>(std::floor((Y0 - lo.y()) / w)));
    for (int i = i0; i <= i1; ++i)
      for (int j = j0; j <= j1; ++j) {
        const double x0 = X0 + j * w, y1 = Y0 - i * w;
        const double area = triangle_box_overlap(a, b, c, x0, x0 + w, y1 - w, y1);
        if (area > 0) entries.emplace_back(t, i * n + j, area);
      }
  }
  Eigen::SparseMatrix<double, Eigen::RowMajor> overlap(mesh.num_triangles(), grid.num_pixels());
  overlap.setFromTriplets(entries.begin(), entries.end());
  return overlap;
}

Eigen::SparseMatrix<double, Eigen::RowMajor> pixel_to_element(const Mesh& mesh,
                                                              const PixelGrid& grid) {
  return pixel_to_element(mesh, grid, pixel_overlap(mesh, grid));
}

Eigen::SparseMatrix<double, Eigen::RowMajor> pixel_to_element(
    const Mesh& mesh, const PixelGrid& grid,
    const Eigen::SparseMatrix<double, Eigen::RowMajor>& overlap) {
  const auto& mask = grid.mask();
  std::vector<Eigen::Triplet<double>> entries;
  for (int t = 0; t < overlap.rows(); ++t) {
    double total = 0;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(overlap, t); it; ++it)
      if (mask[it.col()]) total += it.value();
    if (total > 0) {
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(overlap, t); it; ++it)
        if (mask[it.col()]) entries.emplace_back(t, it.col(), it.value() / total);
      continue;
    }
    const Eigen::Vector2d centroid = triangle_centroid(mesh, t);
    int best = -1;
    double best_distance = INFINITY;
    for (int p = 0; p < grid.num_pixels(); ++p) {
      if (!mask[p]) continue;
      const double distance =
          (grid.center(p / grid.size(), p % grid.size()) - centroid).squaredNorm();
      if (distance < best_distance) best_distance = distance, best = p;
    }
    entries.emplace_back(t, best, 1.0);
  }
  Eigen::SparseMatrix<double, Eigen::RowMajor> P(overlap.rows(), overlap.cols());
  P.setFromTriplets(entries.begin(), entries.end());
  return P;
}

Eigen::SparseMatrix<double, Eigen::RowMajor> element_to_pixel(const Mesh& mesh,
                                                              const PixelGrid& grid) {
  Eigen::SparseMatrix<double, Eigen::RowMajor> Q = pixel_overlap(mesh, grid).transpose();
  const auto& mask = grid.mask();
  for (int p = 0; p < Q.rows(); ++p) {
    double total = 0;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(Q, p); it; ++it)
      total += it.value();
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(Q, p); it; ++it)
      it.valueRef() = (mask[p] && total > 0) ? it.value() / total : 0.0;
  }
  Q.prune(0.0);
  return Q;
}

Eigen::VectorXd circles_image(const PixelGrid& grid, const std::vector<Circle>& circles,
                              double background) {
  const int n = grid.size();
  const double w = grid.pixel_width(), X0 = grid.left(), Y0 = grid.top();
  Eigen::VectorXd image = Eigen::VectorXd::Zero(grid.num_pixels());
  for (const Circle& c : circles) {
    const double intensity = (background - c.conductivity) / background;
    const int j0 = std::max(0, static_cast<int>(std::floor((c.x - c.r - X0) / w)));
    const int j1 = std::min(n - 1, static_cast<int>(std::floor((c.x + c.r - X0) / w)));
    const int i0 = std::max(0, static_cast<int>(std::floor((Y0 - c.y - c.r) / w)));
    const int i1 = std::min(n - 1, static_cast<int>(std::floor((Y0 - c.y + c.r) / w)));
    const Eigen::Vector2d centre(c.x, c.y);
    const double r2 = c.r * c.r;
    for (int i = i0; i <= i1; ++i)
      for (int j = j0; j <= j1; ++j) {
        if (!grid.mask()[i * n + j]) continue;
        const double x0 = X0 + j * w, y1 = Y0 - i * w;
        // Wholly inside (farthest corner within r) or wholly outside (nearest point beyond r) is
        // exact and cheap; only the pixels the rim crosses need the overlap, as two triangles.
        const double fx = std::max(std::abs(x0 - c.x), std::abs(x0 + w - c.x));
        const double fy = std::max(std::abs(y1 - w - c.y), std::abs(y1 - c.y));
        const double nx = std::max({x0 - c.x, 0.0, c.x - x0 - w}),
                     ny = std::max({y1 - w - c.y, 0.0, c.y - y1});
        double covered;
        if (fx * fx + fy * fy <= r2) {
          covered = w * w;
        } else if (nx * nx + ny * ny >= r2) {
          continue;
        } else {
          const Eigen::Vector2d a(x0, y1 - w), b(x0 + w, y1 - w), cc(x0 + w, y1), d(x0, y1);
          covered = triangle_circle_overlap(a, b, cc, centre, c.r) +
                    triangle_circle_overlap(a, cc, d, centre, c.r);
        }
        image[i * n + j] += intensity * covered / (w * w);
      }
  }
  return image;
}

}  // namespace eitbench
