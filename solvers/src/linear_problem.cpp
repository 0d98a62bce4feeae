#include "eitbench/solvers/linear_problem.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "eitbench/jacobian/error.h"

#include "neighbour_graphs.h"
namespace eitbench {

Eigen::Vector2d LinearProblem::pixel_centre(Eigen::Index j) const {
  const int pixel = pixels[static_cast<std::size_t>(j)];
  return grid.center(pixel / grid.size(), pixel % grid.size());
}

Eigen::VectorXd LinearProblem::to_image(const Eigen::VectorXd& x) const {
  Eigen::VectorXd image = Eigen::VectorXd::Zero(grid.num_pixels());
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
  SampleMatrix images = SampleMatrix::Zero(rows.rows(), grid.num_pixels());
  for (std::size_t j = 0; j < pixels.size(); ++j)
    images.col(pixels[j]) = rows.col(static_cast<Eigen::Index>(j));
  return images;
}

Eigen::VectorXd LinearProblem::data_of(const Eigen::VectorXd& inputs) const {
  const int all = model ? model->measurement_protocol().input_size() : measurements();
  if (inputs.size() != all)
    throw InputError("frame", "",
                     "has " + std::to_string(inputs.size()) + " values; the protocol has " +
                         std::to_string(all) + " inputs");
  if (rows.empty()) return weights.size() ? Eigen::VectorXd(inputs.cwiseProduct(weights)) : inputs;
  Eigen::VectorXd out(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t i = 0; i < rows.size(); ++i) out[static_cast<Eigen::Index>(i)] = inputs[rows[i]];
  return weights.size() ? Eigen::VectorXd(out.cwiseProduct(weights)) : out;
}

Eigen::VectorXd LinearProblem::model_inputs(const ForwardSolution& solution) const {
  return data_of(model->inputs(solution));
}

Eigen::MatrixXd LinearProblem::model_jacobian(const ForwardSolution& solution,
                                              const std::vector<int>& elements) const {
  Eigen::MatrixXd J = model->input_jacobian(solution, elements);
  if (!rows.empty()) {
    Eigen::MatrixXd picked(static_cast<Eigen::Index>(rows.size()), J.cols());
    for (std::size_t i = 0; i < rows.size(); ++i)
      picked.row(static_cast<Eigen::Index>(i)) = J.row(rows[i]);
    J = std::move(picked);
  }
  if (weights.size()) J = weights.asDiagonal() * J;
  return J;
}

void LinearProblem::check_frame_size(Eigen::Index values) const {
  if (values != measurements())
    throw InputError("frame", "",
                     "has " + std::to_string(values) + " values; the model expects " +
                         std::to_string(measurements()) + " (the " +
                         (model ? model->measurement_protocol().name() : std::string("adjacent")) +
                         " protocol's inputs)");
}

namespace {

// The least share of the mesh's area and of the in-disk pixels' area that must overlap. Disk
// meshes (L = 8, 16, 32; coarse to fine) against grids of 16 to 128 pixels overlap at least 99.1 %
// of the mesh and 95.7 % of the pixels (the rim pixels overhang the disk, most on coarse grids);
// a mesh in other units, off centre by a fifth of R or more, or of another shape falls short.
constexpr double kDiskCoverage = 0.9;

// The pixel basis assumes the mesh is the grid's sensor: the disk of grid.radius() about the
// origin, or the mesh the grid was made to cover. A mesh in other units, off centre or of another
// shape would give a wrong A without an error, so the overlap of the mesh with the in-disk pixels
// must cover nearly all of both.
void check_mesh_is_the_grids_disk(const Mesh& mesh, const PixelGrid& grid,
                                  const Eigen::SparseMatrix<double, Eigen::RowMajor>& overlap) {
  double shared = 0;
  for (int t = 0; t < overlap.rows(); ++t)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(overlap, t); it; ++it)
      if (grid.mask()[it.col()]) shared += it.value();
  const double mesh_area = triangle_areas(mesh).cwiseAbs().sum();
  const double pixel_area = grid.num_inside() * std::pow(grid.pixel_width(), 2);
  const double of_mesh = shared / mesh_area, of_pixels = shared / pixel_area;
  if (of_mesh < kDiskCoverage || of_pixels < kDiskCoverage) {
    char message[256];
    if (grid.is_disk())
      std::snprintf(message, sizeof message,
                    "is not the pixel grid's disk (radius %g about the origin): the in-disk pixels "
                    "cover %.1f %% of the mesh and the mesh %.1f %% of them (check the mesh's "
                    "units and centre)",
                    grid.radius(), 100 * of_mesh, 100 * of_pixels);
    else
      std::snprintf(message, sizeof message,
                    "is not the sensor the pixel grid covers: its unmasked pixels cover %.1f %% of "
                    "the mesh and the mesh %.1f %% of them (make the grid from this mesh)",
                    100 * of_mesh, 100 * of_pixels);
    throw InputError("mesh", "", message);
  }
}

}  // namespace

