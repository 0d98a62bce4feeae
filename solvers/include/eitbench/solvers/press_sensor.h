#pragma once
// Fitting the simulated press to real ones: from a labelled set of presses, the frame their
// recorded positions lie in (a turn, a mirror, a scale to the mesh's unit) and the touch that best
// explains their changes (a disc's radius, and its contrast per unit of depth where depths are
// known), by nonlinear least squares with Ceres over all presses at once. The model is the shape
// fit's linear one (a smoothed disc through the Jacobian at the background), so a fitted touch is
// what the simulation and the shape fit draw. The frame's search (press_frame.h) gives the start:
// a turn on a grid and the handedness, which a local fit cannot change. Part of fitting a sensor
// to real presses (docs/real-presses.md).
#include <Eigen/Core>

#include "eitbench/jacobian/sample_matrix.h"
#include "eitbench/solvers/linear_problem.h"
#include "eitbench/solvers/press_frame.h"

namespace eitbench {

struct PressSensorOptions {
  double start_radius = 0.1;  // the disc's radius to start from (x R)
  double min_radius = 0.02;   // the radius stays within [min, max] (x R)
  double max_radius = 0.5;
  double max_scale = 2;          // the scale stays within [1 / max_scale, max_scale] (> 1)
  double max_turn_degrees = 20;  // the turn moves at most this far from the search's (> 0)
  // 0: plain least squares. Otherwise a Huber loss on each press whose misfit exceeds this
  // fraction of a typical press's change (the set's norm / sqrt(n)), so that a few presses the
  // model cannot explain (a slipped probe) do not pull the fit.
  double huber = 0;
  int max_iterations = 100;  // Levenberg-Marquardt steps, at least 1
  void validate() const;     // InputError("PressSensorOptions", field)
};

struct PressSensor {
  // A recorded position p is R(rotate_degrees) M (scale p) in the model's frame (M: y -> -y when
  // `mirror`), as PressFrame's.
  double rotate_degrees = 0;
  bool mirror = false;
  double scale = 1;
  double touch_radius = 0;  // the disc's radius, the model's unit
  // The disc's contrast on the label scale (sigma = sigma_0 (1 - c) inside): per unit of the
  // press's depth when `per_depth`, else the same for every press.
  double contrast = 0;
  bool per_depth = false;
  // ||model - measured|| / ||measured|| over all presses: at the start (the search's frame, the
  // start radius, the best contrast for it) and at the fit.
  double start_residual = 0, relative_residual = 0;
  int iterations = 0;
  bool converged = false;
  // The fit ended on a bound (options): worth a look, e.g. positions in another unit.
  bool scale_at_bound = false, radius_at_bound = false;
};

// A recorded position on the model, R(a) M (scale p), and back: p = M R(-a) q / scale (a in
// degrees, M: y -> -y when mirror).
Eigen::Vector2d model_position(const Eigen::Vector2d& recorded, double rotate_degrees, bool mirror,
                               double scale);
Eigen::Vector2d recorded_position(const Eigen::Vector2d& on_model, double rotate_degrees,
                                  bool mirror, double scale);

// differences: N x m measured changes in the model's units (the problem's inputs); positions: N x
// 2 recorded centres; depths: N values, or empty where no depth is known (NaN anywhere: none are
// used). `start`: the frame search's result on the same presses. InputError for shapes that do not
// match, fewer than 3 presses, values that are not finite, or depths that are not positive.
PressSensor fit_press_sensor(const LinearProblem& problem, const SampleMatrix& differences,
                             const Eigen::MatrixX2d& positions, const Eigen::VectorXd& depths,
                             const PressFrame& start, const PressSensorOptions& options = {});

}  // namespace eitbench
