#pragma once
// Internal: the quantiles the touch and press metrics report, linear between order statistics
// (numpy's default), so that both read alike.
#include <algorithm>
#include <cmath>
#include <vector>

namespace eitbench::detail {

// The q-quantile (0..1) of sorted values; NaN when empty.
inline double quantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return NAN;
  const double at = q * static_cast<double>(sorted.size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(at));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  return sorted[below] + (at - static_cast<double>(below)) * (sorted[above] - sorted[below]);
}

}  // namespace eitbench::detail
