#pragma once
// Wall-clock figures as reports state them: percentiles of per-call times.
#include <algorithm>
#include <vector>

namespace eitbench {

// The q-quantile (0..1) of `values`, nearest rank; values is taken by copy and sorted.
inline double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1,
                         static_cast<std::size_t>(q * (values.size() - 1) + 0.5))];
}

}  // namespace eitbench
