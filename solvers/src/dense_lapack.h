#pragma once
// The dense products and symmetric eigendecompositions that build the Tikhonov family and TV,
// through the system's BLAS and LAPACK where the build found them (EITBENCH_WITH_LAPACK), else
// through Eigen. On KTC's 2,356-value frame (2-core Intel Xeon) LAPACK's divide and conquer
// took 1.7 s where Eigen's QR iteration took 7.6 s, and OpenBLAS's product 0.45 s against 2.3 s.
//
// Each call runs on one thread: OpenBLAS (its OpenMP build, the one scripts/install.sh sets up)
// splits a call over the calling thread's OpenMP threads, and the eigendecomposition's
// reductions round differently with their count. One thread keeps every figure independent of
// --threads.
#include <Eigen/Dense>

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

}  // namespace eitbench::detail
