#pragma once
// GREIT (Adler et al. 2009) on the 2-D disk: a linear reconstruction matrix trained on simulated
// small targets so that every target's image approaches a "desired image", a disc of fixed radius
// with the target's total intensity. That makes amplitude response, position error and resolution
// uniform across the disk by construction:
//   R = argmin sum_k ||d_k - R y_k||^2 + lambda sum_k ||R n_k||^2 = D Y^T (Y Y^T + lambda N)^-1,
// with y_k = A x_k the training frames (small targets are in the linear regime) and N the noise
// covariance, diagonal and proportional to each measurement's mean signal power.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "eitbench/solvers/linear_problem.h"
#include "eitbench/solvers/reconstructor.h"

namespace eitbench {

struct GreitOptions {
  int targets = 1000;            // training targets, uniform over the disk; at least 10
  double target_radius = 0.05;   // relative to R, in (0, 1)
  double desired_radius = 0.15;  // the desired image's disc, relative to R, in (0, 1]
  // The noise term's weight, positive and finite. N = diag(Y Y^T), so lambda is dimensionless: 1
  // weighs each measurement's noise as much as its mean training signal. It is not Adler et al.'s
  // noise figure (NF): choose it by validation or set it.
  double lambda = 1e-2;
  std::uint64_t seed = 1;
  // fixed (lambda above) or validation (the candidates, by the score in fit(), on at most 500
  // frames); gcv, lcurve and discrepancy are refused.
  Criterion choice = Criterion::fixed;
  std::vector<double> candidates = {1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1.0};

  // Throws InputError("GreitOptions", field) for a value out of range.
  void validate() const;
};

class Greit : public Reconstructor {
 public:
  // Keeps `problem` (shared with the other methods built on it) for as long as it lives.
  Greit(std::shared_ptr<const LinearProblem> problem, const GreitOptions& options);

  std::string name() const override { return "greit"; }
  std::string settings() const override;
  void fit(const SampleMatrix& frames, const SampleMatrix& labels, const ScoreFn& score) override;
  Eigen::VectorXd reconstruct(const Eigen::VectorXd& frame) const override;
  SampleMatrix reconstruct_all(const SampleMatrix& frames) const override;
  void set_lambda(double relative, const std::string& how);
  bool set_regularisation(double relative, const std::string& how) override;

 private:
  std::shared_ptr<const LinearProblem> problem_;  // never null
  GreitOptions options_;
  // The training products, kept to change lambda: Y D^T, the lower triangle of Y Y^T (its strict
  // upper triangle zero) and the noise N, diag(Y Y^T).
  Eigen::MatrixXd YDt_, YYt_;
  Eigen::VectorXd N_;
  double lambda_;
  std::string how_ = "default";
  Eigen::MatrixXf R_;  // n x m
};

}  // namespace eitbench
