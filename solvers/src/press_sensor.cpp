#include "eitbench/solvers/press_sensor.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "eitbench/jacobian/constants.h"
#include "eitbench/jacobian/error.h"
#include "shape_model.h"

namespace eitbench {

void PressSensorOptions::validate() const {
  if (!(min_radius > 0 && min_radius < max_radius && max_radius < 1))
    throw InputError("PressSensorOptions", "min_radius",
                     "needs 0 < min_radius < max_radius < 1 (x R)");
  if (!(start_radius >= min_radius && start_radius <= max_radius))
    throw InputError("PressSensorOptions", "start_radius", "must lie in [min_radius, max_radius]");
  if (!(max_scale > 1 && std::isfinite(max_scale)))
    throw InputError("PressSensorOptions", "max_scale", "must be above 1");
  if (!(max_turn_degrees > 0 && max_turn_degrees <= 180))
    throw InputError("PressSensorOptions", "max_turn_degrees", "must lie in (0, 180]");
  if (!(huber >= 0 && std::isfinite(huber)))
    throw InputError("PressSensorOptions", "huber", "must be 0 (off) or positive");
  if (max_iterations < 1) throw InputError("PressSensorOptions", "max_iterations", "must be >= 1");
}

namespace {

// The parameters, one block: [turn (radians), log scale, radius, contrast (per unit of depth)].
enum Parameter { kTurn, kLogScale, kRadius, kContrast, kParameters };

// One press's misfit, divided by the set's norm so that the cost is the relative residual squared
// (halved). Derivatives by the chain rule from the shape model's d/d[cx, cy, r, c]: the centre
// turns and scales with the recorded position, the contrast is the depth times the parameter.
class PressMisfit : public ceres::SizedCostFunction<ceres::DYNAMIC, kParameters> {
 public:
  PressMisfit(const detail::ShapeModel& model, Eigen::VectorXd measured, Eigen::Vector2d position,
              double depth, double norm)
      : model_(model),
        measured_(std::move(measured)),
        position_(std::move(position)),
        depth_(depth),
        norm_(norm) {
    set_num_residuals(static_cast<int>(measured_.size()));
  }

  // The model's change for this press at parameters `p`, and its d/d[cx, cy, r, c] when asked.
  Eigen::VectorXd predicted(const double* p, Eigen::MatrixXd* d = nullptr) const {
    const Eigen::Vector2d at = centre(p);
    const double circle[4] = {at.x(), at.y(), p[kRadius], p[kContrast] * depth_};
    return model_.difference({circle}, false, d);
  }

  // (predicted - measured) / norm: the press's share of the set's relative residual.
  Eigen::VectorXd misfit(const double* p) const { return (predicted(p) - measured_) / norm_; }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* p = parameters[0];
    Eigen::MatrixXd d;  // m x 4: by cx, cy, r, c
    const Eigen::VectorXd v = predicted(p, jacobians ? &d : nullptr);
    const Eigen::Index m = measured_.size();
    Eigen::Map<Eigen::VectorXd>(residuals, m) = (v - measured_) / norm_;
    if (jacobians && jacobians[0]) {
      const Eigen::Vector2d at = centre(p);
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, kParameters, Eigen::RowMajor>> J(
          jacobians[0], m, kParameters);
      J.col(kTurn) = (d.col(1) * at.x() - d.col(0) * at.y()) / norm_;
      J.col(kLogScale) = (d.col(0) * at.x() + d.col(1) * at.y()) / norm_;
      J.col(kRadius) = d.col(2) / norm_;
      J.col(kContrast) = d.col(3) * depth_ / norm_;
    }
    return true;
  }

 private:
  // The recorded (oriented) position turned and scaled by p: the disc's centre on the model.
  Eigen::Vector2d centre(const double* p) const {
    const double scale = std::exp(p[kLogScale]), c = std::cos(p[kTurn]), s = std::sin(p[kTurn]);
    const double x = position_.x(), y = position_.y();
    return {scale * (c * x - s * y), scale * (s * x + c * y)};
  }

  const detail::ShapeModel& model_;
  Eigen::VectorXd measured_;
  Eigen::Vector2d position_;
  double depth_, norm_;
};

void check_inputs(const LinearProblem& p, const SampleMatrix& differences,
                  const Eigen::MatrixX2d& positions, const Eigen::VectorXd& depths) {
  p.check_frame_size(differences.cols());
  if (differences.rows() != positions.rows())
    throw InputError("presses", "positions", "need one position a frame");
  if (depths.size() != 0 && depths.size() != positions.rows())
    throw InputError("presses", "depths", "need one depth a frame, or none");
  if (differences.rows() < 3) throw InputError("presses", "", "need at least 3 presses");
  if (!differences.allFinite() || !positions.allFinite())
    throw InputError("presses", "", "hold a value that is not finite");
  if (depths.allFinite() && (depths.array() <= 0).any())
    throw InputError("presses", "depths", "must be positive");
}

// The recorded positions, mirrored when the frame is: the turn and the scale are the fit's.
Eigen::Vector2d oriented(const Eigen::MatrixX2d& positions, Eigen::Index i, bool mirror) {
  return {positions(i, 0), mirror ? -positions(i, 1) : positions(i, 1)};
}

}  // namespace

