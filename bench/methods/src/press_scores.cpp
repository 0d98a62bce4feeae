#include "eitbench/bench/methods/press_scores.h"

#include <algorithm>
#include <numeric>

#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

double quantile(const std::vector<double>& sorted, double q) {
  const double at = q * static_cast<double>(sorted.size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(at));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  return sorted[below] + (at - static_cast<double>(below)) * (sorted[above] - sorted[below]);
}

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

PressScores score_presses(const TouchFrames& found,
                          const std::vector<std::vector<PressTouch>>& truth) {
  if (found.size() != truth.size())
    throw InputError("score_presses", "found", "must hold one list a frame of the truth");
  std::vector<double> errors;
  int none = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const PressTouch& press = the_press(truth, i);
    double x = 0, y = 0;  // nothing found: the centre
    if (found[i].empty()) {
      ++none;
    } else {
      const auto strongest =
          std::max_element(found[i].begin(), found[i].end(),
                           [](const Touch& a, const Touch& b) { return a.contrast < b.contrast; });
      x = strongest->x, y = strongest->y;
    }
    errors.push_back(std::hypot(x - press.x, y - press.y));
  }
  return summarize(std::move(errors), none);
}

PressScores centre_floor(const std::vector<std::vector<PressTouch>>& truth) {
  return score_presses(TouchFrames(truth.size()), truth);
}

}  // namespace eitbench
