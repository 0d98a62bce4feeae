#include "eitbench/solvers/shape.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/pixel_grid.h"
#include "eitbench/solvers/tikhonov.h"
#include "shape_fit.h"
#include "shape_seeds.h"

namespace eitbench {

ShapeForward parse_shape_forward(const std::string& name) {
  if (name == "linear") return ShapeForward::linear;
  if (name == "full") return ShapeForward::full;
  throw InputError("ShapeOptions", "forward",
                   "unknown forward model '" + name + "' (linear, full)");
}

const char* to_string(ShapeForward forward) {
  return forward == ShapeForward::full ? "full" : "linear";
}

void ShapeOptions::validate() const {
  auto fail = [](const char* field, const std::string& why) {
    throw InputError("ShapeOptions", field, why);
  };
  auto finite = [](double v) { return std::isfinite(v); };
  if (max_touches < 1 || max_touches > 4)
    fail("max_touches", "must lie in 1..4, got " + std::to_string(max_touches));
  if (!(min_radius > 0 && min_radius < max_radius && max_radius <= 1))
    fail("min_radius", "need 0 < min_radius < max_radius <= 1 (units of R)");
  if (!(min_intensity > 0 && min_intensity < max_intensity && max_intensity < 1))
    fail("min_intensity", "need 0 < min_intensity < max_intensity < 1");
  if (!(width >= 0) || !finite(width)) fail("width", "must be finite and not negative");
  if (!(robust_scale >= 0) || !finite(robust_scale))
    fail("robust_scale", "must be finite and not negative");
  if (max_iterations < 1) fail("max_iterations", "must be at least 1");
  if (!(seed_threshold > 0 && seed_threshold < 1)) fail("seed_threshold", "must lie in (0, 1)");
  if (!(seed_lambda > 0) || !finite(seed_lambda))
    fail("seed_lambda", "must be positive and finite");
  if (!(penalty > 0) || !finite(penalty)) fail("penalty", "must be positive and finite");
  if (!(noise_floor > 0 && noise_floor < 1)) fail("noise_floor", "must lie in (0, 1)");
  check_fixed_or_validation("ShapeOptions", choice, candidates);
}

struct ShapeReconstructor::Impl {
  detail::ShapeModel model;
  Tikhonov noser;  // the start's one-step image

  Impl(const LinearProblem& p, const std::shared_ptr<const LinearProblem>& shared,
       const ShapeOptions& o)
      : model(p, o.width * p.grid.radius()), noser(shared, noser_options()) {
    noser.set_lambda(o.seed_lambda * noser.scale(), "shape start");
  }
  static TikhonovOptions noser_options() {
    TikhonovOptions t;
    t.prior = Prior::noser;
    t.choice = Criterion::fixed;
    t.lambda = 1;  // replaced at once, relative to the scale
    return t;
  }
};

ShapeReconstructor::ShapeReconstructor(std::shared_ptr<const LinearProblem> problem,
                                       const ShapeOptions& options)
    : problem_(require_problem(std::move(problem), "ShapeReconstructor")),
      options_((options.validate(), options)),
      impl_(std::make_unique<Impl>(*problem_, problem_, options_)),
      penalty_(options.penalty) {}

ShapeReconstructor::~ShapeReconstructor() = default;

std::string ShapeReconstructor::settings() const {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, "K <= %d by BIC, penalty=%.3g (%s), %s model%s",
                options_.max_touches, penalty_, how_.c_str(), to_string(options_.forward),
                options_.robust_scale > 0 ? ", Huber loss" : "");
  return buffer;
}

void ShapeReconstructor::set_penalty(double penalty, const std::string& how) {
  if (!(penalty > 0) || !std::isfinite(penalty))
    throw InputError("ShapeOptions", "penalty", "must be positive and finite");
  penalty_ = penalty, how_ = how;
}

