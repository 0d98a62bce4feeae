#pragma once
// Internal: ||K||_2^2 for the step sizes of a primal-dual method, which need tau sigma ||K||^2 < 1.
#include <Eigen/SparseCore>

namespace eitbench::detail {

// The largest eigenvalue of K^T K by power iteration, 5 % above the estimate (power iteration
// approaches it from below), and never above the bound ||K||_1 ||K||_inf. The start vector is
// pseudo-random: a difference operator maps the constant vector to zero, and a start there would
// give 0/0.
double squared_operator_norm(const Eigen::SparseMatrix<double, Eigen::RowMajor>& K,
                             int iterations = 200);

}  // namespace eitbench::detail
