#include "eitbench/bench/report/significance.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace eitbench {
namespace {

// Ranks 1..n of `values` (ties share their average rank) and sum over the tie groups of t^3 - t.
std::vector<double> average_ranks(const std::vector<double>& values, double* tie_term, bool* ties) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t i, std::size_t j) { return values[i] < values[j]; });
  std::vector<double> ranks(values.size());
  *tie_term = 0, *ties = false;
  for (std::size_t start = 0; start < order.size();) {
    std::size_t end = start + 1;
    while (end < order.size() && values[order[end]] == values[order[start]]) ++end;
    const double t = static_cast<double>(end - start);
    for (std::size_t k = start; k < end; ++k) ranks[order[k]] = 0.5 * (start + 1 + end);
    if (t > 1) *tie_term += t * t * t - t, *ties = true;
    start = end;
  }
  return ranks;
}

// Two-sided p of the normal approximation, with a continuity correction of 1/2.
double normal_p(double statistic, double mean, double variance) {
  if (!(variance > 0)) return 1;
  const double z = std::max(0.0, std::abs(statistic - mean) - 0.5) / std::sqrt(variance);
  return std::min(1.0, std::erfc(z / std::sqrt(2.0)));
}

// Two-sided p from an exact null distribution given as counts of each integer statistic value.
double exact_p(const std::vector<double>& counts, double statistic) {
  const double total = std::accumulate(counts.begin(), counts.end(), 0.0);
  const auto s = static_cast<std::size_t>(std::llround(statistic));
  double below = 0, above = 0;  // P(X <= s), P(X >= s)
  for (std::size_t k = 0; k < counts.size(); ++k) {
    if (k <= s) below += counts[k];
    if (k >= s) above += counts[k];
  }
  return std::min(1.0, 2 * std::min(below, above) / total);
}

// counts[u]: arrangements of n values of one sample among n + m with statistic U = u, by the
// recurrence c(u; n, m) = c(u - m; n - 1, m) + c(u; n, m - 1) (the largest value is the first
// sample's, and is above all m of the other's, or it is the second's).
std::vector<double> mann_whitney_counts(int n, int m) {
  // table[j][u] for the current n and every m' = j <= m.
  std::vector<std::vector<double>> table(m + 1, std::vector<double>(1, 1.0));  // n = 0: U = 0
  for (int i = 1; i <= n; ++i) {
    std::vector<std::vector<double>> next(m + 1);
    next[0] = {1.0};  // m' = 0: U = 0 whatever n
    for (int j = 1; j <= m; ++j) {
      next[j].assign(static_cast<std::size_t>(i * j + 1), 0.0);
      for (std::size_t u = 0; u < next[j].size(); ++u) {
        if (u >= static_cast<std::size_t>(j) && u - j < table[j].size())
          next[j][u] += table[j][u - j];
        if (u < next[j - 1].size()) next[j][u] += next[j - 1][u];
      }
    }
    table = std::move(next);
  }
  return table[m];
}

// counts[w]: sign patterns of ranks 1..n whose positive ranks sum to w (subset sums).
std::vector<double> signed_rank_counts(int n) {
  std::vector<double> counts(static_cast<std::size_t>(n * (n + 1) / 2 + 1), 0.0);
  counts[0] = 1;
  for (int r = 1; r <= n; ++r)
    for (std::size_t w = counts.size() - 1; w >= static_cast<std::size_t>(r); --w)
      counts[w] += counts[w - r];
  return counts;
}

}  // namespace

TestResult mann_whitney_u(const std::vector<double>& a, const std::vector<double>& b) {
  TestResult out;
  if (a.empty() || b.empty()) return out;
  std::vector<double> both = a;
  both.insert(both.end(), b.begin(), b.end());
  double tie_term = 0;
  bool ties = false;
  const std::vector<double> ranks = average_ranks(both, &tie_term, &ties);
  const double n = static_cast<double>(a.size()), m = static_cast<double>(b.size());
  const double rank_sum = std::accumulate(ranks.begin(), ranks.begin() + a.size(), 0.0);
  out.statistic = rank_sum - n * (n + 1) / 2;
  if (!ties && a.size() <= kExactLimit && b.size() <= kExactLimit) {
    out.exact = true;
    out.p_value =
        exact_p(mann_whitney_counts(static_cast<int>(n), static_cast<int>(m)), out.statistic);
    return out;
  }
  const double N = n + m;
  const double variance = n * m / 12 * ((N + 1) - tie_term / (N * (N - 1)));
  out.p_value = normal_p(out.statistic, n * m / 2, variance);
  return out;
}

TestResult wilcoxon_signed_rank(const std::vector<double>& differences) {
  TestResult out;
  std::vector<double> magnitude, sign;
  for (double d : differences)
    if (d != 0) magnitude.push_back(std::abs(d)), sign.push_back(d > 0 ? 1 : -1);
  if (magnitude.empty()) return out;
  double tie_term = 0;
  bool ties = false;
  const std::vector<double> ranks = average_ranks(magnitude, &tie_term, &ties);
  for (std::size_t k = 0; k < ranks.size(); ++k)
    if (sign[k] > 0) out.statistic += ranks[k];
  const double n = static_cast<double>(ranks.size());
  if (!ties && ranks.size() <= kExactLimit) {
    out.exact = true;
    out.p_value = exact_p(signed_rank_counts(static_cast<int>(n)), out.statistic);
    return out;
  }
  const double variance = n * (n + 1) * (2 * n + 1) / 24 - tie_term / 48;
  out.p_value = normal_p(out.statistic, n * (n + 1) / 4, variance);
  return out;
}

double welch_z_p_value(double mean_a, double sd_a, int n_a, double mean_b, double sd_b, int n_b) {
  if (n_a < 1 || n_b < 1) return 1;
  const double se2 = sd_a * sd_a / n_a + sd_b * sd_b / n_b;
  if (!(se2 > 0)) return mean_a == mean_b ? 1 : 0;
  return std::erfc(std::abs(mean_b - mean_a) / std::sqrt(2 * se2));
}

}  // namespace eitbench