std::shared_ptr<const LinearProblem> require_problem(std::shared_ptr<const LinearProblem> problem,
                                                     const char* who) {
  if (!problem) throw std::invalid_argument(std::string(who) + ": no linear problem");
  return problem;
}

LinearProblem make_linear_problem(std::shared_ptr<const ForwardModel> model, double background,
                                  const PixelGrid& grid) {
  if (!(background > 0) || !std::isfinite(background))
    throw InputError("background", "", "the background conductivity must be positive and finite");
  LinearProblem p;
  p.model = model;
  p.background = background;
  p.grid = grid;
  for (int k = 0; k < grid.num_pixels(); ++k)
    if (grid.mask()[k]) p.pixels.push_back(k);
  const Mesh& mesh = model->mesh();
  const auto overlap = pixel_overlap(mesh, grid);
  check_mesh_is_the_grids_disk(mesh, grid, overlap);
  // Columns of P for the in-disk pixels only (P has no weight on the others).
  const auto full = pixel_to_element(mesh, grid, overlap);
  const std::vector<int> column = detail::unknown_of_pixel(p.pixels, grid.num_pixels());
  std::vector<Eigen::Triplet<double>> entries;
  for (int t = 0; t < full.rows(); ++t)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(full, t); it; ++it)
      entries.emplace_back(t, column[it.col()], it.value());
  p.element_from_pixels.resize(full.rows(), static_cast<Eigen::Index>(p.pixels.size()));
  p.element_from_pixels.setFromTriplets(entries.begin(), entries.end());
  const Eigen::MatrixXd J = model->input_jacobian(
      model->solve(Eigen::VectorXd::Constant(mesh.num_triangles(), background)));
  p.A = -background * (J * p.element_from_pixels);
  return p;
}

LinearProblem restrict_problem(const LinearProblem& full, std::vector<int> rows,
                               Eigen::VectorXd weights) {
  if (!full.rows.empty() || full.weights.size())
    throw std::invalid_argument("restrict_problem: the problem is already restricted");
  if (weights.size() && weights.size() != static_cast<Eigen::Index>(rows.size()))
    throw std::invalid_argument("restrict_problem: one weight a row");
  if (weights.size() && (!weights.allFinite() || !(weights.minCoeff() > 0)))
    throw std::invalid_argument("restrict_problem: weights must be positive and finite");
  std::vector<bool> seen(static_cast<std::size_t>(full.measurements()), false);
  for (int r : rows) {
    if (r < 0 || r >= full.measurements() || seen[static_cast<std::size_t>(r)])
      throw std::invalid_argument("restrict_problem: a row out of range or repeated");
    seen[static_cast<std::size_t>(r)] = true;
  }
  LinearProblem p;
  p.pixels = full.pixels;
  p.grid = full.grid;
  p.background = full.background;
  p.model = full.model;
  p.element_from_pixels = full.element_from_pixels;
  p.A.resize(static_cast<Eigen::Index>(rows.size()), full.A.cols());
  for (std::size_t i = 0; i < rows.size(); ++i)
    p.A.row(static_cast<Eigen::Index>(i)) = full.A.row(rows[i]);
  if (weights.size()) p.A = weights.asDiagonal() * p.A;
  p.rows = std::move(rows);
  p.weights = std::move(weights);
  return p;
}

}  // namespace eitbench
