// The exact matching of found touches to true ones, by enumeration with pruning.
#include <cmath>
#include <limits>

#include "eitbench/bench/methods/touch_metrics.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

constexpr std::size_t kMaxTruth = 8;  // the data sets hold up to 4 circles a frame

double distance(const Touch& a, const Touch& b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

// Depth-first over the true touches: each takes a free found touch within the gate, or none. The
// best assignment has the most pairs, then the least total distance; a branch that cannot beat it
// is cut.
class Search {
 public:
  Search(const std::vector<Touch>& found, const std::vector<Touch>& truth, double gate)
      : truth_count_(truth.size()), used_(found.size(), false), current_(truth.size(), -1) {
    for (const Touch& t : truth) {
      std::vector<std::pair<int, double>> near;
      for (std::size_t f = 0; f < found.size(); ++f) {
        const double d = distance(t, found[f]);
        if (d <= gate) near.emplace_back(static_cast<int>(f), d);
      }
      candidates_.push_back(std::move(near));
    }
  }

  std::vector<int> run() {
    visit(0, 0, 0.0);
    return best_;  // found index of each true touch, -1: missed
  }

 private:
  bool better(int pairs, double total) const {
    return pairs > best_pairs_ || (pairs == best_pairs_ && total < best_total_);
  }

  void visit(std::size_t k, int pairs, double total) {
    const int reachable = pairs + static_cast<int>(truth_count_ - k);
    if (reachable < best_pairs_ || (reachable == best_pairs_ && total >= best_total_)) return;
    if (k == truth_count_) {
      if (better(pairs, total)) best_ = current_, best_pairs_ = pairs, best_total_ = total;
      return;
    }
    for (const auto& [f, d] : candidates_[k]) {
      if (used_[f]) continue;
      used_[f] = true, current_[k] = f;
      visit(k + 1, pairs + 1, total + d);
      used_[f] = false, current_[k] = -1;
    }
    visit(k + 1, pairs, total);  // this true touch missed
  }

  std::size_t truth_count_;
  std::vector<std::vector<std::pair<int, double>>> candidates_;
  std::vector<bool> used_;
  std::vector<int> current_, best_;
  int best_pairs_ = -1;
  double best_total_ = std::numeric_limits<double>::infinity();
};

}  // namespace

FrameMatch match_touches(const std::vector<Touch>& found, const std::vector<Touch>& truth,
                         double radius, const TouchOptions& options) {
  options.validate();
  if (!(radius > 0 && std::isfinite(radius)))
    throw InputError("match_touches", "radius", "must be positive and finite");
  if (truth.size() > kMaxTruth)
    throw InputError("match_touches", "truth", "at most 8 true touches a frame");
  FrameMatch m;
  m.found = static_cast<int>(found.size()), m.truth = static_cast<int>(truth.size());
  for (const Touch& t : truth) m.truth_signals.push_back(t.signal);
  const std::vector<int> of_truth = Search(found, truth, options.gate * radius).run();
  for (std::size_t t = 0; t < truth.size(); ++t) {
    const int f = of_truth[t];
    if (f < 0) continue;
    m.pairs.emplace_back(static_cast<int>(t), f);
    m.centre_errors.push_back(distance(truth[t], found[f]) / radius);
    m.radius_errors.push_back(std::abs(found[f].r - truth[t].r) / radius);
  }
  return m;
}

}  // namespace eitbench