void ShapeReconstructor::fit(const SampleMatrix& frames, const SampleMatrix& labels,
                             const ScoreFn& score) {
  if (options_.choice != Criterion::validation) return;
  const double best = best_by_score(
      options_.candidates, [&](double p) { penalty_ = p; }, frames, labels, score, 20);
  set_penalty(best, "validation");
}

Eigen::VectorXd ShapeReconstructor::draw(const std::vector<Circle>& circles) const {
  return circles_image(problem_->grid, circles, problem_->background);
}

Eigen::VectorXd ShapeReconstructor::reconstruct(const Eigen::VectorXd& frame) const {
  return draw(fit_circles(frame).circles);
}

std::vector<Circle> ShapeReconstructor::touches(const Eigen::VectorXd& frame,
                                                Eigen::VectorXd& image) const {
  std::vector<Circle> circles = fit_circles(frame).circles;
  image = draw(circles);
  return circles;
}

namespace {

// The linear model's intensity is Born's: J0 is the derivative at the background, so it predicts
// a disc's voltage change as (k - 1)|D| with k = sigma/sigma_0 = 1 - c. A disc's own change is
// that of its polarisation, 2 (k - 1)/(k + 1) |D| (Ammari and Kang), so the linear fit of a disc
// of intensity c finds 2c / (2 - c), which runs to 2 as c runs to 1. Bounded at c's own range, the
// linear fit pinned strong touches at the bound, grew their radius to compensate and crawled
// along the box (40-50 Levenberg-Marquardt steps a fit); in Born units it converges in about ten.
double born(double c) {
  return 2 * c / (2 - c);
}
double from_born(double b) {
  return 2 * b / (2 + b);
}
void map_intensities(std::vector<detail::CircleParameters>& circles, double (*map)(double)) {
  for (auto& c : circles) c[3] = map(c[3]);
}

detail::FitSettings fit_settings(const ShapeOptions& o, double R, ShapeForward forward) {
  detail::FitSettings s;
  s.full = forward == ShapeForward::full;
  s.min_radius = o.min_radius * R, s.max_radius = o.max_radius * R;
  s.min_intensity = o.min_intensity, s.max_intensity = o.max_intensity;
  if (!s.full) s.min_intensity = born(o.min_intensity), s.max_intensity = born(o.max_intensity);
  s.robust_scale = o.robust_scale;
  s.max_iterations = o.max_iterations;
  return s;
}

// Circles on the data set's scale (conductivity in S/m) and the fit's [cx, cy, r, c].
std::vector<Circle> to_circles(const std::vector<detail::CircleParameters>& p, double sigma0) {
  std::vector<Circle> out;
  for (const auto& c : p) out.push_back({c[0], c[1], c[2], sigma0 * (1 - c[3])});
  return out;
}
std::vector<detail::CircleParameters> to_parameters(const std::vector<Circle>& circles,
                                                    double sigma0) {
  std::vector<detail::CircleParameters> out;
  for (const Circle& c : circles) out.push_back({c.x, c.y, c.r, 1 - c.conductivity / sigma0});
  return out;
}

// The Bayesian information criterion of a fit with K circles to m values, its penalty weighted;
// misfits below `floor` count as the floor.
double bic(double rss, double floor, int m, int K, double penalty) {
  return m * std::log(std::max({rss, floor, 1e-300}) / m) +
         penalty * detail::kCircleParameters * K * std::log(double(m));
}

}  // namespace

ShapeFit ShapeReconstructor::fit_circles(const Eigen::VectorXd& frame, std::vector<Circle> start,
                                         ShapeForward forward) const {
  problem_->check_frame_size(frame.size());
  if (!frame.allFinite()) throw InputError("frame", "", "holds a value that is not finite");
  const int K = static_cast<int>(start.size());
  if (K < 1 || K > 4)
    throw InputError("ShapeReconstructor", "K", "fits 1 to 4 circles, not " + std::to_string(K));
  auto parameters = to_parameters(start, problem_->background);
  if (forward == ShapeForward::linear) map_intensities(parameters, born);
  auto fit = detail::fit_shape(impl_->model, frame, std::move(parameters),
                               fit_settings(options_, problem_->grid.radius(), forward));
  if (forward == ShapeForward::linear) map_intensities(fit.circles, from_born);
  return {to_circles(fit.circles, problem_->background), fit.rss, fit.iterations, fit.converged};
}

