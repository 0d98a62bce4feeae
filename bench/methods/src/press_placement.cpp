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

void check_inputs(const std::vector<Eigen::Vector2d>& at, const std::vector<Eigen::Vector2d>& truth,
                  double radius, const PlacementMapOptions& options) {
  check(options.min_presses >= 2, "min_presses", "must be at least 2 (one is left out)");
  check(at.size() == truth.size(), "truth", "must hold one position a press placed");
  check(static_cast<int>(at.size()) >= options.min_presses, "presses",
        "needs at least " + std::to_string(options.min_presses) + " labelled presses, has " +
            std::to_string(at.size()));
  check(radius > 0 && std::isfinite(radius), "radius", "must be positive and finite");
  check(!options.bandwidths.empty(), "bandwidths", "must not be empty");
  for (double b : options.bandwidths)
    check(b > 0 && std::isfinite(b), "bandwidths", "must be positive and finite");
  for (std::size_t i = 0; i < at.size(); ++i)
    check(at[i].allFinite() && truth[i].allFinite(), "positions",
          "press " + std::to_string(i) + " is not finite");
  check(std::any_of(truth.begin(), truth.end(), [&](const auto& t) { return t != truth[0]; }),
        "presses", "are all recorded at one position: nothing to measure a bias by");
}

}  // namespace

PlacementMap::PlacementMap(const std::vector<Eigen::Vector2d>& at,
                           const std::vector<Eigen::Vector2d>& truth, double radius,
                           const PlacementMapOptions& options) {
  check_inputs(at, truth, radius, options);
  truth_ = truth;
  for (std::size_t i = 0; i < at.size(); ++i) {
    const double found = at[i].norm();
    // A press put at (or truly at) the centre has no direction: it says how far out presses lie,
    // not how they are turned.
    const bool direction = found > 0 && truth[i].norm() > 0;
    const double turn = direction ? std::remainder(std::atan2(truth[i].y(), truth[i].x()) -
                                                       std::atan2(at[i].y(), at[i].x()),
                                                   2 * M_PI)
                                  : 0.0;
    found_radius_.push_back(found), true_radius_.push_back(truth[i].norm());
    turn_.push_back(turn), has_direction_.push_back(direction);
  }
  // Left out with every press at the same recorded position: a spot pressed again would
  // otherwise vouch for the narrowest width.
  loo_error_ = std::numeric_limits<double>::infinity();
  for (double b : options.bandwidths) {
    double sum = 0;
    for (std::size_t i = 0; i < at.size(); ++i)
      sum += (at_width(at[i], b * radius, &truth[i]) - truth[i]).norm();
    const double mean = sum / static_cast<double>(at.size());
    if (mean < loo_error_) loo_error_ = mean, bandwidth_ = b * radius;
  }
  check(bandwidth_ > 0, "positions", "give no finite leave-one-out error at any width");
}

Eigen::Vector2d PlacementMap::at_width(const Eigen::Vector2d& found, double h,
                                       const Eigen::Vector2d* skip) const {
  const double r = found.norm();
  if (!(r > 0)) return found;
  const auto skipped = [&](std::size_t j) { return skip && truth_[j] == *skip; };
  // Weights relative to the nearest labelled radius, so that a press far from all of them still
  // gets the nearest ones' average rather than 0/0.
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < found_radius_.size(); ++j)
    if (!skipped(j)) nearest = std::min(nearest, std::abs(found_radius_[j] - r));
  if (!std::isfinite(nearest)) return found;  // nothing left to measure by
  double w_sum = 0, radius = 0, s = 0, c = 0;
  for (std::size_t j = 0; j < found_radius_.size(); ++j) {
    if (skipped(j)) continue;
    const double d = std::abs(found_radius_[j] - r), d0 = nearest;
    const double w = std::exp(-0.5 * (d - d0) * (d + d0) / (h * h));
    w_sum += w, radius += w * true_radius_[j];
    if (has_direction_[j]) s += w * std::sin(turn_[j]), c += w * std::cos(turn_[j]);
  }
  // No press with a direction nearby: the radius alone is measured, the turn is not.
  const double turn = s == 0 && c == 0 ? 0.0 : std::atan2(s, c);
  const double angle = std::atan2(found.y(), found.x()) + turn;
  return radius / w_sum * Eigen::Vector2d(std::cos(angle), std::sin(angle));
}

Eigen::Vector2d PlacementMap::apply(const Eigen::Vector2d& found) const {
  return at_width(found, bandwidth_, nullptr);
}

std::vector<Eigen::Vector2d> PlacementMap::apply(const std::vector<Eigen::Vector2d>& found) const {
  std::vector<Eigen::Vector2d> out;
  for (const auto& f : found) out.push_back(apply(f));
  return out;
}

}  // namespace eitbench
