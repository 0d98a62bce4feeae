#include "eitbench/solvers/shape.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <atomic>
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

// The full model's K: the linear fits choose a K, but they misjudge it both ways. On a strong
// touch the linear model's own error (2-10 % of a frame) is explained by an extra circle, a phantom
// a frame on single touches; and beside strong touches a faint one buys the linear fit too little
// to pay its BIC, while the FEM fits the right K to 0.3-0.7 % of a frame. So the full fit starts
// from the linear one's K, grows while the next linear fit, re-fitted on the FEM, lowers the BIC
// of the full misfits, and otherwise drops the weakest circle (intensity times area) while that
// lowers it. On 80 quick test frames this local walk found the K of the smallest BIC over all
// full fits in all but a few, at two or three full fits a frame.
class FullRefinement {
 public:
  FullRefinement(const detail::ShapeModel& model, const Eigen::VectorXd& frame,
                 const detail::FitSettings& full, double floor, double penalty, int max_touches)
      : model_(model),
        frame_(frame),
        full_(full),
        floor_(floor),
        penalty_(penalty),
        max_touches_(max_touches) {}

  detail::FitOutcome run(const std::vector<detail::FitOutcome>& linear, std::size_t K) {
    // The fit at the linear K and the first step up start from the linear fits, so they run side
    // by side (a core each): both are always computed, and so the result is the same on any
    // number of threads.
    detail::FitOutcome best, more;
    const bool can_grow = K + 1 < linear.size();
    tbb::parallel_invoke([&] { best = fit(linear[K].circles); },
                         [&] {
                           if (can_grow) more = fit(linear[K + 1].circles);
                         });
    if (can_grow && better(more, best)) return split(grow(linear, K + 2, std::move(more)));
    return split(prune(std::move(best)));
  }
  int iterations() const { return iterations_; }

 private:
  // Up from `best` (K - 1 circles) while the next linear fit, refitted, is better.
  detail::FitOutcome grow(const std::vector<detail::FitOutcome>& linear, std::size_t K,
                          detail::FitOutcome best) {
    for (; K < linear.size(); ++K) {
      detail::FitOutcome more = fit(linear[K].circles);
      if (!better(more, best)) break;
      best = std::move(more);
    }
    return best;
  }
  // Down from `best`, the weakest circle (intensity times area) first, while the BIC says so.
  detail::FitOutcome prune(detail::FitOutcome best) {
    while (!best.circles.empty()) {
      auto circles = best.circles;
      circles.erase(std::min_element(circles.begin(), circles.end(), [](auto& a, auto& b) {
        return a[3] * a[2] * a[2] < b[3] * b[2] * b[2];
      }));
      detail::FitOutcome fewer = fit(std::move(circles));
      if (score(fewer) > score(best)) break;
      best = std::move(fewer);
    }
    return best;
  }
  // Two neighbouring touches fitted as one circle: the linear fits never seed the second, since
  // the one circle explains most of both. While the FEM leaves more than the BIC's floor
  // unexplained, the largest circle (neighbours merge into it) is tried as two, half its radius
  // apart along three directions, each with 0.9 of half its area, side by side; the best that
  // lowers the BIC without overlap is kept. On the quick test split (noise-free, penalty 2) the
  // count went from 54 to 66 % of frames right at 114 ms a frame (median) instead of 95; trying
  // every circle reached 68 % at 121 ms, and 252 ms at 30 dB, where noise keeps every frame above
  // the floor.
  detail::FitOutcome split(detail::FitOutcome best) {
    constexpr int kDirections = 3;
    while (best.rss > floor_ && static_cast<int>(best.circles.size()) < max_touches_) {
      const auto& c = best.circles;
      const std::size_t largest = static_cast<std::size_t>(
          std::max_element(c.begin(), c.end(), [](auto& a, auto& b) { return a[2] < b[2]; }) -
          c.begin());
      const std::size_t n = kDirections;
      std::vector<detail::FitOutcome> tried(n);
      tbb::parallel_for(std::size_t{0}, n, [&](std::size_t k) {
        tried[k] = fit(split_start(best.circles, largest, static_cast<int>(k), kDirections));
      });
      std::size_t chosen = n;
      for (std::size_t k = 0; k < n; ++k)
        if (better(tried[k], chosen < n ? tried[chosen] : best)) chosen = k;
      if (chosen == n) break;
      best = std::move(tried[chosen]);
    }
    return best;
  }
  std::vector<detail::CircleParameters> split_start(std::vector<detail::CircleParameters> circles,
                                                    std::size_t i, int direction,
                                                    int directions) const {
    const detail::CircleParameters c = circles[i];
    const double angle = M_PI * direction / directions, offset = c[2] / 2;
    const double r = std::clamp(0.9 * c[2] / std::sqrt(2.0), full_.min_radius, full_.max_radius);
    circles.erase(circles.begin() + static_cast<std::ptrdiff_t>(i));
    for (double side : {1.0, -1.0})
      circles.push_back({c[0] + side * offset * std::cos(angle),
                         c[1] + side * offset * std::sin(angle), r, c[3]});
    return circles;
  }
  detail::FitOutcome fit(std::vector<detail::CircleParameters> start) {
    detail::FitOutcome f;
    if (start.empty())
      f.rss = frame_.squaredNorm(), f.converged = true;
    else
      f = detail::fit_shape(model_, frame_, std::move(start), full_);
    iterations_ += f.iterations;  // atomic: the first two fits run side by side
    return f;
  }
  double score(const detail::FitOutcome& f) const {
    return bic(f.rss, floor_, static_cast<int>(frame_.size()), static_cast<int>(f.circles.size()),
               penalty_);
  }
  // Touches do not overlap (two fingers cannot press the same spot), so a step up whose circles
  // overlap is the FEM correcting one touch's profile, not another touch: a small touch that the
  // smoothed indicator misses by 1.5 % of its frame got a second circle inside it.
  bool better(const detail::FitOutcome& more, const detail::FitOutcome& than) const {
    const auto& c = more.circles;
    for (std::size_t i = 0; i < c.size(); ++i)
      for (std::size_t j = i + 1; j < c.size(); ++j)
        if (std::hypot(c[i][0] - c[j][0], c[i][1] - c[j][1]) < c[i][2] + c[j][2]) return false;
    return score(more) < score(than);
  }

