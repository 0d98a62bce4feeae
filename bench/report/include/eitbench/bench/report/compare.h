#pragma once
// Two runs side by side, for regression tracking across versions (eitbench compare).
#include <string>
#include <vector>

#include "eitbench/bench/report/results.h"

namespace eitbench {

struct Comparison {
  std::vector<std::vector<std::string>> table;  // header first
  std::vector<std::string> regressions;
};

struct QualityOptions {
  double tolerance = 0.01;         // the smallest drop in CC or rise in RE (absolute) that matters
  double latency_tolerance = 0.5;  // the smallest relative rise in median latency (0.5: 50 %)
  // Where both rows kept each test frame's scores, a change must also be significant: Wilcoxon's
  // signed-rank test over the frames, paired, two-sided p below alpha.
  double alpha = 0.05;
};

// Row-by-row changes between two runs. A regression is a row that disappeared, a median latency
// beyond the latency tolerance, or quality beyond the tolerance in the bad direction: with
// per-frame scores on both sides only when the paired test finds it significant, without them on
// the means alone (runs from before the scores were kept).
Comparison compare_results(const RunResults& old_run, const RunResults& new_run,
                           const QualityOptions& options);

}  // namespace eitbench
