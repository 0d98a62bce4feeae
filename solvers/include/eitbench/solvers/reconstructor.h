#pragma once
// One interface for every reconstructor (docs/conventions.md): an optional fit on labelled data,
// then difference frame -> image. Frames are difference voltages, the protocol's inputs (the
// reduced 104 for the adjacent protocol); images are image_size^2 values on the label scale,
// -dsigma/sigma_0, row-major, 0 outside the disk.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "eitbench/jacobian/geometry.h"
#include "eitbench/jacobian/sample_matrix.h"

namespace eitbench {

// How a method's hyperparameter is chosen: one mechanism for every method (EIDORS, too, keeps the
// choice apart from the solvers). Each options struct has a `choice` and, where it can sweep, its
// `candidates`; asking a method for a criterion it cannot use is an InputError, never ignored.
enum class Criterion {
  fixed,       // the value in the options
  validation,  // the candidate with the best total score on labelled frames, in fit()
  gcv,         // generalised cross-validation: one-step linear methods only (frames, no labels)
  lcurve,      // the L-curve's corner: one-step linear methods only (frames, no labels)
  // Morozov's discrepancy principle: the lambda whose residual matches the frames' known noise
  // (one-step linear methods; frames and a noise level, no labels).
  discrepancy,
};
const char* to_string(Criterion c);
// fixed | validation | gcv | lcurve | discrepancy; InputError("Criterion", "name") for another.
Criterion parse_criterion(const std::string& name);
// For the methods that choose by validation or take a fixed value (TV, Gauss-Newton, GREIT):
// InputError(options, "choice") for gcv, lcurve or discrepancy, InputError(options, "candidates")
// for validation with no candidates or one that is not positive and finite.
void check_fixed_or_validation(const char* options, Criterion choice,
                               const std::vector<double>& candidates);

// How good an image is against its label (higher is better): the caller's metric, e.g. the mean
// correlation coefficient of bench/metrics. Reconstructors choose hyperparameters by it.
using ScoreFn = std::function<double(const Eigen::VectorXd& image, const Eigen::VectorXd& label)>;

class Reconstructor {
 public:
  virtual ~Reconstructor() = default;
  virtual std::string name() const = 0;
  // Hyperparameters and how they were chosen, for reports ("lambda=0.012 (gcv)").
  virtual std::string settings() const = 0;

  // Chooses hyperparameters on labelled frames (one a row) by `score`. Does nothing by default.
  virtual void fit(const SampleMatrix& frames, const SampleMatrix& labels, const ScoreFn& score);

  // Sets the method's regularisation weight on its own relative scale (the value its options'
  // fixed choice takes: Tikhonov's lambda in units of its scale(), TV's alpha, Gauss-Newton's and
  // GREIT's lambda), keeping what the method precomputed, so that a sweep over it costs only the
  // reconstructions; `how` is what settings() reports. False, nothing changed, for a method
  // without one (the default).
  virtual bool set_regularisation(double relative, const std::string& how);

  virtual Eigen::VectorXd reconstruct(const Eigen::VectorXd& frame) const = 0;
  // Many frames at once: in parallel over frames by default (reconstruct() must be thread-safe,
  // as every const method here is); linear methods use one matrix product.
  virtual SampleMatrix reconstruct_all(const SampleMatrix& frames) const;

  // Whether the method finds the touches as circles (the shape fit): then touches() gives them,
  // and the touch metrics take them as found instead of looking for blobs in the image.
  virtual bool finds_circles() const { return false; }
  // The circles of one frame and, in `image`, the image they draw. Only for a method that
  // finds_circles(); std::logic_error otherwise.
  virtual std::vector<Circle> touches(const Eigen::VectorXd& frame, Eigen::VectorXd& image) const;
  // touches() of every frame (one a row), in parallel: circles per frame, images in `images`.
  std::vector<std::vector<Circle>> touches_all(const SampleMatrix& frames,
                                               SampleMatrix& images) const;

 protected:
  // The validation sweep of the iterative and trained methods: for each candidate, set(candidate)
  // then score reconstruct_all on at most `max_frames` frames spread evenly; returns the candidate
  // with the best total score. InputError when labels or the score are missing.
  double best_by_score(const std::vector<double>& candidates,
                       const std::function<void(double)>& set, const SampleMatrix& frames,
                       const SampleMatrix& labels, const ScoreFn& score,
                       Eigen::Index max_frames) const;
  // Row indices 0, k, 2k, ... with k rounded up so that at most `at_most` are taken.
  static std::vector<Eigen::Index> spread_rows(Eigen::Index rows, Eigen::Index at_most);
};

}  // namespace eitbench
