#include "eitbench/solvers/gauss_newton.h"

#include <cmath>
#include <cstdio>
#include <optional>

#include "eitbench/jacobian/error.h"
#include "eitbench/solvers/dense_lapack.h"
#include "line_search.h"

namespace eitbench {
namespace {

struct State {
  Eigen::VectorXd x;  // relative conductivities sigma_pix / sigma_0 - 1
  ForwardSolution solution;
  Eigen::VectorXd v;  // the protocol's inputs of sigma(x)
  Eigen::MatrixXd J;  // d v / d x (m x n), once linearised
  double phi = INFINITY;
};

State forward(const LinearProblem& p, Eigen::VectorXd x) {
  State s;
  const Eigen::VectorXd sigma_pix = p.background * (1.0 + x.array()).matrix();
  s.solution = p.model->solve(p.element_from_pixels * sigma_pix);
  s.v = p.model_inputs(s.solution);
  s.x = std::move(x);
  return s;
}

// The Jacobian at a state, from the fields its forward solve already holds (the line search
// solved the accepted step; solving it again only to linearise would double that cost).
void linearise(const LinearProblem& p, State& s) {
  s.J = (p.model_jacobian(s.solution) * p.element_from_pixels) * p.background;
}

// One frame's objective: data misfit plus the weighted prior, over the box on x.
struct Objective {
  const LinearProblem& p;
  Eigen::VectorXd target;  // the inputs to fit
  Eigen::VectorXd prior;   // x_prior
  const Eigen::VectorXd& weight;
  double lambda;  // absolute: relative lambda times the scale
  double lower, upper;

  State evaluate(Eigen::VectorXd x) const {
    State s = forward(p, std::move(x));
    s.phi = (s.v - target).squaredNorm() +
            lambda * (weight.array() * (s.x - prior).array().square()).sum();
    return s;
  }
  // Half the gradient of Phi: J^T r + lambda W (x - x_prior).
  Eigen::VectorXd gradient(const State& s) const {
    return s.J.transpose() * (s.v - target) + lambda * weight.cwiseProduct(s.x - prior);
  }
  // (J^T J + lambda W) delta = -g, by Woodbury in measurement space (m << n), over the free
  // pixels only: one held at a bound by its gradient keeps delta = 0 (its (lambda W)^-1 entry is
  // 0, an infinite weight), or the projected step need not descend (projected Newton).
  // Empty where S below is not positive definite, which takes a non-finite Jacobian.
  std::optional<Eigen::VectorXd> direction(const State& s, const Eigen::VectorXd& g) const {
    Eigen::VectorXd winv = weight.cwiseInverse() / lambda;  // (lambda W)^-1
    for (Eigen::Index i = 0; i < winv.size(); ++i)
      if ((s.x[i] <= lower && g[i] > 0) || (s.x[i] >= upper && g[i] < 0)) winv[i] = 0;
    const Eigen::VectorXd a = winv.cwiseProduct(g);
    // S = I + J W^-1 J^T, symmetric positive definite: only its lower triangle is formed (half
    // the product) and factorised. Three quarters of a KTC frame's time went to these two.
    const Eigen::MatrixXd Jw = s.J * winv.cwiseSqrt().asDiagonal();
    const auto solved = detail::cholesky_solve(detail::lower_gram(Jw, 1), s.J * a);
    if (!solved) return {};
    return -(a - winv.cwiseProduct(s.J.transpose() * *solved));
  }
  Eigen::VectorXd project(const Eigen::VectorXd& x) const {
    return x.cwiseMax(lower).cwiseMin(upper);
  }
};

std::string message(const char* format, double a, double b = 0) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, format, a, b);
  return buffer;
}

}  // namespace

void GaussNewtonOptions::validate() const {
  auto fail = [](const char* field, const std::string& why) {
    throw InputError("GaussNewtonOptions", field, why);
  };
  if (!(lambda > 0) || !std::isfinite(lambda)) fail("lambda", "must be positive and finite");
  if (max_iterations < 0) fail("max_iterations", "must not be negative");
  if (!(tolerance >= 0)) fail("tolerance", "must not be negative");
  if (!(residual_tolerance >= 0)) fail("residual_tolerance", "must not be negative");
  if (!(min_ratio > 0 && min_ratio < 1)) fail("min_ratio", "must lie in (0, 1)");
  if (!(max_ratio > 1) || !std::isfinite(max_ratio)) fail("max_ratio", "must be above 1");
  check_fixed_or_validation("GaussNewtonOptions", choice, candidates);
}

