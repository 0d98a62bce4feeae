#pragma once
// The shape reconstructor's forward map (internal to solvers/): K circular touches on the
// background, each a smoothed indicator over the reconstruction mesh's elements, and the reduced
// frame they give, linearised at the background or re-solved by the FEM. Parameters are K blocks
// of [cx, cy, r, c]: centre and radius in sensor units, c the touch's intensity on the label scale
// (sigma = sigma_0 (1 - c) inside), so the image they draw is directly comparable with labels.
#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "eitbench/solvers/linear_problem.h"

namespace eitbench::detail {

constexpr int kCircleParameters = 4;  // cx, cy, r, c

class ShapeModel {
 public:
  // width: the indicator's transition width (sensor units); 0 takes half the mesh's mean element
  // size, so that the 12-88 % transition spans about one element.
  ShapeModel(const LinearProblem& problem, double width);

  const LinearProblem& problem() const { return problem_; }
  double width() const { return width_; }
  int measurements() const { return static_cast<int>(J0_.rows()); }
  const Eigen::VectorXd& reference() const { return v0_; }  // v(sigma_0), the inputs

  // s = sigma / sigma_0 per element: prod_j (1 - c_j H_j), H_j = (1 + tanh((r_j - d_j) / w)) / 2
  // with d_j the element centroid's distance from centre j. The product keeps sigma positive
  // where touches overlap and equals the sum where they do not.
  Eigen::VectorXd relative_sigma(const std::vector<const double*>& circles) const;
  // d s / d p: triangles x 4K, by the chain rule through H; with `elements`, their rows only.
  Eigen::MatrixXd relative_sigma_jacobian(const std::vector<const double*>& circles,
                                          const std::vector<int>& elements = {}) const;
  // The elements some circle reaches (below), in ascending order.
  std::vector<int> reached_elements(const std::vector<const double*>& circles) const;

  // A circle reaches the elements whose centroid lies within r + kReach w of its centre. Beyond,
  // its H is below 1.3e-5 (1 - tanh(u) < 2 exp(-2u)): a thousandth of the model's own error (about
  // 1 % of a frame). Both models take H as zero there, so that the full model's Jacobian needs
  // the reached elements' columns only, and the linear model sums over them only. At 9.5 widths
  // (1e-8) it summed over twice as many.
  static constexpr double kReach = 6;

  // The difference inputs v(sigma) - v(sigma_0) and its Jacobian d/dp (m x 4K, when given):
  // linear, J0 sigma_0 (s - 1); or full, one FEM solve and the element Jacobian at sigma.
  Eigen::VectorXd difference(const std::vector<const double*>& circles, bool full,
                             Eigen::MatrixXd* jacobian) const;

 private:
  Eigen::VectorXd linear_difference(const std::vector<const double*>& circles,
                                    Eigen::MatrixXd* jacobian) const;
  // f times d s / d p of circle p at element t, [cx, cy, r, c], from its distance d and its
  // indicator's h and dh/dr; f is minus the other circles' factors (and sigma_0 in the frame).
  // Both models' Jacobians take it.
  Eigen::Vector4d scaled_derivatives(Eigen::Index t, const double* p, double d, double h,
                                     double dh_dr, double f) const;
  // Elements first..last-1's terms of linear_difference, added to v and *jacobian.
  void add_linear_terms(const std::vector<const double*>& circles, Eigen::Index first,
                        Eigen::Index last, Eigen::VectorXd& v, Eigen::MatrixXd* jacobian) const;
  // The distance from element t's centroid to the centre of circle p (sqrt, not hypot: the
  // values are of order 1, and hypot's care for overflow cost a twentieth of a fit).
  double distance(Eigen::Index t, const double* p) const {
    const double dx = centroids_(0, t) - p[0], dy = centroids_(1, t) - p[1];
    return std::sqrt(dx * dx + dy * dy);
  }
  const LinearProblem& problem_;
  Eigen::Matrix2Xd centroids_;
  double width_;
  Eigen::MatrixXd J0_;  // d v / d sigma at sigma_0, input rows x triangles
  Eigen::VectorXd v0_;
};

}  // namespace eitbench::detail
