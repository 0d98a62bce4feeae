// The Tikhonov family's, TV's, GREIT's and Gauss-Newton's dense linear algebra
// (eitbench/solvers/dense_lapack.h): LAPACK's eigendecomposition against Eigen's and against its
// own definition, the rank update and the Cholesky solve against their definitions, and the same
// bits whatever the calling thread's OpenMP thread count.
#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "eitbench/solvers/dense_lapack.h"

namespace eitbench {
namespace {

Eigen::MatrixXd random_matrix(int rows, int cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index k = 0; k < m.size(); ++k) m.data()[k] = normal(rng);
  return m;
}

// G = A A^T of a tall A: positive semi-definite, with a null space, as the Tikhonov family's G.
Eigen::MatrixXd gram(int n, int rank, unsigned seed) {
  const Eigen::MatrixXd a = random_matrix(n, rank, seed);
  return a * a.transpose();
}

TEST(DenseLapack, TheProductIsEigensProduct) {
  const Eigen::MatrixXd a = random_matrix(70, 40, 1), b = random_matrix(40, 90, 2);
  const Eigen::MatrixXd c = detail::product(a, b);
  EXPECT_LE((c - a * b).norm(), 1e-13 * (a * b).norm());
  EXPECT_EQ(detail::product(Eigen::MatrixXd(3, 0), Eigen::MatrixXd(0, 4)),
            Eigen::MatrixXd::Zero(3, 4));
  EXPECT_THROW(detail::product(a, a), std::invalid_argument);
}

// Eigenpairs by definition (G V = V diag(w), V orthonormal, w ascending), and Eigen's solver's
// eigenvalues and sign-fixed eigenvectors, where an eigenvalue is apart from its neighbours.
TEST(DenseLapack, TheEigendecompositionIsGsAndEigensUpToRounding) {
  const int n = 300;
  const Eigen::MatrixXd G = gram(n, 200, 3);
  const detail::SymmetricEigen e = detail::symmetric_eigen(G);
  ASSERT_EQ(e.values.size(), n);
  for (int k = 1; k < n; ++k) EXPECT_LE(e.values[k - 1], e.values[k]);
  EXPECT_LE((G * e.vectors - e.vectors * e.values.asDiagonal()).norm(), 1e-12 * G.norm());
  EXPECT_LE((e.vectors.transpose() * e.vectors - Eigen::MatrixXd::Identity(n, n)).norm(), 1e-12);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(G);
  EXPECT_LE((e.values - eigen.eigenvalues()).cwiseAbs().maxCoeff(), 1e-11 * e.values.maxCoeff());
  int compared = 0;
  for (int k = n - 150; k < n - 1; ++k) {  // the range's eigenvalues, each apart from the next
    if (e.values[k + 1] - e.values[k] < 1e-3 * e.values[n - 1]) continue;
    Eigen::VectorXd v = eigen.eigenvectors().col(k);
    Eigen::Index at = 0;
    v.cwiseAbs().maxCoeff(&at);
    if (v[at] < 0) v = -v;
    EXPECT_LE((e.vectors.col(k) - v).norm(), 1e-8) << k;
    EXPECT_GT(e.vectors.col(k).maxCoeff(), -e.vectors.col(k).minCoeff()) << k;
    ++compared;
  }
  EXPECT_GT(compared, 50);
}

// shift I + a a^T in the lower triangle, nothing above it.
TEST(DenseLapack, TheLowerGramIsTheShiftedProductsLowerTriangle) {
  const Eigen::MatrixXd a = random_matrix(80, 50, 6);
  const Eigen::MatrixXd expected = 2.5 * Eigen::MatrixXd::Identity(80, 80) + a * a.transpose();
  const Eigen::MatrixXd c = detail::lower_gram(a, 2.5);
  ASSERT_EQ(c.rows(), 80);
  ASSERT_EQ(c.cols(), 80);
  const Eigen::MatrixXd lower = expected.triangularView<Eigen::Lower>();
  EXPECT_LE((c - lower).norm(), 1e-13 * expected.norm());
  EXPECT_TRUE(c.triangularView<Eigen::StrictlyUpper>().toDenseMatrix().isZero(0));
  EXPECT_EQ(detail::lower_gram(Eigen::MatrixXd(3, 0), 1), Eigen::MatrixXd::Identity(3, 3));
}

// s x = b to rounding from s's lower triangle alone (the upper one is garbage here); nothing for
// an indefinite or non-finite s.
TEST(DenseLapack, TheCholeskySolveSolvesAndRefusesWhatIsNotPositiveDefinite) {
  const int n = 120;
  Eigen::MatrixXd s = detail::lower_gram(random_matrix(n, 60, 7), 1);
  const Eigen::MatrixXd full = s.selfadjointView<Eigen::Lower>();
  s.triangularView<Eigen::StrictlyUpper>().setConstant(1e3);
  const Eigen::VectorXd b = random_matrix(n, 1, 8);
  const auto x = detail::cholesky_solve(s, b);
  ASSERT_TRUE(x.has_value());
  EXPECT_LE((full * *x - b).norm(), 1e-12 * b.norm());
  Eigen::MatrixXd indefinite = s;
  indefinite(n / 2, n / 2) = -1e4;
  EXPECT_FALSE(detail::cholesky_solve(indefinite, b).has_value());
  Eigen::MatrixXd not_finite = s;
  not_finite(n - 1, 3) = std::nan("");
  EXPECT_FALSE(detail::cholesky_solve(not_finite, b).has_value());
  EXPECT_THROW(detail::cholesky_solve(s, Eigen::VectorXd::Ones(n - 1)), std::invalid_argument);
  // Many right-hand sides, one factorisation (GREIT's): each column solved, the same refusals.
  const Eigen::MatrixXd B = random_matrix(n, 5, 9);
  const auto X = detail::cholesky_solve_columns(s, B);
  ASSERT_TRUE(X.has_value());
  ASSERT_EQ(X->cols(), 5);
  for (int k = 0; k < 5; ++k)
    EXPECT_LE((full * X->col(k) - B.col(k)).norm(), 1e-12 * B.col(k).norm()) << k;
  EXPECT_FALSE(detail::cholesky_solve_columns(indefinite, B).has_value());
  EXPECT_FALSE(detail::cholesky_solve_columns(not_finite, B).has_value());
  EXPECT_THROW(detail::cholesky_solve_columns(s, B.topRows(n - 1)), std::invalid_argument);
}

// OpenBLAS would split the calls over the calling thread's OpenMP threads, and the
// eigendecomposition's rounding then depends on their count: the calls keep to one.
TEST(DenseLapack, TheCallingThreadsOpenMpThreadsChangeNoBit) {
  const Eigen::MatrixXd G = gram(600, 500, 4), b = random_matrix(600, 300, 5);
  const int before = omp_get_max_threads();
  omp_set_num_threads(1);
  const detail::SymmetricEigen one = detail::symmetric_eigen(G);
  const Eigen::MatrixXd one_product = detail::product(G, b);
  const Eigen::MatrixXd one_gram = detail::lower_gram(b, 1);
  const auto one_solve = detail::cholesky_solve(one_gram, b.col(0));
  const auto one_columns = detail::cholesky_solve_columns(one_gram, b);
  omp_set_num_threads(4);
  const detail::SymmetricEigen four = detail::symmetric_eigen(G);
  const Eigen::MatrixXd four_product = detail::product(G, b);
  const Eigen::MatrixXd four_gram = detail::lower_gram(b, 1);
  const auto four_solve = detail::cholesky_solve(four_gram, b.col(0));
  const auto four_columns = detail::cholesky_solve_columns(four_gram, b);
  EXPECT_EQ(omp_get_max_threads(), 4);  // the caller's setting is given back
  omp_set_num_threads(before);
  EXPECT_TRUE(one.values == four.values);
  EXPECT_TRUE(one.vectors == four.vectors);
  EXPECT_TRUE(one_product == four_product);
  EXPECT_TRUE(one_gram == four_gram);
  ASSERT_TRUE(one_solve && four_solve);
  EXPECT_TRUE(*one_solve == *four_solve);
  ASSERT_TRUE(one_columns && four_columns);
  EXPECT_TRUE(*one_columns == *four_columns);
}

}  // namespace
}  // namespace eitbench
