#include "eitbench/solvers/linear_problem.h"

#include <stdexcept>

#include "eitbench/jacobian/error.h"

namespace eitbench {

Eigen::VectorXd LinearProblem::to_image(const Eigen::VectorXd& x) const {
  Eigen::VectorXd image = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(image_size) * image_size);
  for (std::size_t j = 0; j < pixels.size(); ++j)
    image[pixels[j]] = x[static_cast<Eigen::Index>(j)];
  return image;
}

Eigen::VectorXd LinearProblem::from_image(const Eigen::VectorXd& image) const {
  Eigen::VectorXd x(static_cast<Eigen::Index>(pixels.size()));
  for (std::size_t j = 0; j < pixels.size(); ++j)
    x[static_cast<Eigen::Index>(j)] = image[pixels[j]];
  return x;
}

SampleMatrix LinearProblem::to_images(const Eigen::MatrixXd& rows) const {
  SampleMatrix images =
      SampleMatrix::Zero(rows.rows(), static_cast<Eigen::Index>(image_size) * image_size);
  for (std::size_t j = 0; j < pixels.size(); ++j)
    images.col(pixels[j]) = rows.col(static_cast<Eigen::Index>(j));
  return images;
}

void LinearProblem::check_frame_size(Eigen::Index values) const {
  if (values != measurements())
    throw InputError("frame", "",
                     "has " + std::to_string(values) + " values; the model expects " +
                         std::to_string(measurements()) + " (the reduced layout)");
}

LinearProblem make_linear_problem(std::shared_ptr<const ForwardModel> model, double background,
                                  const PixelGrid& grid) {
  if (!(background > 0))
    throw std::invalid_argument("make_linear_problem: the background must be positive");
  LinearProblem p;
  p.model = model;
  p.background = background;
  p.image_size = grid.size();
  p.radius = grid.radius();
  for (int k = 0; k < grid.num_pixels(); ++k)
    if (grid.mask()[k]) p.pixels.push_back(k);
  const Mesh& mesh = model->mesh();
  // Columns of P for the in-disk pixels only (P has no weight on the others).
  const auto full = eitbench::pixel_to_element(mesh, grid);
  std::vector<int> column(grid.num_pixels(), -1);
  for (std::size_t j = 0; j < p.pixels.size(); ++j) column[p.pixels[j]] = static_cast<int>(j);
  std::vector<Eigen::Triplet<double>> entries;
  for (int t = 0; t < full.rows(); ++t)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(full, t); it; ++it)
      entries.emplace_back(t, column[it.col()], it.value());
  p.pixel_to_element.resize(full.rows(), static_cast<Eigen::Index>(p.pixels.size()));
  p.pixel_to_element.setFromTriplets(entries.begin(), entries.end());
  const Eigen::MatrixXd J = model->protocol().select_rows(
      model->jacobian(Eigen::VectorXd::Constant(mesh.num_triangles(), background)),
      MeasurementOrder::rotating, true);
  p.A = -background * (J * p.pixel_to_element);
  return p;
}

}  // namespace eitbench
