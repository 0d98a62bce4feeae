#pragma once
// Significance tests for comparing runs (eitbench compare and history): is a change real or the
// spread of repeated measurements? Mann-Whitney's U over the repetitions of a microbenchmark (the
// test Google Benchmark's compare.py applies), Wilcoxon's signed ranks over scores paired by test
// frame, and Welch's z for two means known only by their spread and count.
#include <vector>

namespace eitbench {

struct TestResult {
  double statistic = 0;  // U of the first sample; W+ (the positive differences' rank sum)
  double p_value = 1;    // two-sided
  bool exact = false;    // from the exact null distribution, not the normal approximation
};

// Two independent samples. Exact when neither has more than kExactLimit values and no value ties;
// otherwise the normal approximation with the ties' correction and a continuity correction (as
// scipy.stats.mannwhitneyu). p = 1 when either sample is empty or every value is equal.
TestResult mann_whitney_u(const std::vector<double>& a, const std::vector<double>& b);

// Paired differences (new - old per frame); zeros are dropped (Wilcoxon's own treatment). Exact
// for at most kExactLimit non-zero differences without ties in |d|, else the normal approximation
// with the ties' correction. p = 1 when no difference is non-zero.
TestResult wilcoxon_signed_rank(const std::vector<double>& differences);

// Two means from their standard deviations and counts (the results' cc, cc_std and frames), for
// runs that kept no per-frame scores: z = (b - a) / sqrt(sa^2/na + sb^2/nb), two-sided p. 1 when
// the spread is 0 and the means are equal, 0 when only the means differ.
double welch_z_p_value(double mean_a, double sd_a, int n_a, double mean_b, double sd_b, int n_b);

constexpr int kExactLimit = 50;

}  // namespace eitbench
