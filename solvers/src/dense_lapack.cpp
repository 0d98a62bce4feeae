#include "eitbench/solvers/dense_lapack.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#ifdef EITBENCH_WITH_LAPACK
#include <omp.h>

#include <cstddef>

// Fortran's calling convention: every argument by pointer, then each character argument's length.
extern "C" {
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
            const double* alpha, const double* a, const int* lda, const double* b, const int* ldb,
            const double* beta, double* c, const int* ldc, std::size_t transa_length,
            std::size_t transb_length);
void dsyevd_(const char* jobz, const char* uplo, const int* n, double* a, const int* lda, double* w,
             double* work, const int* lwork, int* iwork, const int* liwork, int* info,
             std::size_t jobz_length, std::size_t uplo_length);
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* beta, double* c, const int* ldc,
            std::size_t uplo_length, std::size_t trans_length);
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info,
             std::size_t uplo_length);
void dpotrs_(const char* uplo, const int* n, const int* nrhs, const double* a, const int* lda,
             double* b, const int* ldb, int* info, std::size_t uplo_length);
}
#endif

namespace eitbench::detail {
namespace {

#ifdef EITBENCH_WITH_LAPACK
// OpenBLAS's OpenMP build runs a call on omp_get_max_threads() threads of the calling thread; one,
// for the scope of this object (the setting is the calling thread's own).
class OneBlasThread {
 public:
  OneBlasThread() : before_(omp_get_max_threads()) { omp_set_num_threads(1); }
  ~OneBlasThread() { omp_set_num_threads(before_); }
  OneBlasThread(const OneBlasThread&) = delete;
  OneBlasThread& operator=(const OneBlasThread&) = delete;

 private:
  int before_;
};

int fortran_size(Eigen::Index n) {
  if (n > std::numeric_limits<int>::max())
    throw std::length_error("dense_lapack: a dimension of " + std::to_string(n) +
                            " passes LAPACK's 32-bit indices");
  return static_cast<int>(n);
}
#endif

// The sign convention of symmetric_eigen: each column's entry of largest magnitude positive.
void orient_columns(Eigen::MatrixXd& vectors) {
  for (Eigen::Index j = 0; j < vectors.cols(); ++j) {
    Eigen::Index at = 0;
    vectors.col(j).cwiseAbs().maxCoeff(&at);
    if (vectors(at, j) < 0) vectors.col(j) *= -1;
  }
}

}  // namespace

Eigen::MatrixXd product(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.cols() != b.rows()) throw std::invalid_argument("product: inner dimensions differ");
#ifdef EITBENCH_WITH_LAPACK
  Eigen::MatrixXd c(a.rows(), b.cols());
  if (c.size() == 0) return c;
  if (a.cols() == 0) return Eigen::MatrixXd::Zero(a.rows(), b.cols());
  const int m = fortran_size(a.rows()), n = fortran_size(b.cols()), k = fortran_size(a.cols());
  const double one = 1, zero = 0;
  const OneBlasThread one_thread;
  dgemm_("N", "N", &m, &n, &k, &one, a.data(), &m, b.data(), &k, &zero, c.data(), &m, 1, 1);
  return c;
#else
  return a * b;
#endif
}

SymmetricEigen symmetric_eigen(Eigen::MatrixXd a) {
  if (a.rows() != a.cols())
    throw std::invalid_argument("symmetric_eigen: the matrix is not square");
  SymmetricEigen e;
#ifdef EITBENCH_WITH_LAPACK
  const int n = fortran_size(a.rows());
  e.values.resize(n);
  if (n > 0) {
    int lwork = -1, liwork = -1, info = 0, iwork_size = 0;
    double work_size = 0;
    const OneBlasThread one_thread;
    dsyevd_("V", "L", &n, a.data(), &n, e.values.data(), &work_size, &lwork, &iwork_size, &liwork,
            &info, 1, 1);  // the workspace's size
    lwork = static_cast<int>(work_size), liwork = iwork_size;
    std::vector<double> work(static_cast<std::size_t>(lwork));
    std::vector<int> iwork(static_cast<std::size_t>(liwork));
    dsyevd_("V", "L", &n, a.data(), &n, e.values.data(), work.data(), &lwork, iwork.data(), &liwork,
            &info, 1, 1);
    if (info != 0)
      throw std::runtime_error("symmetric_eigen: LAPACK's dsyevd failed (info " +
                               std::to_string(info) + ")");
  }
  e.vectors = std::move(a);
#else
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(a);
  if (solver.info() != Eigen::Success)
    throw std::runtime_error("symmetric_eigen: the eigensolver did not converge");
  e.values = solver.eigenvalues();
  e.vectors = solver.eigenvectors();
#endif
  orient_columns(e.vectors);
  return e;
}

Eigen::MatrixXd lower_gram(const Eigen::MatrixXd& a, double shift) {
  Eigen::MatrixXd c = shift * Eigen::MatrixXd::Identity(a.rows(), a.rows());
#ifdef EITBENCH_WITH_LAPACK
  if (c.size() == 0 || a.cols() == 0) return c;
  const int n = fortran_size(a.rows()), k = fortran_size(a.cols());
  const double one = 1;
  const OneBlasThread one_thread;
  dsyrk_("L", "N", &n, &k, &one, a.data(), &n, &one, c.data(), &n, 1, 1);
#else
  c.selfadjointView<Eigen::Lower>().rankUpdate(a);
#endif
  return c;
}

std::optional<Eigen::MatrixXd> cholesky_solve_columns(Eigen::MatrixXd s, Eigen::MatrixXd b) {
  if (s.rows() != s.cols() || s.rows() != b.rows())
    throw std::invalid_argument("cholesky_solve: the sizes do not match");
  if (!b.allFinite()) return {};
  for (Eigen::Index j = 0; j < s.cols(); ++j)
    if (!s.col(j).tail(s.rows() - j).allFinite()) return {};
#ifdef EITBENCH_WITH_LAPACK
  if (b.size() == 0) return b;
  const int n = fortran_size(s.rows()), nrhs = fortran_size(b.cols());
  int info = 0;
  const OneBlasThread one_thread;
  dpotrf_("L", &n, s.data(), &n, &info, 1);
  if (info != 0) return {};
  dpotrs_("L", &n, &nrhs, s.data(), &n, b.data(), &n, &info, 1);
  return b;
#else
  const Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> llt(s);
  if (llt.info() != Eigen::Success) return {};
  return llt.solve(b).eval();
#endif
}

std::optional<Eigen::VectorXd> cholesky_solve(Eigen::MatrixXd s, const Eigen::VectorXd& b) {
  std::optional<Eigen::MatrixXd> x = cholesky_solve_columns(std::move(s), Eigen::MatrixXd(b));
  if (!x) return {};
  return Eigen::VectorXd(x->col(0));
}

}  // namespace eitbench::detail
