#include "eitbench/solvers/tikhonov.h"

#include <Eigen/SparseCholesky>
#include <cmath>
#include <stdexcept>

#include "eitbench/jacobian/error.h"
#include "eitbench/solvers/dense_lapack.h"
#include "neighbour_graphs.h"

namespace eitbench {
namespace {

// n m^2 floating-point operations: below this the reconstruction matrix is formed for each lambda
// (set_lambda), above it the factors are applied to each frame (factored_ in the header).
constexpr double kFormLimit = 2e9;

// The 4-neighbour graph Laplacian of the in-disk pixels.
Eigen::SparseMatrix<double> pixel_laplacian(const LinearProblem& p) {
  const int n = p.grid.size();
  const std::vector<int> column = detail::unknown_of_pixel(p.pixels, n * n);
  std::vector<Eigen::Triplet<double>> entries;
  for (std::size_t j = 0; j < p.pixels.size(); ++j) {
    const int i = p.pixels[j] / n, k = p.pixels[j] % n;
    int degree = 0;
    for (const auto& [di, dk] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
      const int a = i + di, b = k + dk;
      if (a < 0 || a >= n || b < 0 || b >= n || column[a * n + b] < 0) continue;
      entries.emplace_back(static_cast<int>(j), column[a * n + b], -1.0);
      ++degree;
    }
    entries.emplace_back(static_cast<int>(j), static_cast<int>(j), degree);
  }
  Eigen::SparseMatrix<double> L(static_cast<Eigen::Index>(p.pixels.size()),
                                static_cast<Eigen::Index>(p.pixels.size()));
  L.setFromTriplets(entries.begin(), entries.end());
  return L;
}

// The edge-neighbour graph Laplacian of the mesh's triangles, applied to the elements' values P x.
Eigen::SparseMatrix<double> element_laplacian(const LinearProblem& p) {
  const Mesh& mesh = p.model->mesh();
  std::vector<Eigen::Triplet<double>> entries;
  for (const detail::InteriorEdge& e : detail::interior_edges(mesh)) {
    const int u = e.first, t = e.second;
    entries.insert(entries.end(), {{u, u, 1.0}, {t, t, 1.0}, {u, t, -1.0}, {t, u, -1.0}});
  }
  Eigen::SparseMatrix<double> L(mesh.num_triangles(), mesh.num_triangles());
  L.setFromTriplets(entries.begin(), entries.end());
  return L * Eigen::SparseMatrix<double>(p.element_from_pixels);
}

// The smooth prior's covariance times A^T: Gamma_ij = exp(-d_ij^2 / (2 b^2)) over the in-disk
// pixels' centres, b such that Gamma is 1 % at `length`. P is the covariance itself, so no
// inverse is formed: B = Gamma A^T directly.
Eigen::MatrixXd smooth_covariance_times(const LinearProblem& p, double length,
                                        const Eigen::MatrixXd& At) {
  const Eigen::Index n = p.unknowns();
  Eigen::MatrixXd centres(2, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    // Element by element: GCC 12 takes a Vector2d stored into a column block for a 16-byte read
    // of an 8-byte object (-Wstringop-overread), a false alarm.
    const Eigen::Vector2d c = p.pixel_centre(j);
    centres(0, j) = c.x(), centres(1, j) = c.y();
  }
  const double b2 = length * length / (2.0 * std::log(100.0));
  Eigen::MatrixXd gamma(n, n);
  for (Eigen::Index j = 0; j < n; ++j)
    gamma.col(j) =
        (-(centres.colwise() - centres.col(j)).colwise().squaredNorm().array() / (2.0 * b2))
            .exp()
            .transpose();
  return detail::product(gamma, At);
}

}  // namespace

Prior parse_prior(const std::string& method) {
  if (method == "tikhonov" || method == "identity") return Prior::identity;
  if (method == "noser") return Prior::noser;
  if (method == "laplace") return Prior::laplace;
  if (method == "smooth") return Prior::smooth;
  throw InputError("Prior", "name",
                   "unknown prior '" + method + "' (tikhonov, identity, noser, laplace or smooth)");
}

void TikhonovOptions::validate() const {
  auto fail = [](const char* field, const std::string& why) {
    throw InputError("TikhonovOptions", field, why);
  };
  if (choice == Criterion::fixed && !lambda) fail("lambda", "choice fixed needs a lambda");
  if (lambda && choice != Criterion::fixed)
    fail("lambda", "is used only with choice fixed; another choice would ignore it");
  if (lambda && (!(*lambda > 0) || !std::isfinite(*lambda)))
    fail("lambda", "must be positive and finite");
  if (!(noser_exponent >= 0 && noser_exponent <= 1)) fail("noser_exponent", "must lie in [0, 1]");
  if (choice == Criterion::discrepancy && !noise)
    fail("noise", "choice discrepancy needs the frames' noise");
  if (noise && choice != Criterion::discrepancy)
    fail("noise", "is used only with choice discrepancy; another choice would ignore it");
  if (noise && (!(*noise > 0) || !std::isfinite(*noise)))
    fail("noise", "must be positive and finite");
  if (!(discrepancy_factor >= 1) || !std::isfinite(discrepancy_factor))
    fail("discrepancy_factor", "must be finite and at least 1");
  // GCV and the L-curve need a curve to minimise or to bend: at least three candidates.
  if (grid < 3) fail("grid", "needs at least 3 lambdas, got " + std::to_string(grid));
  // L^T L has the constants in its kernel: without epsilon R^T R is singular.
  if (!(laplace_epsilon > 0) || !std::isfinite(laplace_epsilon))
    fail("laplace_epsilon", "must be positive and finite");
  if (!(smooth_length > 0) || !std::isfinite(smooth_length))
    fail("smooth_length", "must be positive and finite");
}

Tikhonov::Tikhonov(std::shared_ptr<const LinearProblem> shared, const TikhonovOptions& options)
    : problem_(require_problem(std::move(shared), "Tikhonov")), options_(options) {
  options.validate();
  const LinearProblem& problem = *problem_;
  const Eigen::MatrixXd& A = problem.A;
  // B = P A^T with P = (R^T R)^-1.
  Eigen::MatrixXd B;
  switch (options.prior) {
    case Prior::identity:
      B = A.transpose();
      break;
    case Prior::noser: {
      const Eigen::VectorXd w =
          A.colwise().squaredNorm().transpose().array().pow(options.noser_exponent);
      const double floor = 1e-12 * w.maxCoeff();  // pixels the data do not see keep a finite weight
      B = (1.0 / w.array().max(floor)).matrix().asDiagonal() * A.transpose();
      break;
    }
    case Prior::laplace: {
      const Eigen::SparseMatrix<double> L = options.neighbours == Neighbours::pixels
                                                ? pixel_laplacian(problem)
                                                : element_laplacian(problem);
      Eigen::SparseMatrix<double> RtR = L.transpose() * L;
      const double eps = options.laplace_epsilon * RtR.diagonal().mean();
      for (Eigen::Index j = 0; j < RtR.rows(); ++j) RtR.coeffRef(j, j) += eps;
      Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(RtR);
      if (solver.info() != Eigen::Success)
        throw std::runtime_error("Tikhonov: the Laplace prior could not be factorised");
      B = solver.solve(Eigen::MatrixXd(A.transpose()));
      break;
    }
    case Prior::smooth:
      B = smooth_covariance_times(problem, options.smooth_length * problem.grid.radius(),
                                  A.transpose());
      break;
  }
  const Eigen::MatrixXd G = detail::product(A, B);
  detail::SymmetricEigen eig = detail::symmetric_eigen(0.5 * (G + G.transpose()));
  g_ = eig.values.cwiseMax(0.0);
  U_ = std::move(eig.vectors);
  C_ = detail::product(B, U_);
  factored_ = static_cast<double>(C_.rows()) * C_.cols() * C_.cols() > kFormLimit;
  const double scale = g_.sum() / static_cast<double>(g_.size());
  for (int k = 0; k < options.grid; ++k)
    grid_.push_back(scale * std::pow(10.0, -8.0 + 10.0 * k / std::max(1, options.grid - 1)));
  if (options.choice == Criterion::fixed) {
    set_lambda(options.relative ? *options.lambda * scale : *options.lambda, "fixed");
  } else {
    set_lambda(grid_[grid_.size() / 2], "default");  // until a choice is made
  }
}

std::string Tikhonov::name() const {
  switch (options_.prior) {
    case Prior::identity:
      return "tikhonov";
    case Prior::noser:
      return "noser";
    case Prior::laplace:
      return "laplace";
    case Prior::smooth:
      return "smooth";
  }
  return "?";
}

std::string Tikhonov::settings() const {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, "lambda=%.4g (%s)", lambda_, how_.c_str());
  return buffer;
}

