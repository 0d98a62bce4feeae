#pragma once
// Google Benchmark's JSON (--benchmark_out=F --benchmark_out_format=json), read for eitbench
// compare and history: each benchmark's repetitions, and a speed comparison of two such files that
// decides each change with Mann-Whitney's U, as Google Benchmark's compare.py does.
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "eitbench/bench/report/compare.h"

namespace eitbench {

struct MicrobenchSeries {
  std::string name;                     // run_name: the benchmark and its arguments
  std::vector<double> real_ns, cpu_ns;  // one value a repetition, in nanoseconds
};
struct MicrobenchRun {
  std::map<std::string, std::string> context;  // host_name, num_cpus, mhz_per_cpu, date, ...
  std::vector<MicrobenchSeries> series;        // in the file's order
};

// The median (the mean of the middle two for an even count; NaN for none).
double median(std::vector<double> values);

// A JSON file whole (at most 1 GiB): InputError naming it when it is missing or not JSON. What
// compare and history add read before they know which kind of file it is.
nlohmann::json read_json_file(const std::string& path);

// True when `doc` has Google Benchmark's shape (a "benchmarks" array and a "context" object).
bool is_microbench_json(const nlohmann::json& doc);
// InputError naming the file and the field (benchmarks[i].time_unit, ...) on anything else.
// Aggregates (mean, median, stddev, cv) and errored runs are skipped: the repetitions are the data.
MicrobenchRun parse_microbench_json(const nlohmann::json& doc, const std::string& source);
MicrobenchRun read_microbench_json(const std::string& path);

struct SpeedOptions {
  double alpha = 0.05;  // a change counts when Mann-Whitney's two-sided p is below this
  // ... and the medians differ by more than this fraction (0.05: 5 %), so that a real but tiny
  // change does not fail CI.
  double min_change = 0.05;
  bool cpu_time = false;    // compare CPU time instead of wall-clock time
  int min_repetitions = 9;  // fewer: reported, never decided (compare.py's advice)
};

// One row a benchmark of the old run: medians, change, p, verdict (SLOWER is a regression, as is
// a benchmark missing from the new run; faster, same, or "too few repetitions" are not).
Comparison compare_microbench(const MicrobenchRun& old_run, const MicrobenchRun& new_run,
                              const SpeedOptions& options);

}  // namespace eitbench
