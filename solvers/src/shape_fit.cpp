#include "shape_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace eitbench::detail {
namespace {

// The model at the last parameter point asked for: Ceres evaluates every measurement's block at
// the same point in turn (one thread), so the frame and its Jacobian are computed once per point.
class SharedEvaluation {
 public:
  SharedEvaluation(const ShapeModel& model, const Eigen::VectorXd& frame, int K, bool full)
      : model_(model), frame_(frame), K_(K), full_(full) {}

  // The residuals (model - frame), and the Jacobian when `jacobian` is set.
  void at(double const* const* parameters, bool jacobian) {
    if (same_point(parameters) && (has_jacobian_ || !jacobian)) return;
    point_.clear();
    for (int j = 0; j < K_; ++j)
      point_.insert(point_.end(), parameters[j], parameters[j] + kCircleParameters);
    const std::vector<const double*> circles(parameters, parameters + K_);
    residuals_ = model_.difference(circles, full_, jacobian ? &jacobian_ : nullptr) - frame_;
    has_jacobian_ = jacobian;
  }
  const Eigen::VectorXd& residuals() const { return residuals_; }
  const Eigen::MatrixXd& jacobian() const { return jacobian_; }

 private:
  bool same_point(double const* const* parameters) const {
    if (point_.size() != static_cast<std::size_t>(K_ * kCircleParameters)) return false;
    for (int j = 0; j < K_; ++j)
      for (int k = 0; k < kCircleParameters; ++k)
        if (point_[static_cast<std::size_t>(j * kCircleParameters + k)] != parameters[j][k])
          return false;
    return true;
  }
  const ShapeModel& model_;
  const Eigen::VectorXd& frame_;
  int K_;
  bool full_;
  std::vector<double> point_;
  bool has_jacobian_ = false;
  Eigen::VectorXd residuals_;
  Eigen::MatrixXd jacobian_;
};

// Measurements row .. row + count - 1. One block holds them all unless a robust loss must weigh
// each on its own: a block per measurement cost Ceres a tenth of a linear fit's time.
class MeasurementCost final : public ceres::CostFunction {
 public:
  MeasurementCost(SharedEvaluation& shared, int row, int count, int K)
      : shared_(shared), row_(row) {
    set_num_residuals(count);
    for (int j = 0; j < K; ++j) mutable_parameter_block_sizes()->push_back(kCircleParameters);
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    shared_.at(parameters, jacobians != nullptr);
    const int count = num_residuals();
    const auto rows = shared_.residuals().segment(row_, count);
    Eigen::Map<Eigen::VectorXd>(residuals, count) = rows;
    if (!rows.allFinite()) return false;
    if (!jacobians) return true;
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, kCircleParameters, Eigen::RowMajor>;
    for (std::size_t j = 0; j < parameter_block_sizes().size(); ++j)
      if (jacobians[j])
        Eigen::Map<RowMajor>(jacobians[j], count, kCircleParameters) = shared_.jacobian().block(
            row_, kCircleParameters * static_cast<Eigen::Index>(j), count, kCircleParameters);
    return true;
  }

 private:
  SharedEvaluation& shared_;
  int row_;
};

// weight * max(0, |centre| + r - R): zero inside the disk, growing as a circle leaves it.
class InsideCost final : public ceres::SizedCostFunction<1, kCircleParameters> {
 public:
  InsideCost(double radius, double weight) : radius_(radius), weight_(weight) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* p = parameters[0];
    const double rho = std::hypot(p[0], p[1]), excess = rho + p[2] - radius_;
    residuals[0] = excess > 0 ? weight_ * excess : 0;
    if (jacobians && jacobians[0]) {
      const bool on = excess > 0 && rho > 0;
      jacobians[0][0] = on ? weight_ * p[0] / rho : 0;
      jacobians[0][1] = on ? weight_ * p[1] / rho : 0;
      jacobians[0][2] = excess > 0 ? weight_ : 0;
      jacobians[0][3] = 0;
    }
    return true;
  }

 private:
  double radius_, weight_;
};

// A sensor of another shape: weight * max(0, |c_a - m_a| + r - h_a) on each axis a, zero while the
// circle stays in the mesh's bounding box (centre m, half-extents h). Exact for a rectangle; on an
// ellipse a circle may leave the sensor near the box's corners, where the mask clips its image.
class InsideBoxCost final : public ceres::SizedCostFunction<2, kCircleParameters> {
 public:
  InsideBoxCost(const Eigen::Vector2d& middle, const Eigen::Vector2d& half, double weight)
      : middle_(middle), half_(half), weight_(weight) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* p = parameters[0];
    if (jacobians && jacobians[0])
      std::fill(jacobians[0], jacobians[0] + 2 * kCircleParameters, 0.0);
    for (int a = 0; a < 2; ++a) {
      const double d = p[a] - middle_[a], excess = std::abs(d) + p[2] - half_[a];
      residuals[a] = excess > 0 ? weight_ * excess : 0;
      if (jacobians && jacobians[0] && excess > 0) {
        jacobians[0][a * kCircleParameters + a] = d >= 0 ? weight_ : -weight_;
        jacobians[0][a * kCircleParameters + 2] = weight_;
      }
    }
    return true;
  }

 private:
  Eigen::Vector2d middle_, half_;
  double weight_;
};