void Tikhonov::set_lambda(double lambda, const std::string& how) {
  lambda_ = lambda;
  how_ = how;
  const Eigen::VectorXd f = (g_.array() + lambda).inverse();
  f_ = f;
  if (factored_) return;
  if (options_.single_precision)
    M_ = (C_ * f.asDiagonal() * U_.transpose()).cast<float>();
  else
    Md_ = C_ * f.asDiagonal() * U_.transpose();
}

void Tikhonov::fit(const SampleMatrix& frames, const SampleMatrix& labels, const ScoreFn& score) {
  switch (options_.choice) {
    case Criterion::fixed:
      return;
    case Criterion::gcv:
      choose_gcv(frames);
      return;
    case Criterion::lcurve:
      choose_lcurve(frames);
      return;
    case Criterion::discrepancy:
      choose_discrepancy(frames);
      return;
    case Criterion::validation:
      choose_validation(frames, labels, score);
      return;
  }
}

std::vector<double> Tikhonov::gcv_curve(const SampleMatrix& frames) const {
  const Eigen::ArrayXd z2 = eigen_power(frames);
  std::vector<double> out;
  for (double lambda : grid_) {
    const Eigen::ArrayXd keep = lambda / (g_.array() + lambda);  // the diagonal of I - H
    out.push_back((keep.square() * z2.array()).sum() / std::pow(keep.sum(), 2));
  }
  return out;
}

