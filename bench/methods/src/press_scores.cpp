#include "eitbench/bench/methods/press_scores.h"

#include <algorithm>
#include <numeric>

#include "eitbench/jacobian/error.h"
#include "order_statistics.h"

namespace eitbench {
namespace {

using detail::quantile;

PressScores summarize(std::vector<double> errors, int none_found) {
  PressScores s;
  s.frames = static_cast<int>(errors.size()), s.none_found = none_found;
  if (errors.empty()) return s;
  std::sort(errors.begin(), errors.end());
  s.median = quantile(errors, 0.5), s.p90 = quantile(errors, 0.9);
  s.mean = std::accumulate(errors.begin(), errors.end(), 0.0) / static_cast<double>(errors.size());
  return s;
}

const PressTouch& the_press(const std::vector<std::vector<PressTouch>>& truth, std::size_t i) {
  if (truth[i].size() != 1)
    throw InputError("press set", "touches",
                     "frame " + std::to_string(i) + " has " + std::to_string(truth[i].size()) +
                         " known touches; press scores take one a frame");
  return truth[i][0];
}

}  // namespace

Eigen::Vector2d located_press(const std::vector<Touch>& found, const Eigen::Vector2d& centre) {
  if (found.empty()) return centre;
  const auto strongest =
      std::max_element(found.begin(), found.end(),
                       [](const Touch& a, const Touch& b) { return a.contrast < b.contrast; });
  return {strongest->x, strongest->y};
}

std::vector<Eigen::Vector2d> located_presses(const TouchFrames& found) {
  std::vector<Eigen::Vector2d> at;
  for (const auto& touches : found) at.push_back(located_press(touches, Eigen::Vector2d::Zero()));
  return at;
}

std::vector<Eigen::Vector2d> true_presses(const std::vector<std::vector<PressTouch>>& truth) {
  std::vector<Eigen::Vector2d> at;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const PressTouch& press = the_press(truth, i);
    at.emplace_back(press.x, press.y);
  }
  return at;
}

PressScores score_presses(const TouchFrames& found,
                          const std::vector<std::vector<PressTouch>>& truth) {
  if (found.size() != truth.size())
    throw InputError("score_presses", "found", "must hold one list a frame of the truth");
  std::vector<double> errors;
  int none = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const PressTouch& press = the_press(truth, i);
    none += found[i].empty();
    const Eigen::Vector2d at = located_press(found[i], Eigen::Vector2d::Zero());
    errors.push_back(std::hypot(at.x() - press.x, at.y() - press.y));
  }
  return summarize(std::move(errors), none);
}

namespace {

// The frames of each band of `edges` (see PressBand), checked.
std::vector<std::pair<PressBand, std::vector<std::size_t>>> bands_of(
    const std::vector<std::vector<PressTouch>>& truth, double radius,
    const std::vector<double>& edges) {
  if (!(radius > 0) || !std::isfinite(radius))
    throw InputError("press bands", "radius", "must be positive and finite");
  if (edges.empty() || edges.front() != 0 || !std::is_sorted(edges.begin(), edges.end()) ||
      std::adjacent_find(edges.begin(), edges.end()) != edges.end())
    throw InputError("press bands", "edges", "must rise strictly from 0");
  std::vector<std::pair<PressBand, std::vector<std::size_t>>> bands;
  for (std::size_t b = 0; b < edges.size(); ++b)
    bands.push_back({{edges[b], b + 1 < edges.size() ? edges[b + 1] : INFINITY, {}, {}}, {}});
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const PressTouch& press = the_press(truth, i);
    const double r = std::hypot(press.x, press.y) / radius;
    for (auto& [band, frames] : bands)
      if (r >= band.inner && r < band.outer) frames.push_back(i);
  }
  return bands;
}

