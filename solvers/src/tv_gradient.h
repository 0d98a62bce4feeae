#pragma once
// Internal: the gradient operator K of total variation, in either neighbourhood, as the
// primal-dual iteration uses it: K^T z, the projected dual step, and the TV value itself. Each
// term of TV(x) = sum_i w_i |(K x)_i| carries a weight:
//   pixels:   isotropic, forward differences to the right and down in-disk neighbours, w_p the
//             pixel's sensitivity weight s_p; the dual z_p = (zx_p, zy_p) lies in |z_p| <= alpha
//             w_p.
//   elements: anisotropic, K = D P (differences of P x across interior mesh edges), w_e = edge
//             length / pixel width times the mean of P s over the edge's two elements; the dual
//             lies in |z_e| <= alpha w_e.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "eitbench/solvers/linear_problem.h"

namespace eitbench::detail {

class TvGradient {
 public:
  // `sensitivity` holds s_p for each in-disk pixel (all ones for plain TV).
  static TvGradient pixels(const LinearProblem& problem, const Eigen::VectorXd& sensitivity);
  static TvGradient elements(const LinearProblem& problem, const Eigen::VectorXd& sensitivity);

  Eigen::Index duals() const { return duals_; }   // entries of zx (and of zy for pixels)
  double squared_norm() const { return norm2_; }  // an upper bound of ||K||^2

  // v -= tau K^T z.
  void subtract_adjoint(const Eigen::VectorXd& zx, const Eigen::VectorXd& zy, double tau,
                        Eigen::VectorXd& v) const;
  // z += rho (proj(z + sigma K bar) - z), the projection onto the TV dual ball of radius alpha.
  void dual_step(const Eigen::VectorXd& bar, double sigma, double alpha, double rho,
                 Eigen::VectorXd& zx, Eigen::VectorXd& zy, Eigen::VectorXd& kbar) const;
  // sum_i w_i |(K x)_i|.
  double total_variation(const Eigen::VectorXd& x) const;

 private:
  std::vector<int> right_, down_;  // pixels: in-disk neighbour of each unknown, or -1
  Eigen::SparseMatrix<double, Eigen::RowMajor> K_, Kt_;  // elements
  Eigen::VectorXd weight_;                               // w_i
  Eigen::Index duals_ = 0;
  double norm2_ = 8.0;  // pixels: ||forward differences||^2 <= 8
};

}  // namespace eitbench::detail
