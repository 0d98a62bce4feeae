#include "eitbench/bench/ktc/ktc_method.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "eitbench/bench/methods/registry.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

namespace {
bool fine(double v) {
  return v >= 0 && std::isfinite(v);
}
}  // namespace

bool KtcNoise::valid() const {
  return fine(relative) && fine(floor) && !(relative == 0 && floor == 0);
}

void KtcNoise::validate() const {
  if (!fine(relative)) throw InputError("KtcNoise", "relative", "must be zero or more, finite");
  if (!fine(floor)) throw InputError("KtcNoise", "floor", "must be zero or more, finite");
  if (relative == 0 && floor == 0)
    throw InputError("KtcNoise", "floor", "and relative cannot both be zero");
}

Eigen::VectorXd KtcNoise::of(const Eigen::VectorXd& reference) const {
  validate();
  double largest = 0;
  for (double v : reference)
    if (std::isfinite(v)) largest = std::max(largest, std::abs(v));
  Eigen::VectorXd out(reference.size());
  for (Eigen::Index i = 0; i < out.size(); ++i) {
    const double u = std::isfinite(reference[i]) ? std::abs(reference[i]) : largest;
    out[i] = std::hypot(relative * u, floor * largest);
  }
  if (!(out.minCoeff() > 0))
    throw InputError("KtcNoise", "floor", "gives a value zero noise (the reference is zero there)");
  return out;
}

void check_ktc_grid(int grid_size) {
  if (grid_size < 16 || grid_size > 256)
    throw InputError("KtcSetup", "grid", "must lie in 16 ... 256 pixels a side");
}

KtcSetup make_ktc_setup(KtcTank tank, int grid_size, const KtcNoise& noise,
                        const KtcOrientation& orientation) {
  check_ktc_grid(grid_size);
  KtcSetup s;
  s.grid = PixelGrid(grid_size, tank.options.radius);
  s.problem = std::make_shared<const LinearProblem>(
      make_linear_problem(tank.model, tank.background, s.grid));
  s.noise = noise.of(tank.reference);
  s.orientation = orientation;
  s.tank = std::move(tank);
  return s;
}

const std::vector<std::string>& ktc_method_names() {
  static const std::vector<std::string> names{"tikhonov", "noser", "laplace", "smooth",
                                              "greit",    "tv",    "gn"};
  return names;
}

const std::vector<double>& ktc_candidates(const std::string& method) {
  // The one-step family on its scale (trace(A P A^T)/m), half-decades over four decades (a
  // candidate costs only its reconstructions), NOSER's one decade further: with its noise model
  // tuned, its optimum on all four samples fell on 1, the grid's edge then. GREIT's lambda
  // relative to its training frames; TV's alpha and Gauss-Newton's lambda over the range their
  // optimum fell in on KTC's samples, fewer of them, as each costs a nonlinear solve a frame.
  static const std::map<std::string, std::vector<double>> table{
      {"tikhonov", {1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0}},
      {"noser", {1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0, 3.0, 10.0}},
      {"laplace", {1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0}},
      {"smooth", {1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0}},
      {"greit", {1e-4, 1e-3, 1e-2, 1e-1, 1.0}},
      {"tv", {3e-6, 1e-5, 3e-5, 1e-4, 3e-4}},
      {"gn", {1e-2, 1e-1, 1.0, 10.0}},
  };
  const auto it = table.find(method);
  if (it == table.end()) {
    std::string names;
    for (const auto& n : ktc_method_names()) names += (names.empty() ? "" : ", ") + n;
    throw InputError("--method", "", "'" + method + "' is not a KTC method (" + names + ")");
  }
  return it->second;
}

KtcSetting ktc_default_setting(const std::string& method) {
  ktc_candidates(method);  // a KTC method, or InputError
  using K = SegmentationKind;
  // eitbench run --ktc ../shared/data/ktc2023 (docs/ktc.md#the-benchmark): each method's setting
  // tuned on all four samples, its noise model with it (GREIT's is the run's: it changes nothing).
  static const std::map<std::string, KtcSetting> table{
      {"tikhonov", {0.01, {K::otsu, 0.5, 0.5}, 5e-3}},
      {"noser", {1.0, {K::levels, 0.45, 0.4}, 5e-3}},
      {"laplace", {0.03, {K::levels, 0.35, 0.45}, 5e-3}},
      {"smooth", {0.1, {K::levels, 0.45, 0.35}, 5e-3}},
      {"greit", {0.1, {K::levels, 0.35, 0.45}}},
      {"tv", {1e-4, {K::otsu, 0.5, 0.5}, 5e-3}},
      {"gn", {1.0, {K::levels, 0.2, 0.7}}},
  };
  return table.at(method);
}

std::unique_ptr<MissingValues> make_ktc_method(const KtcSetup& setup, const std::string& method,
                                               double relative) {
  ktc_candidates(method);  // a KTC method, or InputError
  if (!(relative > 0) || !std::isfinite(relative))
    throw InputError("--lambda", "", "must be positive and finite");
  MethodOptions o;
  o.choose = "fixed";
  o.lambda = relative;
  o.relative_lambda = true;
  return std::make_unique<MissingValues>(
      setup.problem, method,
      [method, o](std::shared_ptr<const LinearProblem> p) {
        return make_reconstructor(method, std::move(p), o);
      },
      setup.noise);
}

Eigen::VectorXd ktc_difference(const KtcMeasurement& measurement, const KtcSetup& setup,
                               int level) {
  check_same_patterns(measurement, setup.tank.protocol->patterns());
  return ktc_level_frame(measurement.voltages - setup.tank.reference,
                         setup.tank.protocol->patterns(), level);
}

Eigen::MatrixXd ktc_image(const KtcSetup& setup, const Eigen::VectorXd& image) {
  return to_ktc_grid(image, setup.grid, setup.orientation);
}

}  // namespace eitbench
