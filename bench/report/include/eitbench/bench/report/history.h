#pragma once
// A history of results over commits (eitbench history), as airspeed velocity and Conbench keep
// one: a JSON-lines file, one entry a line, each a benchmark run's figures (results.json) or a
// microbenchmark run's repetitions (Google Benchmark JSON) at one commit. `add` appends an entry;
// `show` lays each metric out over the commits and marks the changes the significance tests find.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "eitbench/bench/report/compare.h"
#include "eitbench/bench/report/figures.h"
#include "eitbench/bench/report/microbench.h"
#include "eitbench/bench/report/results.h"

namespace eitbench {

struct HistoryRow {  // one row of a run: method/augment/snr and what compare needs of it
  std::string key;
  double cc = NAN, cc_std = NAN, re = NAN, re_std = NAN, latency_median_ms = NAN;
  int frames = 0;
};

struct HistoryEntry {
  std::string commit;            // as given (a SHA, a tag)
  std::string date;              // ISO 8601, UTC, when it was added
  std::string kind;              // "run" or "microbench"
  std::string source;            // the file it came from
  std::string program, machine;  // eitbench's version; the CPU (run) or host (microbench)
  std::vector<HistoryRow> rows;  // kind "run"
  std::vector<MicrobenchSeries> benchmarks;  // kind "microbench", every repetition
};

HistoryEntry history_entry(const RunResults& run, const std::string& commit,
                           const std::string& date, const std::string& source);
HistoryEntry history_entry(const MicrobenchRun& run, const std::string& commit,
                           const std::string& date, const std::string& source);

nlohmann::json to_json(const HistoryEntry& entry);
// Every line of the file; none when it does not exist. InputError naming the file, the line and
// the field on a line that is not an entry.
std::vector<HistoryEntry> read_history(const std::string& path);
// Appends `entry` (the file rewritten whole, atomically). InputError when the history holds an
// entry of the same kind for the same commit already, unless `replace` (then it is replaced).
void add_to_history(const std::string& path, const HistoryEntry& entry, bool replace);

// One metric of one series over the entries of its kind that hold it, in the file's order.
struct HistoryPoint {
  std::size_t entry = 0;  // index into the history
  double value = NAN;
  bool changed = false;  // a significant change from the point before
  double p_value = NAN;  // of that change's test (NaN: none, as for latency)
};
struct HistorySeries {
  std::string kind, name,
      metric;  // "run", "noser/-/inf", "cc"; "microbench", "BM_Forward/1", "time"
  std::vector<HistoryPoint> points;
};

struct HistoryOptions {
  QualityOptions quality;  // runs: CC and RE by Welch's z on the means, latency by tolerance
  SpeedOptions speed;      // microbenchmarks: Mann-Whitney over the repetitions
};
// Runs give cc, re and latency_ms a row; microbenchmarks give time (the median, ms).
std::vector<HistorySeries> history_series(const std::vector<HistoryEntry>& history,
                                          const HistoryOptions& options);

// A figure of one metric: a line a series over the commits (x ticks: the commits' first 8
// characters), a circle at each significant change. Only series whose name contains `filter`.
LinePlot history_plot(const std::vector<HistoryEntry>& history,
                      const std::vector<HistorySeries>& series, const std::string& kind,
                      const std::string& metric, const std::string& filter = "");

}  // namespace eitbench
