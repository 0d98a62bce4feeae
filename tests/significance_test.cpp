// The significance tests of compare and history against brute force: every relabelling of two
// samples (Mann-Whitney) and every sign pattern of paired differences (Wilcoxon) enumerated, the
// two-sided p counted; the normal approximation against those exact permutation p values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "eitbench/bench/report/significance.h"

namespace eitbench {
namespace {

// Rank sum statistic U of the first n values of `pooled` (average ranks for ties), by counting
// pairs: U = #{x > y} + 0.5 #{x == y}, an independent definition.
double pair_count_u(const std::vector<double>& x, const std::vector<double>& y) {
  double u = 0;
  for (double a : x)
    for (double b : y) u += a > b ? 1 : (a == b ? 0.5 : 0);
  return u;
}

// Two-sided permutation p: the share of the C(n+m, n) splits of the pooled values whose U lies at
// least as far from its mean as the observed one.
double permutation_p_mann_whitney(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> pooled = a;
  pooled.insert(pooled.end(), b.begin(), b.end());
  const double mean = a.size() * b.size() / 2.0, observed = std::abs(pair_count_u(a, b) - mean);
  std::vector<bool> pick(pooled.size(), false);
  std::fill(pick.begin(), pick.begin() + a.size(), true);
  double extreme = 0, total = 0;
  do {
    std::vector<double> x, y;
    for (std::size_t k = 0; k < pooled.size(); ++k) (pick[k] ? x : y).push_back(pooled[k]);
    total += 1;
    if (std::abs(pair_count_u(x, y) - mean) >= observed - 1e-9) extreme += 1;
  } while (std::prev_permutation(pick.begin(), pick.end()));
  return extreme / total;
}

double permutation_p_signed_rank(const std::vector<double>& d) {
  // W+ through the average ranks of |d| (computed here by counting, not sorting).
  auto rank = [&](double v) {
    double below = 0, equal = 0;
    for (double e : d) below += std::abs(e) < v, equal += std::abs(e) == v;
    return below + (equal + 1) / 2;
  };
  std::vector<double> r;
  for (double e : d) r.push_back(rank(std::abs(e)));
  const double total_rank = std::accumulate(r.begin(), r.end(), 0.0), mean = total_rank / 2;
  double observed = 0;
  for (std::size_t k = 0; k < d.size(); ++k) observed += d[k] > 0 ? r[k] : 0;
  double extreme = 0;
  const unsigned patterns = 1u << d.size();
  for (unsigned s = 0; s < patterns; ++s) {
    double w = 0;
    for (std::size_t k = 0; k < d.size(); ++k) w += (s >> k & 1u) ? r[k] : 0;
    if (std::abs(w - mean) >= std::abs(observed - mean) - 1e-9) extreme += 1;
  }
  return extreme / patterns;
}

std::vector<double> draw(std::mt19937& rng, int n, double shift, bool round) {
  std::normal_distribution<double> normal(shift, 1);
  std::vector<double> v;
  for (int k = 0; k < n; ++k) v.push_back(round ? std::round(2 * normal(rng)) : normal(rng));
  return v;
}

TEST(Significance, MannWhitneyExactEqualsEnumeration) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const auto a = draw(rng, 3 + trial % 5, 0.8 * (trial % 3), false), b = draw(rng, 6, 0, false);
    const TestResult t = mann_whitney_u(a, b);
    ASSERT_TRUE(t.exact);
    EXPECT_DOUBLE_EQ(t.statistic, pair_count_u(a, b));
    EXPECT_NEAR(t.p_value, permutation_p_mann_whitney(a, b), 1e-12) << "trial " << trial;
  }
}

