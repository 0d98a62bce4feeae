#include "eitbench/solvers/total_variation.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include <tbb/parallel_invoke.h>

#include "eitbench/jacobian/error.h"
#include "eitbench/solvers/tikhonov.h"
#include "operator_norm.h"

namespace eitbench {

struct TotalVariation::Impl {
  std::vector<int> right, down;  // in-disk neighbour of each unknown, or -1
  // A A^T = U diag(g) U^T, kept on the directions with g > 0. B = U^T A (single precision) gives
  // the data term's proximal step. Only B^T is stored: B w as B^T's transpose times w takes the
  // dot-product form, 1.3x faster here than a column-major B.
  Eigen::VectorXd g;
  Eigen::MatrixXf Bt, At;
  // Element neighbours: K (edges x n) = edge differences of P x, weights w_e, and ||K||^2.
  Eigen::SparseMatrix<double, Eigen::RowMajor> K;
  Eigen::SparseMatrix<double, Eigen::RowMajor> Kt;
  Eigen::VectorXd weight;
  double norm2 = 8.0;
  std::unique_ptr<Tikhonov> start;
};

namespace {

// Chambolle-Pock for min_x ||A x - y||^2 / s + alpha sum_p |grad x|_p, over-relaxed (rho = 1.8,
// Condat's form: primal step, dual step on 2 x~ - x, then both moved rho of the way). The dual
// variable z lives on the pixel gradients (projected onto |z_p| <= alpha); the primal step is the
// exact proximal map of the data term, (I + c A^T A)^-1 w = w - c B^T diag(1 / (1 + c g)) B w
// with B = U^T A, evaluated in single precision (the products with B are most of the cost).
Eigen::VectorXd chambolle_pock(const TotalVariation::Impl& im, const Eigen::VectorXd& y,
                               Eigen::VectorXd x, double alpha, double tolerance,
                               int max_iterations, TotalVariation::Report* report) {
  const Eigen::Index n = x.size();
  const double s = std::max(y.squaredNorm(), 1e-300);
  // tau sigma ||grad||^2 < 1 (||grad||^2 <= 8), with tau / sigma = 3 / alpha: the primal solution
  // is ~1 (label scale), the dual ~alpha. The factor 3 was measured on the EIDORS two-disc case and
  // 60 quick-set frames: 0.1 -> 1,388 iterations (misses CC 0.949), 1 -> 934, 3 -> 705, 10 -> 524,
  // 30 -> stalls (no convergence in 20,000); 3 keeps a wide margin from the stall.
  const double ratio = 3.0 / std::max(alpha, 1e-12);
  const double tau = std::sqrt(0.99 * ratio / im.norm2),
               sigma = std::sqrt(0.99 / (ratio * im.norm2)), rho = 1.8;
  const double c = 2 * tau / s;
  const Eigen::VectorXf shrink = (c * (1.0 + c * im.g.array()).inverse()).cast<float>().matrix();
  const Eigen::VectorXd cAty = c * (im.At * y.cast<float>()).cast<double>();
  const Eigen::Index duals = im.K.rows() > 0 ? im.K.rows() : n;
  Eigen::VectorXd zx = Eigen::VectorXd::Zero(duals), zy = Eigen::VectorXd::Zero(duals), v(n), xt(n),
                  bar(n);
  const Eigen::Index half = n / 2;
  Eigen::VectorXf w1(shrink.size()), w2(shrink.size()), u(n);
  int it = 0;
  bool converged = false;
  while (it < max_iterations) {
    ++it;
    v = x;  // v = x - tau grad^T z + c A^T y
    if (im.K.rows() > 0) {
      v -= tau * (im.Kt * zx);
    } else {
      for (Eigen::Index p = 0; p < n; ++p) {
        if (im.right[p] >= 0) v[im.right[p]] -= tau * zx[p], v[p] += tau * zx[p];
        if (im.down[p] >= 0) v[im.down[p]] -= tau * zy[p], v[p] += tau * zy[p];
      }
    }
    v += cAty;
    const Eigen::VectorXf vf = v.cast<float>();
    // The two products with B are 2/3 of an iteration: each is split in two halves over pixels
    // that run as two tasks. The halves are summed in a fixed order, so the result does not depend
    // on the thread count.
    tbb::parallel_invoke(
        [&] { w1.noalias() = im.Bt.topRows(half).transpose() * vf.head(half); },
        [&] { w2.noalias() = im.Bt.bottomRows(n - half).transpose() * vf.tail(n - half); });
    w1 = shrink.cwiseProduct(w1 + w2);
    tbb::parallel_invoke([&] { u.head(half).noalias() = im.Bt.topRows(half) * w1; },
                         [&] { u.tail(n - half).noalias() = im.Bt.bottomRows(n - half) * w1; });
    xt = v - u.cast<double>();
    double change = 0, size = 0;
    if (im.K.rows() > 0) {  // element edges: anisotropic, |z_e| <= alpha w_e
      bar = 2 * xt - x;
      const Eigen::VectorXd kz = zx + sigma * (im.K * bar);
      for (Eigen::Index e = 0; e < kz.size(); ++e) {
        const double bound = alpha * im.weight[e];
        zx[e] += rho * (std::clamp(kz[e], -bound, bound) - zx[e]);
      }
    } else {
      bar = 2 * xt - x;
      for (Eigen::Index p = 0; p < n; ++p) {  // dual step on 2 x~ - x, projected; then relax both
        const double bx = bar[p];
        const double dx = im.right[p] >= 0 ? bar[im.right[p]] - bx : 0.0;
        const double dy = im.down[p] >= 0 ? bar[im.down[p]] - bx : 0.0;
        double a = zx[p] + sigma * dx, b = zy[p] + sigma * dy;
        const double norm = std::sqrt(a * a + b * b);
        if (norm > alpha) a *= alpha / norm, b *= alpha / norm;
        zx[p] += rho * (a - zx[p]), zy[p] += rho * (b - zy[p]);
      }
    }
    for (Eigen::Index p = 0; p < n; ++p) {
      const double step = rho * (xt[p] - x[p]);
      x[p] += step;
      change += step * step, size += x[p] * x[p];
    }
    if (change <= tolerance * tolerance * std::max(size, 1e-300)) {
      converged = true;
      break;
    }
  }
  if (report) report->iterations = it, report->converged = converged;
  return x;
}

}  // namespace

void TotalVariationOptions::validate() const {
  auto fail = [](const char* field, const std::string& why) {
    throw InputError("TotalVariationOptions", field, why);
  };
  if (!(alpha > 0) || !std::isfinite(alpha))
    fail("alpha", "the TV weight must be positive and finite");
  if (!(tolerance > 0) || !std::isfinite(tolerance))
    fail("tolerance", "must be positive and finite");
  if (max_iterations < 1) fail("max_iterations", "must be at least 1");
}

TotalVariation::TotalVariation(std::shared_ptr<const LinearProblem> shared,
                               const TotalVariationOptions& options)
    : impl_(std::make_unique<Impl>()),
      problem_(require_problem(std::move(shared), "TotalVariation")),
      options_(options),
      alpha_(options.alpha) {
  options.validate();
  const LinearProblem& problem = *problem_;
  const int n = problem.image_size;
  std::vector<int> column(static_cast<std::size_t>(n) * n, -1);
  for (std::size_t j = 0; j < problem.pixels.size(); ++j)
    column[problem.pixels[j]] = static_cast<int>(j);
  for (int pixel : problem.pixels) {
    const int i = pixel / n, k = pixel % n;
    impl_->right.push_back(k + 1 < n ? column[pixel + 1] : -1);
    impl_->down.push_back(i + 1 < n ? column[pixel + n] : -1);
  }
  if (options.neighbours == Neighbours::elements) {
    const Mesh& mesh = problem.model->mesh();
    const double h = 2.0 * problem.radius / problem.image_size;
    std::map<std::pair<int, int>, int> first;
    std::vector<Eigen::Triplet<double>> entries;
    std::vector<double> weights;
    for (int t = 0; t < mesh.num_triangles(); ++t)
      for (int k = 0; k < 3; ++k) {
        const int a = mesh.triangles(t, k), b = mesh.triangles(t, (k + 1) % 3);
        const auto [it, fresh] = first.emplace(std::make_pair(std::min(a, b), std::max(a, b)), t);
        if (fresh) continue;
        const int e = static_cast<int>(weights.size());
        entries.insert(entries.end(), {{e, t, 1.0}, {e, it->second, -1.0}});
        weights.push_back((mesh.nodes.row(a) - mesh.nodes.row(b)).norm() / h);
      }
    Eigen::SparseMatrix<double, Eigen::RowMajor> D(static_cast<Eigen::Index>(weights.size()),
                                                   mesh.num_triangles());
    D.setFromTriplets(entries.begin(), entries.end());
    impl_->K = D * problem.pixel_to_element;
    impl_->Kt = impl_->K.transpose();
    impl_->weight = Eigen::Map<const Eigen::VectorXd>(weights.data(),
                                                      static_cast<Eigen::Index>(weights.size()));
    impl_->norm2 = detail::squared_operator_norm(impl_->K);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(problem.A * problem.A.transpose());
  // Eigenvalues ascend: the rank largest are the last columns.
  const Eigen::Index rank =
      (eig.eigenvalues().array() > 1e-10 * eig.eigenvalues().maxCoeff()).count();
  impl_->g = eig.eigenvalues().tail(rank);
  impl_->Bt = (problem.A.transpose() * eig.eigenvectors().rightCols(rank)).cast<float>();
  impl_->At = problem.A.transpose().cast<float>();
  TikhonovOptions start;  // the starting point: NOSER, regularised near its usual optimum
  start.prior = Prior::noser;
  start.choice = Choice::gcv;  // placeholder choice; lambda is set just below
  impl_->start = std::make_unique<Tikhonov>(problem_, start);
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
  problem_->check_frame_size(frame.size());
  const Eigen::VectorXd start = problem_->from_image(impl_->start->reconstruct(frame));
  return problem_->to_image(chambolle_pock(*impl_, frame, start, alpha_, options_.tolerance,
                                           options_.max_iterations, report));
}

Eigen::VectorXd TotalVariation::reconstruct(const Eigen::VectorXd& frame) const {
  return solve(frame, nullptr);
}

void TotalVariation::fit(const SampleMatrix& frames, const SampleMatrix& labels,
                         const ScoreFn& score) {
  if (!options_.choose_by_validation) return;
  // A TV solve costs a tenth of a second: sweep on at most 20 frames.
  const double best = best_by_score(
      {1e-6, 3e-6, 1e-5, 3e-5, 1e-4, 3e-4, 1e-3}, [&](double a) { alpha_ = a; }, frames, labels,
      score, 20);
  set_alpha(best, "validation");
}

}  // namespace eitbench
