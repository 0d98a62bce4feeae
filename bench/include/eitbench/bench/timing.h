#pragma once
// Wall-clock figures as reports state them: per-call times and their percentiles.
#include <algorithm>
#include <chrono>
#include <vector>

namespace eitbench {

// The q-quantile (0..1) of `values`, nearest rank; values is taken by copy and sorted.
inline double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1,
                         static_cast<std::size_t>(q * (values.size() - 1) + 0.5))];
}

// Milliseconds of each of `repeats` calls of f.
template <typename F>
std::vector<double> time_calls_ms(int repeats, F&& f) {
  std::vector<double> ms;
  for (int i = 0; i < repeats; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  return ms;
}

}  // namespace eitbench