// Nine repetitions each, wholly separated: the smallest p two samples of nine can give, 2 / C(18,
// 9).
TEST(Significance, MannWhitneyOfSeparatedSamples) {
  std::vector<double> a(9), b(9);
  std::iota(a.begin(), a.end(), 1.0), std::iota(b.begin(), b.end(), 100.0);
  EXPECT_NEAR(mann_whitney_u(a, b).p_value, 2.0 / 48620, 1e-15);
  EXPECT_DOUBLE_EQ(mann_whitney_u(a, a).p_value, 1.0);  // ties everywhere: the approximation
  EXPECT_DOUBLE_EQ(mann_whitney_u({}, b).p_value, 1.0);
}

// With ties (rounded values) the approximation stands in for the exact conditional test; against
// the enumerated permutation p on samples of eight: within 0.01 where p < 0.1, the tail that
// decides (0.004 at most measured), and 0.06 above (0.047 measured, at p = 0.87).
TEST(Significance, MannWhitneyApproximationWithTies) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 12; ++trial) {
    const auto a = draw(rng, 8, 0.6 * (trial % 3), true), b = draw(rng, 8, 0, true);
    const TestResult t = mann_whitney_u(a, b);
    EXPECT_FALSE(t.exact);
    const double exact = permutation_p_mann_whitney(a, b);
    EXPECT_NEAR(t.p_value, exact, exact < 0.1 ? 0.01 : 0.06) << "trial " << trial;
  }
}

// Past the exact limit, the approximation against the exact distribution at the limit's edge:
// samples of 50 (exact) and the same samples with one value more each (approximate).
TEST(Significance, MannWhitneyApproximationMeetsTheExactTail) {
  std::mt19937 rng(3);
  for (double shift : {0.0, 0.3, 0.6}) {
    auto a = draw(rng, kExactLimit, shift, false), b = draw(rng, kExactLimit, 0, false);
    const double exact = mann_whitney_u(a, b).p_value;
    a.push_back(shift), b.push_back(0.0);
    const TestResult approx = mann_whitney_u(a, b);
    EXPECT_FALSE(approx.exact);
    EXPECT_NEAR(approx.p_value, exact, 0.05 + 0.2 * exact) << "shift " << shift;
  }
}

TEST(Significance, WilcoxonExactEqualsEnumeration) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    const auto d = draw(rng, 4 + trial % 9, 0.5 * (trial % 3), false);
    const TestResult t = wilcoxon_signed_rank(d);
    ASSERT_TRUE(t.exact);
    EXPECT_NEAR(t.p_value, permutation_p_signed_rank(d), 1e-12) << "trial " << trial;
  }
}

// The same for 14 paired differences with ties and zeros (at most 0.0025 and 0.021 measured).
TEST(Significance, WilcoxonApproximationWithTiesAndZeros) {
  std::mt19937 rng(9);
  for (int trial = 0; trial < 12; ++trial) {
    auto d = draw(rng, 14, 0.4 * (trial % 3), true);  // ties and zeros among 14
    std::vector<double> nonzero;
    for (double e : d)
      if (e != 0) nonzero.push_back(e);
    const TestResult t = wilcoxon_signed_rank(d);
    const double exact = permutation_p_signed_rank(nonzero);
    EXPECT_NEAR(t.p_value, exact, exact < 0.1 ? 0.01 : 0.06) << "trial " << trial;
  }
  EXPECT_DOUBLE_EQ(wilcoxon_signed_rank(std::vector<double>(229, 0.0)).p_value, 1.0);
}

// Welch's z against the normal tail: a difference of 1.96 standard errors has p = 0.05.
TEST(Significance, WelchZ) {
  const double se = std::sqrt(0.1 * 0.1 / 100 + 0.2 * 0.2 / 400);
  EXPECT_NEAR(welch_z_p_value(0.5, 0.1, 100, 0.5 + 1.959964 * se, 0.2, 400), 0.05, 1e-6);
  EXPECT_DOUBLE_EQ(welch_z_p_value(0.5, 0, 10, 0.5, 0, 10), 1.0);
  EXPECT_DOUBLE_EQ(welch_z_p_value(0.5, 0, 10, 0.6, 0, 10), 0.0);
}

}  // namespace
}  // namespace eitbench
