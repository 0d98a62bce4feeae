#pragma once
// The dense products, symmetric eigendecompositions and Cholesky solves that build the Tikhonov
// family, TV and GREIT and take Gauss-Newton's steps, through the system's BLAS and LAPACK where
// the build found them (EITBENCH_WITH_LAPACK), else through Eigen. On KTC's 2,356-value frame
// (2-core Intel Xeon) LAPACK's divide and conquer took 1.7 s where Eigen's QR iteration took 7.6 s,
// and OpenBLAS's product 0.45 s against 2.3 s.
//
// Each call runs on one thread: OpenBLAS (its OpenMP build, the one scripts/install.sh sets up)
// splits a call over the calling thread's OpenMP threads, and the eigendecomposition's
// reductions round differently with their count. One thread keeps every figure independent of
// --threads.
#include <Eigen/Dense>
#include <optional>

namespace eitbench::detail {

// a b.
Eigen::MatrixXd product(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

// a's eigenvalues, ascending, and orthonormal eigenvectors as columns, each column's sign
// chosen so that its largest entry is positive (Eigen and LAPACK then agree up to rounding).
// `a` must be symmetric; its lower triangle is read.
struct SymmetricEigen {
  Eigen::VectorXd values;
  Eigen::MatrixXd vectors;
};
SymmetricEigen symmetric_eigen(Eigen::MatrixXd a);

// The lower triangle of shift I + a a^T (a symmetric rank-k update: half a product's work); the
// strict upper triangle is zero. symmetric_eigen and cholesky_solve read the lower triangle only.
Eigen::MatrixXd lower_gram(const Eigen::MatrixXd& a, double shift = 0);

// s^-1 b for a symmetric positive definite s, by its Cholesky factor; only s's lower triangle is
// read. Empty where s is not positive definite to working precision (or not finite).
std::optional<Eigen::VectorXd> cholesky_solve(Eigen::MatrixXd s, const Eigen::VectorXd& b);
// The same for every column of b at once (one factorisation).
std::optional<Eigen::MatrixXd> cholesky_solve_columns(Eigen::MatrixXd s, Eigen::MatrixXd b);

}  // namespace eitbench::detail
