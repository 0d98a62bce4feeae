#pragma once
// Total variation: the image minimises
//   ||A x - y||^2 / (kappa ||y||) + alpha sum_p s_p |grad x|_p,     kappa = ||A||_F,
// exact isotropic TV (forward differences over in-disk pixel neighbours, or differences across
// mesh edges), by the primal-dual method of Chambolle and Pock (2011). The data term's proximal
// step is exact and cheap in measurement space, so only the gradient operator sets the pace.
//
// s_p = (||A e_p|| / mean)^sensitivity_exponent weights each pixel's variation by how strongly
// the boundary sees it, as NOSER weights its prior: near the electrodes, where the data pin the
// image down, variation costs more; in the centre, where a touch gives a weak signal, less. On
// the EIDORS two-disc case it raises CC at the best alpha from 0.952 (exponent 0) to 0.966
// (exponent 1); on 100 validation frames of the quick data set from 0.817 to 0.838 (0.831 at
// exponent 0.5, 0.826 at 1.5).
//
// Why the data term is divided by kappa ||y||: both terms then grow linearly with the frame, so
// the solver is 1-homogeneous (the image of c y is c times the image of y) and one alpha means
// the same smoothing for a weak touch and a strong one. Dividing by ||y||^2 instead, as this
// solver once did, smoothed a frame c times stronger with c times the TV weight. A frame of norm
// kappa sees the objective ||A x - y||^2 / ||y||^2 + alpha TV(x), and the solver works on exactly
// that frame: y scaled to norm kappa, the image scaled back. (The old normalisation had one merit
// on simulated frames: it smoothed strong touches, mostly near the electrodes, more than weak
// central ones. The sensitivity weight above does that from the geometry, whatever the frame.)
//
// Starts from the NOSER solution; stops when the relative change of x falls below `tolerance`
// (not after a fixed count; max_iterations is a guard, and the report says which ended it).
#include <memory>
#include <string>
#include <vector>

#include "eitbench/solvers/linear_problem.h"
#include "eitbench/solvers/neighbours.h"
#include "eitbench/solvers/reconstructor.h"
#include "eitbench/solvers/termination.h"

namespace eitbench {

struct TotalVariationOptions {
  double alpha = 3e-5;      // TV weight, the quick set's validation choice (exponent 1)
  double tolerance = 1e-4;  // on ||x_k+1 - x_k|| / ||x_k+1||
  int max_iterations = 20000;
  // fixed (alpha above) or validation (the candidates, by the score in fit(), on at most 20
  // frames: a solve costs a tenth of a second); gcv, lcurve and discrepancy are refused.
  Criterion choice = Criterion::fixed;
  std::vector<double> candidates = {1e-6, 3e-6, 1e-5, 3e-5, 1e-4, 3e-4, 1e-3};
  // pixels: isotropic TV of the image; elements: sum over interior mesh edges of
  // (edge length / pixel width) |difference of the two elements' values P x| (anisotropic).
  Neighbours neighbours = Neighbours::pixels;
  // The exponent of the sensitivity weight s_p above; 0 gives plain TV.
  double sensitivity_exponent = 1.0;

  // Throws InputError naming the field ("TotalVariationOptions", field) for a value out of range.
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
    Termination termination = Termination::iteration_limit;
    std::string message;   // why it stopped, with the figures that decided it
    double objective = 0;  // the objective above at the image returned
    bool converged() const { return termination == Termination::converged; }
  };
  Eigen::VectorXd solve(const Eigen::VectorXd& frame, Report* report) const;
  double alpha() const { return alpha_; }
  void set_alpha(double alpha, const std::string& how);
  bool set_regularisation(double relative, const std::string& how) override;  // alpha

  // The objective above for an image (label scale) and a frame.
  double objective(const Eigen::VectorXd& image, const Eigen::VectorXd& frame) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::shared_ptr<const LinearProblem> problem_;  // never null
  TotalVariationOptions options_;
  double alpha_;
  std::string how_ = "default";
};

}  // namespace eitbench
