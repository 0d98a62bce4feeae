#include "eitbench/solvers/greit.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <cstdio>

#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/random.h"

namespace eitbench {

Greit::Greit(const LinearProblem& problem, const GreitOptions& options)
    : problem_(problem), options_(options), lambda_(options.lambda) {
  if (options.targets < 10)
    throw InputError("targets", "", "GREIT needs at least 10 training targets");
  if (!(options.lambda > 0)) throw InputError("--lambda", "", "must be positive");
  const PixelGrid grid(problem.image_size, problem.radius);
  const double R = problem.radius;
  const int m = problem.measurements(), n = problem.unknowns();
  Eigen::MatrixXd Y(m, options.targets), D(n, options.targets);
  RandomStream rng(options.seed, 0);
  const double rt = options.target_radius * R, rd = options.desired_radius * R;
  for (int k = 0; k < options.targets; ++k) {
    // Uniform over the disk of radius R - rt (the target stays inside).
    const double rho = (R - rt) * std::sqrt(rng.uniform()), phi = 2 * M_PI * rng.uniform();
    const double x = rho * std::cos(phi), y = rho * std::sin(phi);
    // A target of label intensity 1; the desired image carries the same total intensity on a disc
    // of radius rd (clipped by the rim, so its mass is normalised after rasterising).
    const Eigen::VectorXd target = problem.from_image(circles_image(grid, {{x, y, rt, 0.0}}, 1.0));
    Eigen::VectorXd desired = problem.from_image(circles_image(grid, {{x, y, rd, 0.0}}, 1.0));
    desired *= target.sum() / std::max(desired.sum(), 1e-300);
    Y.col(k) = problem.A * target;
    D.col(k) = desired;
  }
  DYt_ = D * Y.transpose();
  YYt_ = Y * Y.transpose();
  N_ = YYt_.diagonal().asDiagonal();  // noise power proportional to each measurement's signal power
  set_lambda(lambda_, options.lambda == GreitOptions{}.lambda ? "default" : "fixed");
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
  const double scale = YYt_.trace() / N_.trace();
  const Eigen::MatrixXd S = YYt_ + relative * scale * N_;
  R_ = S.ldlt().solve(DYt_.transpose()).transpose().cast<float>();  // D Y^T S^-1 (S symmetric)
}

void Greit::fit(const SampleMatrix& frames, const SampleMatrix& labels, const ScoreFn& score) {
  if (!options_.choose_by_validation) return;
  if (!score || labels.rows() != frames.rows() || frames.rows() == 0)
    throw InputError("--choose validation", "", "needs labelled validation frames");
  double best_score = -INFINITY, best = lambda_;
  for (double relative : {1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1.0}) {
    set_lambda(relative, "sweep");
    const SampleMatrix images = reconstruct_all(frames);
    double total = 0;
    for (Eigen::Index i = 0; i < frames.rows(); ++i)
      total += score(images.row(i).transpose(), labels.row(i).transpose());
    if (total > best_score) best_score = total, best = relative;
  }
  set_lambda(best, "validation");
}

Eigen::VectorXd Greit::reconstruct(const Eigen::VectorXd& frame) const {
  if (frame.size() != problem_.measurements())
    throw InputError("frame", "",
                     "has " + std::to_string(frame.size()) + " values, the model " +
                         std::to_string(problem_.measurements()));
  const Eigen::VectorXf x = R_ * frame.cast<float>();
  return problem_.to_image(x.cast<double>());
}

SampleMatrix Greit::reconstruct_all(const SampleMatrix& frames) const {
  if (frames.cols() != problem_.measurements())
    throw InputError("frames", "",
                     "have " + std::to_string(frames.cols()) + " values, the model " +
                         std::to_string(problem_.measurements()));
  const Eigen::MatrixXd X = (frames.cast<float>() * R_.transpose()).cast<double>();
  SampleMatrix images = SampleMatrix::Zero(
      frames.rows(), static_cast<Eigen::Index>(problem_.image_size) * problem_.image_size);
  for (std::size_t j = 0; j < problem_.pixels.size(); ++j)
    images.col(problem_.pixels[j]) = X.col(static_cast<Eigen::Index>(j));
  return images;
}

}  // namespace eitbench