// Where a circle's centre may go: the disk's box, or the mesh's bounding box.
struct Domain {
  bool disk = true;
  double R = 1;
  Eigen::Vector2d lo, hi;
};

Domain domain_of(const LinearProblem& p) {
  Domain d;
  d.disk = p.grid.is_disk();
  d.R = p.grid.radius();
  if (d.disk) {
    d.lo = Eigen::Vector2d::Constant(-d.R), d.hi = Eigen::Vector2d::Constant(d.R);
  } else {
    d.lo = p.model->mesh().nodes.colwise().minCoeff().transpose();
    d.hi = p.model->mesh().nodes.colwise().maxCoeff().transpose();
  }
  return d;
}

// Moves a start's centre so that the circle lies inside the domain (as far as its radius allows).
void move_inside(CircleParameters& c, const Domain& d) {
  if (d.disk) {
    const double rho = std::hypot(c[0], c[1]), room = std::max(0.0, d.R - c[2]);
    if (rho > room) c[0] *= room / rho, c[1] *= room / rho;
    return;
  }
  for (int a = 0; a < 2; ++a) {
    const double m = 0.5 * (d.lo[a] + d.hi[a]),
                 room = std::max(0.0, 0.5 * (d.hi[a] - d.lo[a]) - c[2]);
    c[a] = std::clamp(c[a], m - room, m + room);
  }
}

ceres::Solver::Options solver_options(int max_iterations) {
  ceres::Solver::Options o;
  o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  o.linear_solver_type = ceres::DENSE_QR;  // 104 x 4K: dense and small
  o.max_num_iterations = max_iterations;
  o.function_tolerance = 1e-6;
  o.parameter_tolerance = 1e-6;
  o.num_threads = 1;  // frames run in parallel instead; SharedEvaluation assumes one thread
  o.logging_type = ceres::SILENT;
  return o;
}

}  // namespace

FitOutcome fit_shape(const ShapeModel& model, const Eigen::VectorXd& frame,
                     std::vector<CircleParameters> start, const FitSettings& settings) {
  const int K = static_cast<int>(start.size()), m = static_cast<int>(frame.size());
  FitOutcome out;
  out.circles = std::move(start);
  const Domain domain = domain_of(model.problem());
  const double R = domain.R;
  for (auto& c : out.circles) {  // Ceres starts inside the bounds, and inside the sensor
    c[2] = std::clamp(c[2], settings.min_radius, settings.max_radius);
    c[3] = std::clamp(c[3], settings.min_intensity, settings.max_intensity);
    move_inside(c, domain);
  }
  SharedEvaluation shared(model, frame, K, settings.full);
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  std::vector<double*> blocks;
  for (auto& c : out.circles) blocks.push_back(c.data());
  // Huber's scale from the start's residuals: a measurement far off the rest weighs less.
  double huber = 0;
  if (settings.robust_scale > 0) {
    shared.at(blocks.data(), false);
    huber = settings.robust_scale * std::sqrt(shared.residuals().squaredNorm() / m);
  }
  if (huber > 0)
    for (int i = 0; i < m; ++i)
      problem.AddResidualBlock(new MeasurementCost(shared, i, 1, K), new ceres::HuberLoss(huber),
                               blocks);
  else
    problem.AddResidualBlock(new MeasurementCost(shared, 0, m, K), nullptr, blocks);
  const double weight = 10 * std::max(frame.norm(), 1e-300) / R;
  for (double* b : blocks) {
    if (domain.disk)
      problem.AddResidualBlock(new InsideCost(R, weight), nullptr, b);
    else
      problem.AddResidualBlock(
          new InsideBoxCost(0.5 * (domain.lo + domain.hi), 0.5 * (domain.hi - domain.lo), weight),
          nullptr, b);
    for (int a = 0; a < 2; ++a)
      problem.SetParameterLowerBound(b, a, domain.lo[a]),
          problem.SetParameterUpperBound(b, a, domain.hi[a]);
    problem.SetParameterLowerBound(b, 2, settings.min_radius);
    problem.SetParameterUpperBound(b, 2, settings.max_radius);
    problem.SetParameterLowerBound(b, 3, settings.min_intensity);
    problem.SetParameterUpperBound(b, 3, settings.max_intensity);
  }
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options(settings.max_iterations), &problem, &summary);
  shared.at(blocks.data(), false);
  out.rss = shared.residuals().squaredNorm();
  out.iterations = static_cast<int>(summary.iterations.size());
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  return out;
}

}  // namespace eitbench::detail
