#pragma once
// Two runs side by side, for regression tracking across versions (eitbench compare).
#include <string>
#include <vector>

#include "eitbench/bench/report/results.h"

namespace eitbench {

// Row-by-row changes between two runs: quality (CC, RE) beyond `quality_tolerance` (absolute) in
// the bad direction, latency beyond `latency_tolerance` (relative: 0.5 = 50 % slower), or a row
// that disappeared, is a regression.
struct Comparison {
  std::vector<std::vector<std::string>> table;  // header first
  std::vector<std::string> regressions;
};
Comparison compare_results(const RunResults& old_run, const RunResults& new_run,
                           double quality_tolerance, double latency_tolerance);

}  // namespace eitbench