namespace {

// GCV and the L-curve measure how lambda trades residual for smoothness on the frames: with no
// frames, or only zero frames, every lambda scores alike and the choice would be arbitrary.
void check_frames_to_choose_on(const SampleMatrix& frames, const char* criterion) {
  if (frames.rows() == 0)
    throw InputError("frames", "", std::string(criterion) + " needs at least one frame");
  if (!(frames.squaredNorm() > 0) || !frames.allFinite())
    throw InputError("frames", "",
                     std::string(criterion) + " needs frames that are finite and not all zero");
}

}  // namespace

double Tikhonov::choose_gcv(const SampleMatrix& frames) {
  check_frames_to_choose_on(frames, "GCV");
  const std::vector<double> curve = gcv_curve(frames);
  const std::size_t best = std::min_element(curve.begin(), curve.end()) - curve.begin();
  set_lambda(grid_[best], "gcv");
  return lambda_;
}

double Tikhonov::choose_lcurve(const SampleMatrix& frames) {
  check_frames_to_choose_on(frames, "the L-curve");
  const Eigen::ArrayXd z2 = eigen_power(frames);
  const std::size_t n = grid_.size();
  std::vector<double> t(n), rho(n), eta(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double lambda = grid_[k];
    const Eigen::ArrayXd d = g_.array() + lambda;
    t[k] = std::log(lambda);
    rho[k] = 0.5 * std::log(((lambda / d).square() * z2).sum());             // log residual norm
    eta[k] = 0.5 * std::log((g_.array() / d.square() * z2).sum() + 1e-300);  // log seminorm ||R x||
  }
  // Maximum curvature of (rho, eta) along log lambda, by central differences.
  double best_kappa = -INFINITY;
  std::size_t best = n / 2;
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const double h = t[k + 1] - t[k];
    const double r1 = (rho[k + 1] - rho[k - 1]) / (2 * h), e1 = (eta[k + 1] - eta[k - 1]) / (2 * h);
    const double r2 = (rho[k + 1] - 2 * rho[k] + rho[k - 1]) / (h * h),
                 e2 = (eta[k + 1] - 2 * eta[k] + eta[k - 1]) / (h * h);
    const double kappa = (r1 * e2 - r2 * e1) / std::pow(r1 * r1 + e1 * e1, 1.5);
    if (kappa > best_kappa) best_kappa = kappa, best = k;
  }
  set_lambda(grid_[best], "lcurve");
  return lambda_;
}

double Tikhonov::noise_estimate(const SampleMatrix& frames) const {
  check_frames_to_choose_on(frames, "the noise estimate");
  const Eigen::ArrayXd keep = lambda_ / (g_.array() + lambda_);  // the diagonal of I - H
  const double residual2 = (keep.square() * eigen_power(frames)).sum();
  return std::sqrt(residual2 / (static_cast<double>(frames.rows()) * keep.sum()));
}

Eigen::ArrayXd Tikhonov::eigen_power(const SampleMatrix& frames) const {
  const Eigen::MatrixXd Z = frames * U_;  // frames in G's eigenbasis
  return Z.colwise().squaredNorm().transpose().array();
}