GaussNewton::GaussNewton(std::shared_ptr<const LinearProblem> shared,
                         const GaussNewtonOptions& options)
    : problem_(require_problem(std::move(shared), "GaussNewton")),
      options_(options),
      lambda_(options.lambda) {
  options.validate();
  const LinearProblem& problem = *problem_;
  if (!problem.model)
    throw std::invalid_argument("GaussNewton: the linear problem has no forward model");
  State s0 = forward(problem, Eigen::VectorXd::Zero(problem.unknowns()));
  linearise(problem, s0);
  reference_ = s0.v;
  const Eigen::VectorXd w =
      s0.J.colwise().squaredNorm().transpose().array().sqrt();  // NOSER, p = 1/2
  weight_ = w.cwiseMax(1e-12 * w.maxCoeff());
  // trace(J W^-1 J^T) / m, without forming the m x m product.
  scale_ = (s0.J.array().square().rowwise() * weight_.cwiseInverse().transpose().array()).sum() /
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
  Objective f{p,
              options_.absolute ? frame : Eigen::VectorXd(reference_ + frame),
              Eigen::VectorXd::Zero(p.unknowns()),
              weight_,
              lambda_ * scale_,
              options_.min_ratio - 1,
              options_.max_ratio - 1};
  if (options_.absolute) {  // the best homogeneous start: v scales as 1 / sigma
    const double c = reference_.dot(f.target) / reference_.squaredNorm();
    if (!(c > 0))
      throw InputError("frame", "",
                       "does not look like an absolute frame (negative fit to the model)");
    f.prior.setConstant(1.0 / c - 1.0);
    f.prior = f.project(f.prior);
  }
  Report r;
  State s = f.evaluate(f.prior);
  linearise(p, s);
  r.residual.push_back((s.v - f.target).norm());
  r.objective.push_back(s.phi);
  r.message = message("%.0f iterations without meeting the tolerances", options_.max_iterations);
  for (int it = 0; it < options_.max_iterations; ++it, ++r.iterations) {
    const Eigen::VectorXd g = f.gradient(s);
    const auto step = f.direction(s, g);
    if (!step) {
      r.termination = Termination::no_descent;
      r.message = "the step's system is not positive definite (a non-finite Jacobian)";
      break;
    }
    const Eigen::VectorXd& delta = *step;
    // The Gauss-Newton model's own prediction of the decrease: -g^T delta (Phi = 2x the model).
    const double predicted = -g.dot(delta) / s.phi;
    if (!(predicted >= options_.tolerance)) {
      r.termination = predicted >= 0 || std::isnan(predicted) ? Termination::converged
                                                              : Termination::no_descent;
      r.message = message("the model predicts a relative decrease of %.3g (tolerance %.3g)",
                          predicted, options_.tolerance);
      break;
    }
    auto trial = detail::armijo_backtracking(
        s.phi, [&](double t) { return f.evaluate(f.project(s.x + t * delta)); },
        [&](const State& next) { return 2 * g.dot(next.x - s.x); });
    if (!trial) {
      r.termination = Termination::no_descent;
      r.message = message("no step along the direction lowered Phi = %.4g enough", s.phi);
      break;
    }
    const double decrease = (s.phi - trial->phi) / s.phi;
    r.residual.push_back((trial->v - f.target).norm());
    r.objective.push_back(trial->phi);
    if (decrease < options_.tolerance ||
        r.residual.back() < options_.residual_tolerance * f.target.norm()) {
      ++r.iterations;
      r.termination = Termination::converged;
      r.message = message("relative decrease %.3g, relative residual %.3g", decrease,
                          r.residual.back() / f.target.norm());
      s = std::move(*trial);
      break;
    }
    s = std::move(*trial);
    linearise(p, s);  // only when another step follows
  }
  if (report) *report = r;
  return p.to_image(-s.x);  // on the label scale: -dsigma / sigma_0 (against sigma_0 in both modes)
}

Eigen::VectorXd GaussNewton::reconstruct(const Eigen::VectorXd& frame) const {
  return solve(frame, nullptr);
}

void GaussNewton::fit(const SampleMatrix& frames, const SampleMatrix& labels,
                      const ScoreFn& score) {
  if (options_.choice != Criterion::validation) return;
  const double best = best_by_score(
      options_.candidates, [&](double l) { lambda_ = l; }, frames, labels, score, 20);
  set_lambda(best, "validation");
}

bool GaussNewton::set_regularisation(double relative, const std::string& how) {
  set_lambda(relative, how);
  return true;
}

}  // namespace eitbench
