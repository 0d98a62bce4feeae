#include "eitbench/solvers/gauss_newton.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <cstdio>

#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

// Log-conductivity bound: sigma / sigma_0 within [1e-4, 1e4], far beyond any touch.
constexpr double kMaxLog = 9.21;

struct State {
  Eigen::VectorXd v;  // reduced frame of sigma(theta)
  Eigen::MatrixXd J;  // d v / d theta (m x n)
};

State evaluate(const LinearProblem& p, const Eigen::VectorXd& theta, bool jacobian) {
  const Eigen::VectorXd sigma_pix = p.background * theta.array().exp();
  const Eigen::VectorXd sigma = p.pixel_to_element * sigma_pix;
  const ForwardSolution s = p.model->solve(sigma);
  State out;
  out.v = p.model->protocol().reduce(p.model->frame(s), MeasurementOrder::rotating);
  if (jacobian) {
    const Eigen::MatrixXd J = p.model->jacobian(s, p.model->protocol().reduced_pairs());
    out.J = (J * p.pixel_to_element) * sigma_pix.asDiagonal();
  }
  return out;
}

}  // namespace

GaussNewton::GaussNewton(std::shared_ptr<const LinearProblem> shared,
                         const GaussNewtonOptions& options)
    : problem_(require_problem(std::move(shared), "GaussNewton")), options_(options) {
  const LinearProblem& problem = *problem_;
  if (!problem.model)
    throw std::invalid_argument("GaussNewton: the linear problem has no forward model");
  if (options.lambda < 0 || !std::isfinite(options.lambda))
    throw InputError("--lambda", "", "must be positive");
  if (options.lambda > 0) lambda_ = options.lambda, how_ = "fixed";
  const State s0 = evaluate(problem, Eigen::VectorXd::Zero(problem.unknowns()), true);
  reference_ = s0.v;
  const Eigen::VectorXd w =
      s0.J.colwise().squaredNorm().transpose().array().sqrt();  // NOSER, p = 1/2
  weight_ = w.cwiseMax(1e-12 * w.maxCoeff());
  scale_ = (s0.J * weight_.cwiseInverse().asDiagonal() * s0.J.transpose()).trace() /
           problem.measurements();
}

std::string GaussNewton::settings() const {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, "lambda=%.4g (%s), %s mode", lambda_, how_.c_str(),
                options_.absolute ? "absolute" : "difference");
  return buffer;
}

void GaussNewton::set_lambda(double relative, const std::string& how) {
  lambda_ = relative;
  how_ = how;
}

Eigen::VectorXd GaussNewton::solve(const Eigen::VectorXd& frame, Report* report) const {
  const LinearProblem& p = *problem_;
  p.check_frame_size(frame.size());
  const Eigen::VectorXd target = options_.absolute ? frame : Eigen::VectorXd(reference_ + frame);
  Eigen::VectorXd theta = Eigen::VectorXd::Zero(p.unknowns());
  if (options_.absolute) {  // the best homogeneous start: v scales as 1 / sigma
    const double c = reference_.dot(target) / reference_.squaredNorm();
    if (!(c > 0))
      throw InputError("frame", "",
                       "does not look like an absolute frame (negative fit to the model)");
    theta.setConstant(-std::log(c));
  }
  const double lambda = lambda_ * scale_;
  // The prior's centre: sigma_0 in difference mode, the best homogeneous fit in absolute mode.
  const Eigen::VectorXd prior = theta;
  auto objective = [&](const Eigen::VectorXd& v, const Eigen::VectorXd& t) {
    return (v - target).squaredNorm() +
           lambda * (weight_.array() * (t - prior).array().square()).sum();
  };
  State s = evaluate(p, theta, true);
  double phi = objective(s.v, theta);
  Report local;
  local.residual.push_back((s.v - target).norm());
  local.objective.push_back(phi);
  const Eigen::VectorXd winv = weight_.cwiseInverse() / lambda;  // (lambda W)^-1
  for (int it = 0; it < options_.max_iterations; ++it) {
    // (J^T J + lambda W) delta = -(J^T r + lambda W theta), by Woodbury in measurement space.
    const Eigen::VectorXd r = s.v - target;
    const Eigen::VectorXd g = s.J.transpose() * r + lambda * weight_.cwiseProduct(theta - prior);
    const Eigen::VectorXd a = winv.cwiseProduct(g);
    const Eigen::MatrixXd S = Eigen::MatrixXd::Identity(p.measurements(), p.measurements()) +
                              s.J * winv.asDiagonal() * s.J.transpose();
    const Eigen::VectorXd delta =
        -(a - winv.cwiseProduct(s.J.transpose() * S.ldlt().solve(s.J * a)));
    // Backtracking: halve the step until Phi decreases. The step is projected onto
    // |theta| <= kMaxLog, and a trial the forward model cannot solve (a conductivity so extreme
    // that the system loses definiteness in floating point) counts as no descent: a noisy frame
    // at a small lambda once drove a step there (quick set, 30 dB).
    double step = 1.0, next_phi = INFINITY;
    Eigen::VectorXd next;
    State trial;
    for (int k = 0; k < 12; ++k, step *= 0.5) {
      next = (theta + step * delta).cwiseMax(-kMaxLog).cwiseMin(kMaxLog);
      try {
        trial = evaluate(p, next, false);
        next_phi = objective(trial.v, next);
      } catch (const std::exception&) {
        next_phi = INFINITY;
      }
      if (next_phi < phi) break;
    }
    ++local.iterations;
    if (!(next_phi < phi)) {  // no descent along the Gauss-Newton direction: at a minimum
      local.converged = true;
      break;
    }
    const double decrease = (phi - next_phi) / phi;
    theta = next;
    phi = next_phi;
    local.residual.push_back((trial.v - target).norm());  // the line search solved this theta
    local.objective.push_back(phi);
    if (decrease < options_.tolerance ||
        local.residual.back() < options_.residual_tolerance * target.norm()) {
      local.converged = true;
      break;
    }
    s = evaluate(p, theta, true);  // re-linearise only when another step follows
  }
  if (report) *report = local;
  // On the label scale: -dsigma / sigma_0 = 1 - sigma / sigma_0 (against sigma_0 in both modes).
  return p.to_image((1.0 - theta.array().exp()).matrix());
}

Eigen::VectorXd GaussNewton::reconstruct(const Eigen::VectorXd& frame) const {
  return solve(frame, nullptr);
}

void GaussNewton::fit(const SampleMatrix& frames, const SampleMatrix& labels,
                      const ScoreFn& score) {
  if (!options_.choose_by_validation) return;
  const double best = best_by_score(
      {1e-5, 1e-4, 1e-3, 1e-2, 1e-1}, [&](double l) { lambda_ = l; }, frames, labels, score, 20);
  set_lambda(best, "validation");
}

}  // namespace eitbench
