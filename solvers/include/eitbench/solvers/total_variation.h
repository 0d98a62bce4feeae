#pragma once
// Total variation: x = argmin ||A x - y||^2 / ||y||^2 + alpha sum_p |grad x|_p, exact isotropic TV
// (forward differences over in-disk pixel neighbours, or differences across mesh edges), by the
// primal-dual method of Chambolle and Pock (2011). The data term's proximal step is exact and cheap
// in measurement space, so only the gradient operator sets the pace. Starts from the NOSER
// solution; stops when the relative change of x falls below `tolerance` (not after a fixed count;
// max_iterations is a guard and is reported).
#include <memory>
#include <string>

#include "eitbench/solvers/linear_problem.h"
#include "eitbench/solvers/reconstructor.h"
#include "eitbench/solvers/tikhonov.h"

namespace eitbench {

struct TotalVariationOptions {
  double alpha = 3e-5;      // TV weight; the data term is normalised by ||y||^2
  double tolerance = 1e-4;  // on ||x_k+1 - x_k|| / ||x_k+1||
  int max_iterations = 20000;
  bool choose_by_validation = false;
  // pixels: isotropic TV of the image; elements: sum over interior mesh edges of
  // (edge length / pixel width) |difference of the two elements' values P x| (anisotropic).
  Neighbours neighbours = Neighbours::pixels;

  // Throws InputError("TotalVariationOptions", field) when alpha or tolerance is not positive
  // and finite, or max_iterations is below 1.
  void validate() const;
};

class TotalVariation : public Reconstructor {
 public:
  // Keeps `problem` (shared with the other methods built on it) for as long as it lives.
  TotalVariation(std::shared_ptr<const LinearProblem> problem,
                 const TotalVariationOptions& options);
  ~TotalVariation() override;

  std::string name() const override { return "tv"; }
  std::string settings() const override;
  void fit(const SampleMatrix& frames, const SampleMatrix& labels, const ScoreFn& score) override;
  Eigen::VectorXd reconstruct(const Eigen::VectorXd& frame) const override;

  struct Report {
    int iterations = 0;
    bool converged = false;  // the tolerance was met before max_iterations
  };
  Eigen::VectorXd solve(const Eigen::VectorXd& frame, Report* report) const;
  double alpha() const { return alpha_; }
  void set_alpha(double alpha, const std::string& how);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  std::shared_ptr<const LinearProblem> problem_;  // never null
  TotalVariationOptions options_;
  double alpha_;
  std::string how_ = "default";
};

}  // namespace eitbench