double Tikhonov::choose_discrepancy(const SampleMatrix& frames) {
  check_frames_to_choose_on(frames, "the discrepancy principle");
  if (!options_.noise)
    throw InputError("TikhonovOptions", "noise", "the discrepancy principle needs a noise level");
  // y - A x = lambda (G + lambda I)^-1 y: in G's eigenbasis each component shrinks by
  // lambda / (g + lambda). U is square (G is m x m), so nothing of y lies outside it.
  const Eigen::ArrayXd z2 = eigen_power(frames);
  const double values = static_cast<double>(frames.size());
  const auto residual = [&](double log_lambda) {  // the residual's RMS over the frames' values
    const double lambda = std::exp(log_lambda);
    return std::sqrt(((lambda / (g_.array() + lambda)).square() * z2).sum() / values);
  };
  const double target = options_.discrepancy_factor * *options_.noise;
  double lo = std::log(grid_.front()), hi = std::log(grid_.back());
  // At either end of the grid no lambda matches, and the settings say so rather than pass the
  // end off as a match: a model whose own error exceeds the noise misfits the frames by more at
  // every lambda (real frames, docs/real-presses.md); a noise above every residual asks for more
  // regularisation than the grid holds.
  if (residual(lo) >= target) {
    set_lambda(grid_.front(), "discrepancy: the residual exceeds the noise at every lambda");
    return lambda_;
  }
  if (residual(hi) <= target) {
    set_lambda(grid_.back(), "discrepancy: the noise exceeds the residual at every lambda");
    return lambda_;
  }
  // The residual grows with lambda: bisect log lambda.
  for (int k = 0; k < 60 && hi - lo > 1e-6; ++k) {
    const double mid = 0.5 * (lo + hi);
    (residual(mid) < target ? lo : hi) = mid;
  }
  set_lambda(std::exp(0.5 * (lo + hi)), "discrepancy");
  return lambda_;
}

double Tikhonov::choose_validation(const SampleMatrix& frames, const SampleMatrix& labels,
                                   const ScoreFn& score) {
  if (!score || labels.rows() != frames.rows() || frames.rows() == 0)
    throw InputError("validation frames", "",
                     "choosing by validation needs labelled frames and a score");
  // At most 500 frames, evenly spread: the sweep costs frames x grid matrix products. The same
  // sweep as best_by_score, on the eigenbasis, so that every lambda costs one small product.
  const std::vector<Eigen::Index> rows = spread_rows(frames.rows(), 500);
  Eigen::MatrixXd Z(static_cast<Eigen::Index>(rows.size()), frames.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) Z.row(k) = frames.row(rows[k]) * U_;
  double best_score = -INFINITY;
  double best = grid_.front();
  for (double lambda : grid_) {
    const Eigen::MatrixXd X =
        Z * (g_.array() + lambda).inverse().matrix().asDiagonal() * C_.transpose();
    double total = 0;
    for (std::size_t k = 0; k < rows.size(); ++k)
      total += score(problem_->to_image(X.row(k).transpose()), labels.row(rows[k]).transpose());
    if (total > best_score) best_score = total, best = lambda;
  }
  if (best_score == -INFINITY)
    throw InputError("validation frames", "", "no lambda could be scored (every score is NaN)");
  set_lambda(best, "validation");
  return lambda_;
}

Eigen::VectorXd Tikhonov::reconstruct(const Eigen::VectorXd& frame) const {
  problem_->check_frame_size(frame.size());
  if (factored_) return problem_->to_image(C_ * f_.cwiseProduct(U_.transpose() * frame));
  if (!options_.single_precision) return problem_->to_image(Md_ * frame);
  const Eigen::VectorXf x = M_ * frame.cast<float>();
  return problem_->to_image(x.cast<double>());
}

SampleMatrix Tikhonov::reconstruct_all(const SampleMatrix& frames) const {
  problem_->check_frame_size(frames.cols());
  if (factored_) return problem_->to_images(((frames * U_) * f_.asDiagonal()) * C_.transpose());
  if (!options_.single_precision) return problem_->to_images(frames * Md_.transpose());
  return problem_->to_images((frames.cast<float>() * M_.transpose()).cast<double>());
}

bool Tikhonov::set_regularisation(double relative, const std::string& how) {
  set_lambda(relative * scale(), how);
  return true;
}

}  // namespace eitbench