  const detail::ShapeModel& model_;
  const Eigen::VectorXd& frame_;
  const detail::FitSettings& full_;
  double floor_, penalty_;
  int max_touches_;
  std::atomic<int> iterations_{0};
};

// Greedy in K, as matching pursuit is: each K starts from the fit with K - 1 circles plus one at
// the strongest peak of the NOSER image of what that fit leaves unexplained, so a larger K never
// starts worse than the smaller one ended. Every K runs (stopping at the first that does not lower
// the BIC lost a tenth of the count accuracy on quick test frames); K = 0, no touch, competes too.
// Entry K is the linear fit with K circles, its intensities mapped back from Born's.
std::vector<detail::FitOutcome> linear_fits(const ShapeReconstructor::Impl& impl,
                                            const LinearProblem& problem,
                                            const ShapeOptions& options,
                                            const Eigen::VectorXd& frame) {
  problem.check_frame_size(frame.size());
  if (!frame.allFinite()) throw InputError("frame", "", "holds a value that is not finite");
  std::vector<detail::FitOutcome> out(1);
  out[0].rss = frame.squaredNorm(), out[0].converged = true;
  detail::FitOutcome current;
  const auto linear = fit_settings(options, problem.grid.radius(), ShapeForward::linear);
  for (int K = 1; K <= options.max_touches; ++K) {
    std::vector<const double*> fitted;
    for (const auto& c : current.circles) fitted.push_back(c.data());
    const Eigen::VectorXd unexplained = frame - impl.model.difference(fitted, false, nullptr);
    const auto seed = detail::image_seeds(impl.noser.reconstruct(unexplained), problem.grid,
                                          options.seed_threshold, 1, 0.5);
    if (seed.empty()) break;
    auto start = current.circles;
    start.push_back(seed[0]);
    current = detail::fit_shape(impl.model, frame, std::move(start), linear);
    out.push_back(current);
    map_intensities(out.back().circles, from_born);
  }
  return out;
}

// The K of the smallest BIC, given each K's misfit.
std::size_t smallest_bic(const std::vector<double>& rss, double floor, int m, double penalty) {
  std::size_t best = 0;
  for (std::size_t K = 1; K < rss.size(); ++K)
    if (bic(rss[K], floor, m, int(K), penalty) < bic(rss[best], floor, m, int(best), penalty))
      best = K;
  return best;
}

}  // namespace

ShapeFit ShapeReconstructor::fit_circles(const Eigen::VectorXd& frame) const {
  const auto fits = linear_fits(*impl_, *problem_, options_, frame);
  std::vector<double> rss;
  int iterations = 0;
  for (const auto& f : fits) rss.push_back(f.rss), iterations += f.iterations;
  const double floor = std::pow(options_.noise_floor, 2) * frame.squaredNorm();
  const int m = static_cast<int>(frame.size());
  const std::size_t K = smallest_bic(rss, floor, m, penalty_);
  detail::FitOutcome best = fits[K];
  if (options_.forward == ShapeForward::full && K > 0) {
    const auto full = fit_settings(options_, problem_->grid.radius(), ShapeForward::full);
    FullRefinement refinement(impl_->model, frame, full, floor, penalty_, options_.max_touches);
    best = refinement.run(fits, K);
    iterations += refinement.iterations();
  }
  return {to_circles(best.circles, problem_->background), best.rss, iterations, best.converged};
}

std::vector<ShapeFit> ShapeReconstructor::fits_by_count(const Eigen::VectorXd& frame) const {
  std::vector<ShapeFit> out;
  for (const auto& f : linear_fits(*impl_, *problem_, options_, frame))
    out.push_back({to_circles(f.circles, problem_->background), f.rss, f.iterations, f.converged});
  return out;
}

}  // namespace eitbench
