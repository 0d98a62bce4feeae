#pragma once
// One-step Tikhonov: x = argmin ||A x - y||^2 + lambda ||R x||^2, set up in measurement space:
//   x = P A^T (G + lambda I)^-1 y,   P = (R^T R)^-1,   G = A P A^T (m x m).
// One eigendecomposition G = U diag(g) U^T serves every lambda: the fixed-lambda reconstruction
// matrix, GCV, the L-curve and the validation sweep. The per-frame work is one matrix-vector
// product.
#include <memory>
#include <optional>
#include <string>

#include "eitbench/solvers/linear_problem.h"
#include "eitbench/solvers/neighbours.h"
#include "eitbench/solvers/reconstructor.h"

namespace eitbench {

enum class Prior {
  identity,  // R = I
  noser,     // R^T R = diag(A^T A)^p (Cheney's NOSER; p = 0.5 as in EIDORS)
  laplace,   // R^T R = L^T L + epsilon I, L the Laplacian of the in-disk pixels (4-neighbour) or
             // of the elements (epsilon I because L has the constants in its kernel)
  smooth,    // P = (R^T R)^-1 a Gaussian covariance of the pixels' distance d, exp(-d^2 / 2b^2),
             // falling to 1 % at smooth_length (KTC2023's baseline prior, docs/reconstructors.md)
};
// Each parser throws InputError(the enum's name, "name") for a name it does not know.
Prior parse_prior(const std::string& method);  // tikhonov (or identity) | noser | laplace | smooth

struct TikhonovOptions {
  Prior prior = Prior::noser;
  double noser_exponent = 0.5;  // p of NOSER's diag(A^T A)^p, in [0, 1]
  // The fixed lambda, on the scale of G = A P A^T (see scale()), positive and finite. No default:
  // what suits depends on the mesh, the protocol and the prior, so it is given with choice ==
  // fixed and only then (another choice would ignore it).
  std::optional<double> lambda;
  // Whether the fixed lambda is a multiple of scale() (the grid's own unit) rather than absolute:
  // one relative value then means the same on problems of any size and weighting (the values a
  // frame has, their noise), as the other methods' lambdas do.
  bool relative = false;
  Criterion choice = Criterion::gcv;  // any criterion; validation sweeps the grid below
  // For choice == discrepancy, and only then: the frames' noise, as the RMS over a frame's values
  // (positive and finite; in the frames' units). Lambda is set so that the residual's RMS over
  // the frames, sqrt(mean ||y - A x||^2 / m), is discrepancy_factor times it: the largest lambda
  // (most regularised) whose misfit the noise explains. A factor above 1 allows for model error.
  // On real frames the misfit a model cannot remove (its own error) may exceed the noise at
  // every lambda; the grid's smallest lambda is then chosen (docs/real-presses.md).
  std::optional<double> noise;
  double discrepancy_factor = 1.0;  // Morozov's tau, at least 1
  int grid = 41;  // lambdas tried, at least 3: trace(G)/m x 10^[-8, 2], log-spaced
  // epsilon of the Laplace prior, relative to the mean diagonal of L^T L: positive and finite.
  double laplace_epsilon = 1e-3;
  // The smooth prior's correlation length, where the covariance falls to 1 %, in units of the
  // pixel grid's radius (the disk's): positive and finite. 1, as KTC2023's organisers set it
  // (115 mm on their 115 mm tank).
  double smooth_length = 1.0;
  Neighbours neighbours = Neighbours::pixels;
  // The reconstruction matrix in single precision: faster (docs/speed.md). Images
  // agree with double to 1e-7 at the grid's middle lambda but only to 8e-5 at its smallest, which
  // GCV returns on noise-free frames (tested); double for exact work (tiny lambdas amplify
  // rounding).
  bool single_precision = true;

  // Throws InputError("TikhonovOptions", field) for a value out of range.
  void validate() const;
};

class Tikhonov : public Reconstructor {
 public:
  // Keeps `problem` (shared with the other methods built on it) for as long as it lives.
  Tikhonov(std::shared_ptr<const LinearProblem> problem, const TikhonovOptions& options);

  std::string name() const override;
  std::string settings() const override;
  void fit(const SampleMatrix& frames, const SampleMatrix& labels, const ScoreFn& score) override;
  Eigen::VectorXd reconstruct(const Eigen::VectorXd& frame) const override;
  SampleMatrix reconstruct_all(const SampleMatrix& frames) const override;

  // GCV and the L-curve need only frames (no labels): the frames to be reconstructed, or others
  // from the same sensor. Each sets lambda and returns it.
  double choose_gcv(const SampleMatrix& frames);
  double choose_lcurve(const SampleMatrix& frames);
  // Needs options.noise. Within the grid's range (its ends when no lambda there matches).
  double choose_discrepancy(const SampleMatrix& frames);
  double choose_validation(const SampleMatrix& frames, const SampleMatrix& labels,
                           const ScoreFn& score);

  double lambda() const { return lambda_; }
  // The mean eigenvalue of G = A P A^T: lambdas are on this scale (the grid is scale x 10^[-8, 2]).
  double scale() const { return g_.mean(); }
  void set_lambda(double lambda, const std::string& how = "fixed");
  bool set_regularisation(double relative, const std::string& how) override;  // lambda / scale()
  const std::vector<double>& lambda_grid() const { return grid_; }
  // Per lambda of the grid: GCV function, residual norm and seminorm (sums over frames).
  std::vector<double> gcv_curve(const SampleMatrix& frames) const;
  // The frames' noise as GCV estimates it at the current lambda (Wahba): the residual's power
  // over the trace of I - H, an RMS per value. On real frames it holds the model's own error
  // beside the noise: what the method has to regularise against.
  double noise_estimate(const SampleMatrix& frames) const;

 private:
  // Per eigenvector of G, the frames' squared components along it, summed over the frames: what
  // GCV, the L-curve and the discrepancy principle weigh each lambda by.
  Eigen::ArrayXd eigen_power(const SampleMatrix& frames) const;
  std::shared_ptr<const LinearProblem> problem_;  // never null
  TikhonovOptions options_;
  Eigen::MatrixXd C_;  // P A^T U (n x m)
  Eigen::MatrixXd U_;  // eigenvectors of G
  Eigen::VectorXd g_;  // eigenvalues of G
  std::vector<double> grid_;
  double lambda_ = 0;
  std::string how_ = "unset";
  Eigen::MatrixXf M_;   // the reconstruction matrix n x m for lambda_ (single precision) ...
  Eigen::MatrixXd Md_;  // ... or in double precision
  // Forming M = C diag(f) U^T costs n m^2 for each lambda: 35 MFLOP for the 16-electrode
  // protocols' 104 values, 18 GFLOP (seconds) for KTC's 2356, where a sweep reconstructs a few
  // frames at each lambda. Past that the factors are applied instead, x = C (f .* (U^T y)):
  // m^2 + m n a frame instead of m n, and no M.
  bool factored_ = false;
  Eigen::VectorXd f_;  // 1 / (g + lambda_), for the factored form
};

}  // namespace eitbench
