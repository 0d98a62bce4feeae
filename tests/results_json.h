#pragma once
// A run's results.json without what a second run of the same work may change: timings, the
// machine, the pick (it weighs timings), and where the data lay.
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

namespace eitbench::testing {

inline void drop_timings(nlohmann::json& j) {
  static const std::set<std::string> timing{"machine",
                                            "recommendation",
                                            "latency_median_ms",
                                            "latency_p95_ms",
                                            "setup_s",
                                            "seconds",
                                            "samples_per_second",
                                            "total_seconds",
                                            "gemm_peak",
                                            "data",
                                            "training_samples_per_second",
                                            "device_latency_ms",
                                            "device_frames_per_second",
                                            "fraction_of_gemm_peak"};
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end();)
      if (timing.count(it.key()))
        it = j.erase(it);
      else
        drop_timings(*it++);
  } else if (j.is_array()) {
    for (auto& v : j) drop_timings(v);
  }
}

inline nlohmann::json results_without_timings(const std::string& path) {
  std::ifstream in(path);
  nlohmann::json j = nlohmann::json::parse(in);
  drop_timings(j);
  return j;
}

}  // namespace eitbench::testing
