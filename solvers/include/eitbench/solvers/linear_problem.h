#pragma once
// The linearised inverse problem every model-based reconstructor starts from, on the label scale:
//   dv ~= A x,   x = -dsigma / sigma_0 on the in-disk pixels,   A = -sigma_0 J_pix,
// with the Jacobian J_pix = J_elem P taken at the background sigma_0 on the reconstruction mesh,
// rows the protocol's inputs (the reduced 104 for the adjacent one). Solutions are images on the
// label scale directly (docs/conventions.md).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "eitbench/jacobian/forward_model.h"
#include "eitbench/jacobian/pixel_grid.h"
#include "eitbench/jacobian/sample_matrix.h"

namespace eitbench {

struct LinearProblem {
  Eigen::MatrixXd A;        // m x n: m inputs of the protocol, n in-disk pixels
  std::vector<int> pixels;  // column j is image pixel pixels[j]
  PixelGrid grid;           // the image grid: the disk's, or one covering a sensor of any shape
  double background = 1.0;
  // What Gauss-Newton needs to re-linearise: the model and the pixel-to-element map.
  std::shared_ptr<const ForwardModel> model;
  Eigen::SparseMatrix<double, Eigen::RowMajor>
      element_from_pixels;  // triangles x n (in-disk columns)

  // The data term (docs/reconstructors.md#missing-values): A's rows are the protocol's inputs
  // `rows`, in that order (every input when empty), each weighted by `weights` (one over its
  // noise's standard deviation; every weight 1 when empty). Frames given to a reconstructor are
  // already so selected and weighted (data_of); MissingValues (missing_values.h) makes them.
  std::vector<int> rows;
  Eigen::VectorXd weights;

  // The protocol's inputs of a frame, selected and weighted as A's rows (InputError when the
  // frame does not have the protocol's inputs).
  Eigen::VectorXd data_of(const Eigen::VectorXd& inputs) const;
  // What the iterative methods re-linearise with: the model's inputs of a forward solution, and
  // their Jacobian on the elements (or on `elements` only), selected and weighted as A's rows.
  Eigen::VectorXd model_inputs(const ForwardSolution& solution) const;
  Eigen::MatrixXd model_jacobian(const ForwardSolution& solution,
                                 const std::vector<int>& elements = {}) const;

  // The centre of column j's pixel (grid.center of pixels[j]).
  Eigen::Vector2d pixel_centre(Eigen::Index j) const;
  int measurements() const { return static_cast<int>(A.rows()); }
  int unknowns() const { return static_cast<int>(A.cols()); }
  // An n-vector of pixel values as an image of grid.num_pixels() values (masked pixels 0), and
  // back.
  Eigen::VectorXd to_image(const Eigen::VectorXd& x) const;
  Eigen::VectorXd from_image(const Eigen::VectorXd& image) const;
  // Rows of pixel values (N x n) as images (N x grid.num_pixels()).
  SampleMatrix to_images(const Eigen::MatrixXd& rows) const;
  // Throws InputError when frames do not have `measurements()` values.
  void check_frame_size(Eigen::Index values) const;
};

// `problem` itself, for a solver to keep; std::invalid_argument naming `who` when it is null.
std::shared_ptr<const LinearProblem> require_problem(std::shared_ptr<const LinearProblem> problem,
                                                     const char* who);

// Builds A for a mesh, a background conductivity and a pixel grid: every input, weight 1.
LinearProblem make_linear_problem(std::shared_ptr<const ForwardModel> model, double background,
                                  const PixelGrid& grid);

// `full` (every input, weight 1) on the inputs `rows` only, each weighted by `weights` (one per
// row, positive and finite; empty: 1): A's rows picked and scaled, nothing recomputed.
// std::invalid_argument for a row out of range, a repeated row or a bad weight.
LinearProblem restrict_problem(const LinearProblem& full, std::vector<int> rows,
                               Eigen::VectorXd weights = {});

}  // namespace eitbench
