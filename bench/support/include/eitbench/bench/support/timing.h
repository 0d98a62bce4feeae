#pragma once
// Wall-clock figures as reports state them: percentiles of per-call times, seconds since a start.
#include <algorithm>
#include <chrono>
#include <vector>

namespace eitbench {

// Wall-clock seconds from t0 until now (steady: a clock change does not move it).
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The q-quantile (0..1) of `values`, nearest rank; values is taken by copy and sorted.
inline double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1,
                         static_cast<std::size_t>(q * (values.size() - 1) + 0.5))];
}

}  // namespace eitbench