// Mean radii and the median turn of the presses `at`, truly at `truth`.
PressPlacement placement_of(const std::vector<Eigen::Vector2d>& at,
                            const std::vector<std::vector<PressTouch>>& truth) {
  PressPlacement p;
  if (at.empty()) return p;
  double true_sum = 0, found_sum = 0;
  std::vector<double> turns;
  for (std::size_t i = 0; i < at.size(); ++i) {
    const PressTouch& press = the_press(truth, i);
    const double r = std::hypot(press.x, press.y), found = at[i].norm();
    true_sum += r, found_sum += found;
    if (r > 0 && found > 0) {
      const double turn = std::atan2(at[i].y(), at[i].x()) - std::atan2(press.y, press.x);
      turns.push_back(std::remainder(turn, 2 * M_PI) * 180 / M_PI);
    }
  }
  const double n = static_cast<double>(at.size());
  p.true_radius = true_sum / n, p.found_radius = found_sum / n;
  if (!turns.empty()) p.turn_degrees = summarize(std::move(turns), 0).median;
  return p;
}

template <typename T>
std::vector<T> pick(const std::vector<T>& all, const std::vector<std::size_t>& which) {
  std::vector<T> out;
  for (std::size_t i : which) out.push_back(all[i]);
  return out;
}

// `score` (score_presses or score_positions) on each band's frames of `located` and `truth`, and
// where the band's presses were put (`at`, one position a frame).
template <typename Located, typename Score>
std::vector<PressBand> by_distance(const std::vector<Located>& located,
                                   const std::vector<Eigen::Vector2d>& at,
                                   const std::vector<std::vector<PressTouch>>& truth, double radius,
                                   const std::vector<double>& edges, Score score) {
  if (located.size() != truth.size())
    throw InputError("press bands", "located", "must hold one entry a frame of the truth");
  std::vector<PressBand> out;
  for (auto& [band, frames] : bands_of(truth, radius, edges)) {
    band.scores = score(pick(located, frames), pick(truth, frames));
    band.placement = placement_of(pick(at, frames), pick(truth, frames));
    out.push_back(band);
  }
  return out;
}

}  // namespace

std::vector<PressBand> score_presses_by_distance(const TouchFrames& found,
                                                 const std::vector<std::vector<PressTouch>>& truth,
                                                 double radius, const std::vector<double>& edges) {
  return by_distance(found, located_presses(found), truth, radius, edges, score_presses);
}

std::vector<PressBand> score_positions_by_distance(
    const std::vector<Eigen::Vector2d>& at, const std::vector<std::vector<PressTouch>>& truth,
    double radius, const std::vector<double>& edges) {
  return by_distance(at, at, truth, radius, edges, score_positions);
}

PressScores score_positions(const std::vector<Eigen::Vector2d>& at,
                            const std::vector<std::vector<PressTouch>>& truth) {
  if (at.size() != truth.size())
    throw InputError("score_positions", "at", "must hold one position a frame of the truth");
  std::vector<double> errors;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const PressTouch& press = the_press(truth, i);
    errors.push_back(std::hypot(at[i].x() - press.x, at[i].y() - press.y));
  }
  return summarize(std::move(errors), 0);
}

PressScores centre_floor(const std::vector<std::vector<PressTouch>>& truth) {
  return score_presses(TouchFrames(truth.size()), truth);
}

std::vector<Touch> press_touches(const Eigen::VectorXd& image, const PixelGrid& grid,
                                 const PressRule& rule) {
  return rule.centroid ? centroid_touch(image, grid, rule.threshold)
                       : find_touches(image, grid, rule.threshold);
}

TouchFrames press_touches(const SampleMatrix& images, const PixelGrid& grid,
                          const PressRule& rule) {
  TouchFrames frames;
  for (Eigen::Index i = 0; i < images.rows(); ++i)
    frames.push_back(press_touches(Eigen::VectorXd(images.row(i).transpose()), grid, rule));
  return frames;
}

PressRule choose_press_rule(const SampleMatrix& images, const PixelGrid& grid,
                            const std::vector<std::vector<PressTouch>>& truth) {
  PressRule chosen;
  double best = INFINITY;
  for (bool centroid : {false, true})
    for (double t : TouchOptions().thresholds) {
      const PressRule rule{centroid, t};
      const double mean = score_presses(press_touches(images, grid, rule), truth).mean;
      if (mean < best) best = mean, chosen = rule;
    }
  return chosen;
}

}  // namespace eitbench
