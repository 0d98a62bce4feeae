#pragma once
// Parametric reconstruction: the touch as K circles on the background, fitted to the frame by
// nonlinear least squares (Ceres, Levenberg-Marquardt). Each circle has a centre, a radius and an
// intensity c (sigma = sigma_0 (1 - c) inside, the label scale's value); the conductivity is the
// product of smoothed indicators over the reconstruction mesh's elements (about one element
// wide), and the residuals are the frame's inputs (any protocol), with analytic derivatives through
// the element Jacobian. Two forward models: `linear` (the Jacobian at the background: fast) and
// `full` (the FEM re-solved at every step, starting from the linear fit). The start is the
// peaks of a one-step NOSER image; K is chosen in 1..max_touches by the Bayesian information
// criterion, whose penalty weight can be chosen on validation frames: on the linear fits, and for
// `full` then on the FEM's own fits, up or down from the linear K. The output is the circles,
// and the image they draw, so every image metric applies.
#include <memory>
#include <string>
#include <vector>

#include "eitbench/jacobian/geometry.h"
#include "eitbench/solvers/linear_problem.h"
#include "eitbench/solvers/reconstructor.h"

namespace eitbench {

enum class ShapeForward { linear, full };
ShapeForward parse_shape_forward(const std::string& name);  // linear | full; InputError else
const char* to_string(ShapeForward forward);

struct ShapeOptions {
  ShapeForward forward = ShapeForward::linear;
  int max_touches = 4;  // K is chosen in 1..max_touches (1 to 4)
  // The bounds, in units of the sensor radius R for the radius; intensities on the label scale.
  double min_radius = 0.03, max_radius = 0.35;
  double min_intensity = 0.02, max_intensity = 0.999;  // 0 < min < max < 1 (sigma stays > 0)
  // The indicator's transition width in units of R; 0: half the mesh's mean element size.
  double width = 0;
  // Huber's loss on each measurement's residual, at this multiple of the residuals' RMS at the
  // start (0: plain least squares). Outlying electrodes then weigh less.
  double robust_scale = 0;
  int max_iterations = 50;  // Levenberg-Marquardt steps per fit
  // The start: peaks of the NOSER image at least this fraction of its maximum, lambda (relative
  // to the mean eigenvalue of A P A^T) of that image.
  double seed_threshold = 0.3;
  double seed_lambda = 1e-2;
  // BIC = m log(RSS / m) + penalty 4K log m: fixed, or validation (the candidates, by the score
  // in fit(), on at most 20 frames).
  double penalty = 1;
  // The smallest residual the BIC believes, as an RMS relative to the frame's: the model's own
  // error (smoothed circles on the reconstruction mesh against the sensor) is about 1 % of a
  // frame, and below it extra circles buy misfit that is not noise. At 1e-3 a single touch got a
  // phantom in most frames (45 % counted right on the quick set's one-touch frames; 100 % at 1e-2).
  double noise_floor = 1e-2;
  Criterion choice = Criterion::fixed;
  std::vector<double> candidates = {0.25, 0.5, 1, 2, 4};

  // Throws InputError("ShapeOptions", field) for a value out of range.
  void validate() const;
};

struct ShapeFit {
  std::vector<Circle> circles;  // conductivity sigma_0 (1 - c)
  double rss = 0;               // the data misfit at the fit, sum of squares
  int iterations = 0;           // Levenberg-Marquardt steps, every K tried
  bool converged = false;       // the chosen fit's solver converged
};

class ShapeReconstructor : public Reconstructor {
 public:
  // Keeps `problem` (shared with the other methods built on it) for as long as it lives.
  ShapeReconstructor(std::shared_ptr<const LinearProblem> problem, const ShapeOptions& options);
  ~ShapeReconstructor() override;

  std::string name() const override { return "shape"; }
  std::string settings() const override;
  void fit(const SampleMatrix& frames, const SampleMatrix& labels, const ScoreFn& score) override;
  // The image the fitted circles draw (exact pixel coverage), on the label scale.
  Eigen::VectorXd reconstruct(const Eigen::VectorXd& frame) const override;
  bool finds_circles() const override { return true; }
  std::vector<Circle> touches(const Eigen::VectorXd& frame, Eigen::VectorXd& image) const override;

  // The circles of one difference frame (the protocol's inputs); InputError for a frame of the
  // wrong length or with a non-finite value.
  ShapeFit fit_circles(const Eigen::VectorXd& frame) const;
  // The fit with exactly K circles from the given start ([cx, cy, r, c] each): what
  // fit_circles does for each K.
  ShapeFit fit_circles(const Eigen::VectorXd& frame, std::vector<Circle> start,
                       ShapeForward forward) const;
  // The linear fits fit_circles chooses among: entry K holds K circles (entry 0 none, its rss the
  // frame's squared norm); fewer than max_touches + 1 entries when the residual image has no peak.
  std::vector<ShapeFit> fits_by_count(const Eigen::VectorXd& frame) const;
  // Circles as images, on the label scale.
  Eigen::VectorXd draw(const std::vector<Circle>& circles) const;
  double penalty() const { return penalty_; }
  void set_penalty(double penalty, const std::string& how);

  struct Impl;

 private:
  std::shared_ptr<const LinearProblem> problem_;  // never null
  ShapeOptions options_;
  std::unique_ptr<Impl> impl_;
  double penalty_;
  std::string how_ = "default";
};

}  // namespace eitbench
