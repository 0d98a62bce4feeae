#include "eitbench/bench/methods/press_placement.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

void check(bool ok, const std::string& field, const std::string& what) {
  if (!ok) throw InputError("placement map", field, what);
}

}  // namespace

PlacementMap::PlacementMap(const std::vector<Eigen::Vector2d>& at,
                           const std::vector<Eigen::Vector2d>& truth, double radius,
                           const PlacementMapOptions& options) {
  check(at.size() == truth.size(), "truth", "must hold one position a press placed");
  check(static_cast<int>(at.size()) >= options.min_presses, "presses",
        "needs at least " + std::to_string(options.min_presses) + " labelled presses, has " +
            std::to_string(at.size()));
  check(radius > 0 && std::isfinite(radius), "radius", "must be positive and finite");
  check(!options.bandwidths.empty(), "bandwidths", "must not be empty");
  for (double b : options.bandwidths)
    check(b > 0 && std::isfinite(b), "bandwidths", "must be positive and finite");
  for (std::size_t i = 0; i < at.size(); ++i) {
    check(at[i].allFinite() && truth[i].allFinite(), "positions",
          "press " + std::to_string(i) + " is not finite");
    const double found = at[i].norm();
    // A press put at the centre carries no direction; it still says how far out presses lie.
    const double turn = found > 0 && truth[i].norm() > 0
                            ? std::remainder(std::atan2(truth[i].y(), truth[i].x()) -
                                                 std::atan2(at[i].y(), at[i].x()),
                                             2 * M_PI)
                            : 0.0;
    found_radius_.push_back(found), true_radius_.push_back(truth[i].norm()), turn_.push_back(turn);
  }
  loo_error_ = std::numeric_limits<double>::infinity();
  for (double b : options.bandwidths) {
    double sum = 0;
    for (std::size_t i = 0; i < at.size(); ++i)
      sum += (at_width(at[i], b * radius, static_cast<int>(i)) - truth[i]).norm();
    const double mean = sum / static_cast<double>(at.size());
    if (mean < loo_error_) loo_error_ = mean, bandwidth_ = b * radius;
  }
}

Eigen::Vector2d PlacementMap::at_width(const Eigen::Vector2d& found, double h, int skip) const {
  const double r = found.norm();
  if (!(r > 0)) return found;
  // Weights relative to the nearest labelled radius, so that a press far from all of them still
  // gets the nearest ones' average rather than 0/0.
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < found_radius_.size(); ++j)
    if (static_cast<int>(j) != skip) nearest = std::min(nearest, std::abs(found_radius_[j] - r));
  double w_sum = 0, radius = 0, s = 0, c = 0;
  for (std::size_t j = 0; j < found_radius_.size(); ++j) {
    if (static_cast<int>(j) == skip) continue;
    const double d = std::abs(found_radius_[j] - r) / h, d0 = nearest / h;
    const double w = std::exp(-0.5 * (d * d - d0 * d0));
    w_sum += w, radius += w * true_radius_[j];
    s += w * std::sin(turn_[j]), c += w * std::cos(turn_[j]);
  }
  const double angle = std::atan2(found.y(), found.x()) + std::atan2(s, c);
  return radius / w_sum * Eigen::Vector2d(std::cos(angle), std::sin(angle));
}

Eigen::Vector2d PlacementMap::apply(const Eigen::Vector2d& found) const {
  return at_width(found, bandwidth_, -1);
}

std::vector<Eigen::Vector2d> PlacementMap::apply(const std::vector<Eigen::Vector2d>& found) const {
  std::vector<Eigen::Vector2d> out;
  for (const auto& f : found) out.push_back(apply(f));
  return out;
}

}  // namespace eitbench