Eigen::Vector2d model_position(const Eigen::Vector2d& recorded, double rotate_degrees, bool mirror,
                               double scale) {
  const double a = rotate_degrees * kPi / 180, c = std::cos(a), s = std::sin(a);
  const double x = scale * recorded.x(), y = scale * (mirror ? -recorded.y() : recorded.y());
  return {c * x - s * y, s * x + c * y};
}

Eigen::Vector2d recorded_position(const Eigen::Vector2d& on_model, double rotate_degrees,
                                  bool mirror, double scale) {
  const double a = -rotate_degrees * kPi / 180, c = std::cos(a), s = std::sin(a);
  const double x = (c * on_model.x() - s * on_model.y()) / scale;
  const double y = (s * on_model.x() + c * on_model.y()) / scale;
  return {x, mirror ? -y : y};
}

PressSensor fit_press_sensor(const LinearProblem& problem, const SampleMatrix& differences,
                             const Eigen::MatrixX2d& positions, const Eigen::VectorXd& depths,
                             const PressFrame& start, const PressSensorOptions& options) {
  options.validate();
  check_inputs(problem, differences, positions, depths);
  const detail::ShapeModel model(problem, 0);
  const double R = problem.grid.radius();
  const Eigen::Index n = differences.rows();
  const bool per_depth = depths.size() == n && depths.allFinite();
  const double norm = differences.norm();
  if (!(norm > 0)) throw InputError("presses", "", "hold no change: every frame is zero");

  // One misfit a press, kept here (Ceres borrows them) for the start and the residuals too.
  std::vector<std::unique_ptr<PressMisfit>> misfits;
  for (Eigen::Index i = 0; i < n; ++i)
    misfits.push_back(std::make_unique<PressMisfit>(model, differences.row(i).transpose(),
                                                    oriented(positions, i, start.mirror),
                                                    per_depth ? depths[i] : 1.0, norm));

  double p[kParameters] = {start.rotate_degrees * kPi / 180, 0, options.start_radius * R, 1};
  // The start's contrast: the least-squares one for the start's geometry (the model is linear in
  // it), so that the first step moves the geometry, not the amplitude.
  double along = 0, across = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::VectorXd u = misfits[static_cast<std::size_t>(i)]->predicted(p);  // contrast 1
    along += u.dot(differences.row(i).transpose());
    across += u.squaredNorm();
  }
  p[kContrast] = across > 0 ? along / across : 1;

  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem fit(po);
  for (const auto& misfit : misfits) {
    // Huber's scale is a residual norm (Ceres squares it): a press whose misfit is `huber` of a
    // typical press's change, ||D|| / sqrt(n) in these units.
    ceres::LossFunction* loss =
        options.huber > 0 ? new ceres::HuberLoss(options.huber / std::sqrt(static_cast<double>(n)))
                          : nullptr;
    fit.AddResidualBlock(misfit.get(), loss, p);
  }
  const double turn = p[kTurn], reach = options.max_turn_degrees * kPi / 180;
  fit.SetParameterLowerBound(p, kTurn, turn - reach);
  fit.SetParameterUpperBound(p, kTurn, turn + reach);
  fit.SetParameterLowerBound(p, kLogScale, -std::log(options.max_scale));
  fit.SetParameterUpperBound(p, kLogScale, std::log(options.max_scale));
  fit.SetParameterLowerBound(p, kRadius, options.min_radius * R);
  fit.SetParameterUpperBound(p, kRadius, options.max_radius * R);
  // A press lowers the conductivity (c > 0), never below zero (c < 1 at the deepest press).
  const double deepest = per_depth ? depths.maxCoeff() : 1.0;
  p[kContrast] = std::clamp(p[kContrast], 1e-6, 0.99 / deepest);
  fit.SetParameterLowerBound(p, kContrast, 0);
  fit.SetParameterUpperBound(p, kContrast, 0.99 / deepest);

  // ||model - measured|| / ||measured||, without the loss: what the fit's figure means.
  auto residual = [&] {
    double sum = 0;
    for (const auto& misfit : misfits) sum += misfit->misfit(p).squaredNorm();
    return std::sqrt(sum);
  };
  PressSensor out;
  out.start_residual = residual();
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = options.max_iterations;
  so.num_threads = 1;  // sums in one order: the same file on every run (ShapeModel is parallel)
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &fit, &summary);

  out.rotate_degrees = std::remainder(p[kTurn] * 180 / kPi, 360.0);
  if (out.rotate_degrees < 0) out.rotate_degrees += 360;
  out.mirror = start.mirror;
  out.scale = std::exp(p[kLogScale]);
  out.touch_radius = p[kRadius];
  out.contrast = p[kContrast];
  out.per_depth = per_depth;
  out.iterations = static_cast<int>(summary.iterations.size()) - 1;
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  out.relative_residual = residual();
  auto at = [](double v, double lo, double hi) {
    return std::abs(v - lo) < 1e-6 * std::abs(lo) || std::abs(v - hi) < 1e-6 * std::abs(hi);
  };
  out.scale_at_bound = at(p[kLogScale], -std::log(options.max_scale), std::log(options.max_scale));
  out.radius_at_bound = at(p[kRadius], options.min_radius * R, options.max_radius * R);
  return out;
}

}  // namespace eitbench
