#pragma once
// Gauss-Newton: iterative and nonlinear. Unknowns are log-conductivities on the in-disk pixels,
// sigma_pix = sigma_0 exp(theta) (so conductivity stays positive), and every step re-linearises
// the forward model: J_theta = J_elem(sigma) P diag(sigma_pix). It minimises
//   Phi(theta) = ||v(sigma(theta)) - v_target||^2 + lambda ||W^1/2 (theta - theta_prior)||^2,
// W = NOSER's diag(J^T J)^1/2 at the start, solving each step in measurement space (Woodbury),
// with a backtracking line search that accepts only steps that lower Phi. It stops when Phi's
// relative decrease or the relative residual falls below its tolerance.
//   difference mode: v_target = v(sigma_0) + dv (the frame is a difference frame)
//   absolute mode:   v_target = the frame itself (absolute, reduced layout), starting from and
//                    regularised towards the best homogeneous conductivity
// (theta_prior = 0, i.e. sigma_0, in difference mode).
#include <memory>
#include <string>
#include <vector>

#include "eitbench/solvers/linear_problem.h"
#include "eitbench/solvers/reconstructor.h"

namespace eitbench {

struct GaussNewtonOptions {
  bool absolute = false;
  double lambda = 0;  // relative to the mean eigenvalue of J W^-1 J^T at the start; 0: default 1e-3
  int max_iterations = 20;
  double tolerance = 1e-4;           // on Phi's relative decrease
  double residual_tolerance = 1e-6;  // on ||r|| / ||v_target||
  bool choose_by_validation = false;
};

class GaussNewton : public Reconstructor {
 public:
  // Keeps `problem` (shared with the other methods built on it) for as long as it lives.
  GaussNewton(std::shared_ptr<const LinearProblem> problem, const GaussNewtonOptions& options);

  std::string name() const override { return "gn"; }
  std::string settings() const override;
  void fit(const SampleMatrix& frames, const SampleMatrix& labels, const ScoreFn& score) override;
  Eigen::VectorXd reconstruct(const Eigen::VectorXd& frame) const override;

  struct Report {
    std::vector<double>
        residual;  // ||v(sigma_k) - v_target|| at the start and after every accepted step
    std::vector<double> objective;  // Phi at the same points
    int iterations = 0;
    bool converged = false;
  };
  Eigen::VectorXd solve(const Eigen::VectorXd& frame, Report* report) const;
  void set_lambda(double relative, const std::string& how);

 private:
  std::shared_ptr<const LinearProblem> problem_;  // never null
  GaussNewtonOptions options_;
  Eigen::VectorXd reference_;  // v(sigma_0), reduced
  Eigen::VectorXd weight_;     // W (diagonal)
  double scale_ = 1;           // mean eigenvalue of J W^-1 J^T at sigma_0
  double lambda_ = 1e-3;       // relative
  std::string how_ = "default";
};

}  // namespace eitbench