namespace {

// The full model's fit from the linear one's circles, then pruned: the linear model's error on a
// strong touch is explained by extra circles (a phantom a frame on single touches), which the FEM
// does not need. The weakest circle (intensity times area) goes while the BIC of the full fits says
// so.
detail::FitOutcome refine_full(const detail::ShapeModel& model, const Eigen::VectorXd& frame,
                               detail::FitOutcome best, const detail::FitSettings& full,
                               double floor, double penalty, int& iterations) {
  const int m = static_cast<int>(frame.size());
  best = detail::fit_shape(model, frame, best.circles, full);
  iterations += best.iterations;
  while (!best.circles.empty()) {
    const int K = static_cast<int>(best.circles.size());
    auto fewer = best.circles;
    const auto weakest = std::min_element(fewer.begin(), fewer.end(), [](auto& a, auto& b) {
      return a[3] * a[2] * a[2] < b[3] * b[2] * b[2];
    });
    fewer.erase(weakest);
    detail::FitOutcome candidate;
    if (fewer.empty())
      candidate.rss = frame.squaredNorm(), candidate.converged = true;
    else
      candidate = detail::fit_shape(model, frame, std::move(fewer), full);
    iterations += candidate.iterations;
    if (bic(candidate.rss, floor, m, K - 1, penalty) > bic(best.rss, floor, m, K, penalty)) break;
    best = std::move(candidate);
  }
  return best;
}

}  // namespace

// Greedy in K, as matching pursuit is: each K starts from the fit with K - 1 circles plus one at
// the strongest peak of the NOSER image of what that fit leaves unexplained, so a larger K never
// starts worse than the smaller one ended. Every K runs (stopping at the first that does not lower
// the BIC lost a tenth of the count accuracy on quick test frames); K = 0, no touch, competes too.
ShapeFit ShapeReconstructor::fit_circles(const Eigen::VectorXd& frame) const {
  problem_->check_frame_size(frame.size());
  if (!frame.allFinite()) throw InputError("frame", "", "holds a value that is not finite");
  const int m = static_cast<int>(frame.size());
  detail::FitOutcome best, current;
  best.rss = frame.squaredNorm(), best.converged = true;
  const double floor = std::pow(options_.noise_floor, 2) * frame.squaredNorm();
  double best_bic = bic(best.rss, floor, m, 0, penalty_);
  int iterations = 0;
  const auto linear = fit_settings(options_, problem_->grid.radius(), ShapeForward::linear);
  for (int K = 1; K <= options_.max_touches; ++K) {
    std::vector<const double*> fitted;
    for (const auto& c : current.circles) fitted.push_back(c.data());
    const Eigen::VectorXd unexplained = frame - impl_->model.difference(fitted, false, nullptr);
    const auto seed = detail::image_seeds(impl_->noser.reconstruct(unexplained), problem_->grid,
                                          options_.seed_threshold, 1, 0.5);
    if (seed.empty()) break;
    auto start = current.circles;
    start.push_back(seed[0]);
    current = detail::fit_shape(impl_->model, frame, std::move(start), linear);
    iterations += current.iterations;

    const double b = bic(current.rss, floor, m, K, penalty_);
    if (b < best_bic) best_bic = b, best = current;
  }
  map_intensities(best.circles, from_born);  // the linear fits' intensities are Born's
  if (options_.forward == ShapeForward::full && !best.circles.empty())
    best = refine_full(impl_->model, frame, std::move(best),
                       fit_settings(options_, problem_->grid.radius(), ShapeForward::full), floor,
                       penalty_, iterations);
  return {to_circles(best.circles, problem_->background), best.rss, iterations, best.converged};
}

}  // namespace eitbench
