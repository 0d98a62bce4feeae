#include "eitbench/bench/report/compare.h"

#include <fmt/core.h>

#include <cmath>
#include <map>

#include "eitbench/bench/report/significance.h"

namespace eitbench {
namespace {

// The paired test's p for one score (new - old per frame); NaN when either run lacks the scores
// or they cover other frames.
double paired_p(const std::vector<double>& old_scores, const std::vector<double>& new_scores) {
  if (old_scores.empty() || old_scores.size() != new_scores.size()) return NAN;
  // A frame without a finite score on both sides (the RE of an empty label) is left out.
  std::vector<double> d;
  for (std::size_t k = 0; k < old_scores.size(); ++k)
    if (std::isfinite(new_scores[k] - old_scores[k])) d.push_back(new_scores[k] - old_scores[k]);
  return wilcoxon_signed_rank(d).p_value;
}

std::string p_text(double p) {
  return std::isnan(p) ? "-" : fmt::format("{:.2g}", p);
}

}  // namespace

Comparison compare_results(const RunResults& old_run, const RunResults& new_run,
                           const QualityOptions& o) {
  Comparison c;
  c.table.push_back({"method", "augment", "snr_db", "CC old", "CC new", "p", "RE old", "RE new",
                     "p", "latency old ms", "latency new ms", "verdict"});
  auto key = [](const ResultRow& r) {
    return r.method + "/" + r.augment + "/" + snr_label(r.snr_db);
  };
  std::map<std::string, const ResultRow*> fresh;
  for (const auto& r : new_run.rows) fresh[key(r)] = &r;
  for (const auto& old : old_run.rows) {
    const auto it = fresh.find(key(old));
    if (it == fresh.end()) {
      c.table.push_back({old.method, old.augment, snr_label(old.snr_db),
                         fmt::format("{:.4f}", old.cc), "-", "-", fmt::format("{:.4f}", old.re),
                         "-", "-", fmt::format("{:.3g}", old.latency_median_ms), "-", "MISSING"});
      c.regressions.push_back(key(old) + ": missing from the new run");
      continue;
    }
    const ResultRow& n = *it->second;
    const double p_cc = paired_p(old.frame_cc, n.frame_cc),
                 p_re = paired_p(old.frame_re, n.frame_re);
    // Beyond tolerance, and significant where the frames allow the test (NaN p: no test).
    auto matters = [&](double change, double p) { return change > o.tolerance && !(p >= o.alpha); };
    std::vector<std::string> why;
    if (old.frames > 0 && matters(old.cc - n.cc, p_cc))
      why.push_back(fmt::format("CC {:.4f} -> {:.4f}{}", old.cc, n.cc,
                                std::isnan(p_cc) ? "" : fmt::format(" (p = {:.2g})", p_cc)));
    if (old.frames > 0 && matters(n.re - old.re, p_re))
      why.push_back(fmt::format("RE {:.4f} -> {:.4f}{}", old.re, n.re,
                                std::isnan(p_re) ? "" : fmt::format(" (p = {:.2g})", p_re)));
    // Latencies under 0.1 ms are timer noise more than speed: they need 0.05 ms of change too.
    if (n.latency_median_ms > old.latency_median_ms * (1 + o.latency_tolerance) &&
        n.latency_median_ms - old.latency_median_ms > 0.05)
      why.push_back(
          fmt::format("latency {:.3g} -> {:.3g} ms", old.latency_median_ms, n.latency_median_ms));
    for (const auto& w : why) c.regressions.push_back(key(old) + ": " + w);
    c.table.push_back(
        {old.method, old.augment, snr_label(old.snr_db), fmt::format("{:.4f}", old.cc),
         fmt::format("{:.4f}", n.cc), p_text(p_cc), fmt::format("{:.4f}", old.re),
         fmt::format("{:.4f}", n.re), p_text(p_re), fmt::format("{:.3g}", old.latency_median_ms),
         fmt::format("{:.3g}", n.latency_median_ms), why.empty() ? "ok" : "REGRESSION"});
  }
  return c;
}

}  // namespace eitbench
