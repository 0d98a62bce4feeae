#pragma once
// Gauss-Newton: iterative and nonlinear. The unknowns are the in-disk pixels' relative
// conductivities x = sigma_pix / sigma_0 - 1 (the label-scale image is -x), and every step
// re-linearises the forward model: J_x = J_elem(sigma) P sigma_0. It minimises
//   Phi(x) = ||v(sigma(x)) - v_target||^2 + lambda ||W^1/2 (x - x_prior)||^2
// over the box min_ratio <= sigma / sigma_0 <= max_ratio, W = NOSER's diag(J^T J)^1/2 at the
// start, solving each step in measurement space (Woodbury) and searching along the projected step
// with backtracking until Armijo's sufficient decrease holds.
//
// Why the prior is on x and not on log-conductivity: a small inclusion's effect on the boundary
// voltages saturates as its conductivity grows, so the data term goes flat along it. A prior on
// log(sigma) then charges a spike only log^2 of its size, and the fit used spikes of a few pixels
// at 80-180 sigma_0 to absorb the model error between the simulation and reconstruction meshes
// (image values near -100 on noise-free quick frames). On x the charge grows with the square of
// the image value, as in the one-step methods, and the box keeps sigma positive.
//   difference mode: v_target = v(sigma_0) + dv (the frame is a difference frame), x_prior = 0
//   absolute mode:   v_target = the frame itself (absolute, the protocol's inputs), starting from
//   and
//                    regularised towards the best homogeneous conductivity
#include <memory>
#include <string>
#include <vector>

#include "eitbench/solvers/linear_problem.h"
#include "eitbench/solvers/reconstructor.h"
#include "eitbench/solvers/termination.h"

namespace eitbench {

struct GaussNewtonOptions {
  bool absolute = false;
  // Relative to the mean eigenvalue of J W^-1 J^T at the start, so that one value suits meshes
  // and protocols of any scale.
  double lambda = 1e-3;
  int max_iterations = 20;
  double tolerance = 1e-4;           // stop when Phi's relative decrease falls below this
  double residual_tolerance = 1e-6;  // or when ||r|| / ||v_target|| does
  double min_ratio = 1e-4;           // the box on sigma / sigma_0, far beyond any touch
  double max_ratio = 1e4;
  // fixed (lambda above) or validation (the candidates, by the score in fit(), on at most 20
  // frames); gcv, lcurve and discrepancy are refused.
  Criterion choice = Criterion::fixed;
  std::vector<double> candidates = {1e-5, 1e-4, 1e-3, 1e-2, 1e-1};

  // Throws InputError naming the field ("GaussNewtonOptions", field) for a value out of range.
  void validate() const;
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
    // ||v(sigma_k) - v_target|| and Phi at the start and after every accepted step.
    std::vector<double> residual;
    std::vector<double> objective;
    int iterations = 0;  // steps accepted
    Termination termination = Termination::iteration_limit;
    std::string message;  // why it stopped, with the figures that decided it
    bool converged() const { return termination == Termination::converged; }
  };
  Eigen::VectorXd solve(const Eigen::VectorXd& frame, Report* report) const;
  double lambda() const { return lambda_; }
  void set_lambda(double relative, const std::string& how);
  bool set_regularisation(double relative, const std::string& how) override;

 private:
  std::shared_ptr<const LinearProblem> problem_;  // never null
  GaussNewtonOptions options_;
  Eigen::VectorXd reference_;  // v(sigma_0), the inputs
  Eigen::VectorXd weight_;     // W (diagonal)
  double scale_ = 1;           // mean eigenvalue of J W^-1 J^T at sigma_0
  double lambda_;              // relative
  std::string how_ = "default";
};

}  // namespace eitbench
