#include "eitbench/bench/report/compare.h"

#include <fmt/core.h>

#include <map>

namespace eitbench {

Comparison compare_results(const RunResults& old_run, const RunResults& new_run,
                           double quality_tolerance, double latency_tolerance) {
  Comparison c;
  c.table.push_back({"method", "augment", "snr_db", "CC old", "CC new", "RE old", "RE new",
                     "latency old ms", "latency new ms", "verdict"});
  auto key = [](const ResultRow& r) {
    return r.method + "/" + r.augment + "/" + snr_label(r.snr_db);
  };
  std::map<std::string, const ResultRow*> fresh;
  for (const auto& r : new_run.rows) fresh[key(r)] = &r;
  for (const auto& o : old_run.rows) {
    const auto it = fresh.find(key(o));
    if (it == fresh.end()) {
      c.table.push_back({o.method, o.augment, snr_label(o.snr_db), fmt::format("{:.4f}", o.cc), "-",
                         fmt::format("{:.4f}", o.re), "-",
                         fmt::format("{:.3g}", o.latency_median_ms), "-", "MISSING"});
      c.regressions.push_back(key(o) + ": missing from the new run");
      continue;
    }
    const ResultRow& n = *it->second;
    std::vector<std::string> why;
    if (o.frames > 0 && n.cc < o.cc - quality_tolerance)
      why.push_back(fmt::format("CC {:.4f} -> {:.4f}", o.cc, n.cc));
    if (o.frames > 0 && n.re > o.re + quality_tolerance)
      why.push_back(fmt::format("RE {:.4f} -> {:.4f}", o.re, n.re));
    // Latencies under 0.1 ms are timer noise more than speed: they need 0.05 ms of change too.
    if (n.latency_median_ms > o.latency_median_ms * (1 + latency_tolerance) &&
        n.latency_median_ms - o.latency_median_ms > 0.05)
      why.push_back(
          fmt::format("latency {:.3g} -> {:.3g} ms", o.latency_median_ms, n.latency_median_ms));
    std::string verdict = why.empty() ? "ok" : "REGRESSION";
    for (const auto& w : why) c.regressions.push_back(key(o) + ": " + w);
    c.table.push_back({o.method, o.augment, snr_label(o.snr_db), fmt::format("{:.4f}", o.cc),
                       fmt::format("{:.4f}", n.cc), fmt::format("{:.4f}", o.re),
                       fmt::format("{:.4f}", n.re), fmt::format("{:.3g}", o.latency_median_ms),
                       fmt::format("{:.3g}", n.latency_median_ms), verdict});
  }
  return c;
}

}  // namespace eitbench
