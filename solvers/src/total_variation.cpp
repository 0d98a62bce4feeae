#include "eitbench/solvers/total_variation.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>

#include "eitbench/jacobian/error.h"
#include "eitbench/solvers/tikhonov.h"

namespace eitbench {

struct TotalVariation::Impl {
  std::vector<int> right, down;  // in-disk neighbour of each unknown, or -1
  Eigen::MatrixXd U;             // A A^T = U diag(g) U^T: the data term's proximal step
  Eigen::VectorXd g;
  std::unique_ptr<Tikhonov> start;
};

namespace {

// Chambolle-Pock for min_x ||A x - y||^2 / s + alpha sum_p |grad x|_p. The dual variable z lives
// on the pixel gradients (projected onto |z_p| <= alpha); the primal step is the exact proximal
// map of the data term: (I + c A^T A)^-1 w = w - c A^T U diag(1 / (1 + c g)) U^T A w.
Eigen::VectorXd chambolle_pock(const TotalVariation::Impl& im, const Eigen::MatrixXd& A,
                               const Eigen::VectorXd& y, Eigen::VectorXd x, double alpha,
                               double tolerance, int max_iterations,
                               TotalVariation::Report* report) {
  const Eigen::Index n = x.size();
  const double s = std::max(y.squaredNorm(), 1e-300);
  // tau sigma ||grad||^2 < 1 (||grad||^2 <= 8), with tau / sigma ~ |x| / |z| ~ 1 / alpha: steps
  // balanced to the scales of the primal (label scale, ~1) and the dual (~alpha) solutions.
  const double ratio = 1.0 / std::max(alpha, 1e-12);
  const double tau = std::sqrt(0.99 * ratio / 8), sigma = std::sqrt(0.99 / (ratio * 8));
  const double c = 2 * tau / s;
  const Eigen::VectorXd shrink = (1.0 + c * im.g.array()).inverse();
  const Eigen::VectorXd Aty = A.transpose() * y;
  Eigen::VectorXd zx = Eigen::VectorXd::Zero(n), zy = Eigen::VectorXd::Zero(n), bar = x, prev(n),
                  v(n);
  int it = 0;
  bool converged = false;
  while (it < max_iterations) {
    ++it;
    for (Eigen::Index p = 0; p < n; ++p) {  // dual ascent, projected
      const double dx = im.right[p] >= 0 ? bar[im.right[p]] - bar[p] : 0.0;
      const double dy = im.down[p] >= 0 ? bar[im.down[p]] - bar[p] : 0.0;
      double a = zx[p] + sigma * dx, b = zy[p] + sigma * dy;
      const double norm = std::sqrt(a * a + b * b);
      if (norm > alpha) a *= alpha / norm, b *= alpha / norm;
      zx[p] = a, zy[p] = b;
    }
    prev = x;
    v = x;
    for (Eigen::Index p = 0; p < n; ++p) {  // v = x - tau grad^T z
      if (im.right[p] >= 0) v[im.right[p]] -= tau * zx[p], v[p] += tau * zx[p];
      if (im.down[p] >= 0) v[im.down[p]] -= tau * zy[p], v[p] += tau * zy[p];
    }
    v += c * Aty;
    x = v - c * (A.transpose() * (im.U * (shrink.asDiagonal() * (im.U.transpose() * (A * v)))));
    bar = 2 * x - prev;
    if ((x - prev).norm() <= tolerance * std::max(x.norm(), 1e-300)) {
      converged = true;
      break;
    }
  }
  if (report) report->iterations = it, report->converged = converged;
  return x;
}

}  // namespace

TotalVariation::TotalVariation(const LinearProblem& problem, const TotalVariationOptions& options)
    : impl_(std::make_unique<Impl>()), problem_(problem), options_(options), alpha_(options.alpha) {
  if (!(options.alpha > 0) || !std::isfinite(options.alpha))
    throw InputError("--lambda", "", "the TV weight must be positive");
  if (!(options.tolerance > 0)) throw InputError("tolerance", "", "must be positive");
  const int n = problem.image_size;
  std::vector<int> column(static_cast<std::size_t>(n) * n, -1);
  for (std::size_t j = 0; j < problem.pixels.size(); ++j)
    column[problem.pixels[j]] = static_cast<int>(j);
  for (int pixel : problem.pixels) {
    const int i = pixel / n, k = pixel % n;
    impl_->right.push_back(k + 1 < n ? column[pixel + 1] : -1);
    impl_->down.push_back(i + 1 < n ? column[pixel + n] : -1);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(problem.A * problem.A.transpose());
  impl_->U = eig.eigenvectors();
  impl_->g = eig.eigenvalues().cwiseMax(0.0);
  TikhonovOptions start;  // the starting point: NOSER, regularised near its usual optimum
  start.prior = Prior::noser;
  start.choice = Choice::gcv;  // placeholder choice; lambda is set just below
  impl_->start = std::make_unique<Tikhonov>(problem, start);
  impl_->start->set_lambda(1e-3 * impl_->start->scale(), "start");
}

TotalVariation::~TotalVariation() = default;

std::string TotalVariation::settings() const {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, "alpha=%.4g (%s), tolerance=%.0e", alpha_, how_.c_str(),
                options_.tolerance);
  return buffer;
}

void TotalVariation::set_alpha(double alpha, const std::string& how) {
  alpha_ = alpha;
  how_ = how;
}

Eigen::VectorXd TotalVariation::solve(const Eigen::VectorXd& frame, Report* report) const {
  if (frame.size() != problem_.measurements())
    throw InputError("frame", "",
                     "has " + std::to_string(frame.size()) + " values, the model " +
                         std::to_string(problem_.measurements()));
  const Eigen::VectorXd start = problem_.from_image(impl_->start->reconstruct(frame));
  return problem_.to_image(chambolle_pock(*impl_, problem_.A, frame, start, alpha_,
                                          options_.tolerance, options_.max_iterations, report));
}

Eigen::VectorXd TotalVariation::reconstruct(const Eigen::VectorXd& frame) const {
  return solve(frame, nullptr);
}

void TotalVariation::fit(const SampleMatrix& frames, const SampleMatrix& labels,
                         const ScoreFn& score) {
  if (!options_.choose_by_validation) return;
  if (!score || labels.rows() != frames.rows() || frames.rows() == 0)
    throw InputError("--choose validation", "", "needs labelled validation frames");
  // A TV solve costs a fraction of a second: sweep on at most 20 frames, evenly spread.
  std::vector<Eigen::Index> rows;
  const Eigen::Index step = std::max<Eigen::Index>(1, frames.rows() / 20);
  for (Eigen::Index i = 0; i < frames.rows(); i += step) rows.push_back(i);
  double best_score = -INFINITY, best = alpha_;
  for (double alpha : {1e-6, 3e-6, 1e-5, 3e-5, 1e-4, 3e-4, 1e-3}) {
    alpha_ = alpha;
    double total = 0;
    for (Eigen::Index i : rows)
      total += score(reconstruct(frames.row(i).transpose()), labels.row(i).transpose());
    if (total > best_score) best_score = total, best = alpha;
  }
  set_alpha(best, "validation");
}

}  // namespace eitbench
