#include "operator_norm.h"

#include <algorithm>
#include <cmath>

#include "eitbench/jacobian/random.h"

namespace eitbench::detail {

double squared_operator_norm(const Eigen::SparseMatrix<double, Eigen::RowMajor>& K,
                             int iterations) {
  // ||K||_2^2 <= ||K||_1 ||K||_inf: the largest absolute column sum times the largest row sum.
  Eigen::VectorXd column_sums = Eigen::VectorXd::Zero(K.cols());
  Eigen::VectorXd row_sums = Eigen::VectorXd::Zero(K.rows());
  for (Eigen::Index r = 0; r < K.outerSize(); ++r)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(K, r); it; ++it)
      column_sums[it.col()] += std::abs(it.value()), row_sums[r] += std::abs(it.value());
  const double bound = K.nonZeros() == 0 ? 0.0 : column_sums.maxCoeff() * row_sums.maxCoeff();
  RandomStream rng(0x7e57, 0);
  Eigen::VectorXd u(K.cols());
  for (Eigen::Index i = 0; i < u.size(); ++i) u[i] = rng.normal();
  double estimate = 0;
  for (int k = 0; k < iterations && u.norm() > 0; ++k) {
    const Eigen::VectorXd w = K.transpose() * (K * u);
    estimate = w.norm() / u.norm();
    u = w / std::max(w.norm(), 1e-300);
  }
  if (!(estimate > 0) || !std::isfinite(estimate)) return bound;
  return std::min(1.05 * estimate, bound);
}

}  // namespace eitbench::detail
