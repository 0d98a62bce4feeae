#include "eitbench/solvers/greit.h"

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/random.h"
#include "eitbench/solvers/dense_lapack.h"

namespace eitbench {

void GreitOptions::validate() const {
  auto fail = [](const char* field, const std::string& why) {
    throw InputError("GreitOptions", field, why);
  };
  if (targets < 10) fail("targets", "GREIT needs at least 10 training targets");
  // A target must fit inside the disk; a desired disc of radius 0 would make D, and R, zero.
  if (!(target_radius > 0 && target_radius < 1)) fail("target_radius", "must lie in (0, 1)");
  if (!(desired_radius > 0 && desired_radius <= 1)) fail("desired_radius", "must lie in (0, 1]");
  if (!(lambda > 0) || !std::isfinite(lambda)) fail("lambda", "must be positive and finite");
  check_fixed_or_validation("GreitOptions", choice, candidates);
}

namespace {

// Uniform over the disk of radius R - r about the origin; on a sensor of another shape, by
// rejection over the grid's box: inside the mesh and at least r from its boundary.
Eigen::Vector2d target_centre(const LinearProblem& problem, const MeshDomain& domain, double r,
                              RandomStream& rng) {
  const PixelGrid& grid = problem.grid;
  const double R = grid.radius();
  if (grid.is_disk()) {
    const double rho = (R - r) * std::sqrt(rng.uniform()), phi = 2 * M_PI * rng.uniform();
    return {rho * std::cos(phi), rho * std::sin(phi)};
  }
  for (int attempt = 0; attempt < 100000; ++attempt) {
    const double u = rng.uniform(-R, R), v = rng.uniform(-R, R);  // in this order, always
    const Eigen::Vector2d x = grid.box_centre() + Eigen::Vector2d(u, v);
    if (domain.contains(x) && domain.boundary_distance(x) >= r) return x;
  }
  throw InputError("GreitOptions", "target_radius",
                   "no target of this radius fits inside the sensor");
}

}  // namespace

Greit::Greit(std::shared_ptr<const LinearProblem> shared, const GreitOptions& options)
    : problem_(require_problem(std::move(shared), "Greit")),
      options_(options),
      lambda_(options.lambda) {
  options.validate();
  const LinearProblem& problem = *problem_;
  const PixelGrid& grid = problem.grid;
  const double R = grid.radius();
  const int m = problem.measurements(), n = problem.unknowns();
  // Each target and desired image covers a few dozen pixels of thousands: Y = A X and D Y^T are
  // formed from their non-zeros only (X and D sparse).
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(m, options.targets);
  std::vector<Eigen::Triplet<double>> desired_entries;
  RandomStream rng(options.seed, 0);
  const MeshDomain domain(problem.model->mesh());
  const double rt = options.target_radius * R, rd = options.desired_radius * R;
  for (int k = 0; k < options.targets; ++k) {
    // Uniform over the points at least rt inside the sensor (the target stays inside).
    const Eigen::Vector2d at = target_centre(problem, domain, rt, rng);
    const double x = at.x(), y = at.y();
    // A target of label intensity 1; the desired image carries the same total intensity on a disc
    // of radius rd (clipped by the rim, so its mass is normalised after rasterising).
    const Eigen::VectorXd target = problem.from_image(circles_image(grid, {{x, y, rt, 0.0}}, 1.0));
    const Eigen::VectorXd desired = problem.from_image(circles_image(grid, {{x, y, rd, 0.0}}, 1.0));
    for (int j = 0; j < n; ++j)
      if (target[j] != 0) Y.col(k) += target[j] * problem.A.col(j);
    const double mass = target.sum() / std::max(desired.sum(), 1e-300);
    for (int j = 0; j < n; ++j)
      if (desired[j] != 0) desired_entries.emplace_back(j, k, desired[j] * mass);
  }
  Eigen::SparseMatrix<double> D(n, options.targets);
  D.setFromTriplets(desired_entries.begin(), desired_entries.end());
  YDt_ = (D * Y.transpose()).transpose();
  YYt_ = detail::lower_gram(Y);
  N_ = YYt_.diagonal();  // noise power proportional to each measurement's signal power
  set_lambda(lambda_, options.lambda == GreitOptions().lambda ? "default" : "fixed");
}

std::string Greit::settings() const {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer,
                "lambda=%.4g (%s), %d targets of radius %.3g R, desired radius %.3g R", lambda_,
                how_.c_str(), options_.targets, options_.target_radius, options_.desired_radius);
  return buffer;
}

void Greit::set_lambda(double relative, const std::string& how) {
  lambda_ = relative;
  how_ = how;
  // N is diag(Y Y^T), so lambda is already relative to the training frames' power: no scale.
  Eigen::MatrixXd S = YYt_;  // lower triangle
  S.diagonal() += relative * N_;
  // R = D Y^T S^-1, that is R^T = S^-1 Y D^T (S symmetric). S is positive definite where every
  // measurement sees some target; LDLT takes the semi-definite rest, as it always did. On KTC's
  // 2,356 values Cholesky through LAPACK took 2 s off the set-up (2-core Intel Xeon).
  std::optional<Eigen::MatrixXd> Rt = detail::cholesky_solve_columns(S, YDt_);
  if (!Rt) Rt = S.selfadjointView<Eigen::Lower>().ldlt().solve(YDt_);
  R_ = Rt->transpose().cast<float>();
}

void Greit::fit(const SampleMatrix& frames, const SampleMatrix& labels, const ScoreFn& score) {
  if (options_.choice != Criterion::validation) return;
  const double best = best_by_score(
      options_.candidates, [&](double l) { set_lambda(l, "sweep"); }, frames, labels, score, 500);
  set_lambda(best, "validation");
}

Eigen::VectorXd Greit::reconstruct(const Eigen::VectorXd& frame) const {
  problem_->check_frame_size(frame.size());
  const Eigen::VectorXf x = R_ * frame.cast<float>();
  return problem_->to_image(x.cast<double>());
}

SampleMatrix Greit::reconstruct_all(const SampleMatrix& frames) const {
  problem_->check_frame_size(frames.cols());
  return problem_->to_images((frames.cast<float>() * R_.transpose()).cast<double>());
}

bool Greit::set_regularisation(double relative, const std::string& how) {
  set_lambda(relative, how);
  return true;
}

}  // namespace eitbench
