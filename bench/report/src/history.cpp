#include "eitbench/bench/report/history.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/report/significance.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

using json = nlohmann::json;

namespace {

json number(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}
double number(const json& j) {
  return j.is_null() ? NAN : j.get<double>();
}

HistoryEntry entry_from_json(const json& x) {
  HistoryEntry e;
  e.commit = x.at("commit").get<std::string>();
  e.date = x.at("date").get<std::string>();
  e.kind = x.at("kind").get<std::string>();
  if (e.kind != "run" && e.kind != "microbench")
    throw std::invalid_argument("kind: '" + e.kind + "' is neither run nor microbench");
  e.source = x.at("source").get<std::string>();
  e.program = x.at("program").get<std::string>();
  e.machine = x.at("machine").get<std::string>();
  for (const auto& r : x.at("rows"))
    e.rows.push_back({r.at("key").get<std::string>(), number(r.at("cc")), number(r.at("cc_std")),
                      number(r.at("re")), number(r.at("re_std")), number(r.at("latency_median_ms")),
                      r.at("frames").get<int>()});
  for (const auto& b : x.at("benchmarks"))
    e.benchmarks.push_back({b.at("name").get<std::string>(),
                            b.at("real_ns").get<std::vector<double>>(),
                            b.at("cpu_ns").get<std::vector<double>>()});
  return e;
}

}  // namespace

HistoryEntry history_entry(const RunResults& run, const std::string& commit,
                           const std::string& date, const std::string& source) {
  HistoryEntry e{commit, date, "run", source, run.program, "", {}, {}};
  if (const auto it = run.machine.find("cpu"); it != run.machine.end()) e.machine = it->second;
  for (const ResultRow& r : run.rows)
    e.rows.push_back({r.method + "/" + r.augment + "/" + snr_label(r.snr_db), r.cc, r.cc_std, r.re,
                      r.re_std, r.latency_median_ms, r.frames});
  return e;
}

HistoryEntry history_entry(const MicrobenchRun& run, const std::string& commit,
                           const std::string& date, const std::string& source) {
  HistoryEntry e{commit, date, "microbench", source, "", "", {}, run.series};
  auto context = [&](const char* key) {
    const auto it = run.context.find(key);
    return it == run.context.end() ? std::string("?") : it->second;
  };
  e.program = context("executable");
  e.machine = context("host_name") + ", " + context("num_cpus") + " CPUs at " +
              context("mhz_per_cpu") + " MHz";
  return e;
}

json to_json(const HistoryEntry& e) {
  json rows = json::array(), benchmarks = json::array();
  for (const HistoryRow& r : e.rows)
    rows.push_back({{"key", r.key},
                    {"cc", number(r.cc)},
                    {"cc_std", number(r.cc_std)},
                    {"re", number(r.re)},
                    {"re_std", number(r.re_std)},
                    {"latency_median_ms", number(r.latency_median_ms)},
                    {"frames", r.frames}});
  for (const MicrobenchSeries& b : e.benchmarks)
    benchmarks.push_back({{"name", b.name}, {"real_ns", b.real_ns}, {"cpu_ns", b.cpu_ns}});
  return {{"commit", e.commit}, {"date", e.date},          {"kind", e.kind},
          {"source", e.source}, {"program", e.program},    {"machine", e.machine},
          {"rows", rows},       {"benchmarks", benchmarks}};
}

std::vector<HistoryEntry> read_history(const std::string& path) {
  std::vector<HistoryEntry> out;
  if (!std::filesystem::exists(path)) return out;
  std::istringstream in(read_file_bytes(path, 1LL << 30));
  int number_of_line = 0;
  for (std::string line; std::getline(in, line);) {
    ++number_of_line;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    try {
      out.push_back(entry_from_json(json::parse(line)));
    } catch (const std::exception& e) {
      throw InputError(path, fmt::format("line {}", number_of_line),
                       std::string("not a history entry: ") + e.what());
    }
  }
  return out;
}

void add_to_history(const std::string& path, const HistoryEntry& entry, bool replace) {
  std::vector<HistoryEntry> history = read_history(path);
  const auto same = std::find_if(history.begin(), history.end(), [&](const HistoryEntry& e) {
    return e.commit == entry.commit && e.kind == entry.kind;
  });
  if (same != history.end() && !replace)
    throw InputError(path, "commit",
                     fmt::format("holds a {} entry for {} already (added {} from {}); --replace "
                                 "to replace it",
                                 entry.kind, entry.commit, same->date, same->source));
  if (same != history.end())
    *same = entry;
  else
    history.push_back(entry);
  write_text_atomically(path, [&](std::ostream& out) {
    for (const HistoryEntry& e : history) out << to_json(e).dump() << '\n';
  });
}

namespace {

// The series of one kind, in order of first appearance, each with a point an entry holding it.
void run_series(const std::vector<HistoryEntry>& history, const QualityOptions& o,
                std::vector<HistorySeries>& out) {
  std::map<std::string, std::size_t> index;
  std::map<std::string, const HistoryRow*> last;
  for (std::size_t k = 0; k < history.size(); ++k) {
    if (history[k].kind != "run") continue;
    for (const HistoryRow& r : history[k].rows) {
      if (!index.count(r.key)) {
        index[r.key] = out.size();
        for (const char* metric : {"cc", "re", "latency_ms"})
          out.push_back({"run", r.key, metric, {}});
      }
      const std::size_t at = index[r.key];
      const HistoryRow* before = last.count(r.key) ? last[r.key] : nullptr;
      auto quality = [&](double mean, double sd, double mean0, double sd0, bool higher_is_better) {
        HistoryPoint p{k, mean, false, NAN};
        if (before && r.frames > 0 && before->frames > 0) {
          p.p_value = welch_z_p_value(mean0, sd0, before->frames, mean, sd, r.frames);
          const double worse = higher_is_better ? mean0 - mean : mean - mean0;
          p.changed = p.p_value < o.alpha && std::abs(worse) > o.tolerance;
        }
        return p;
      };
      out[at].points.push_back(
          quality(r.cc, r.cc_std, before ? before->cc : NAN, before ? before->cc_std : NAN, true));
      out[at + 1].points.push_back(
          quality(r.re, r.re_std, before ? before->re : NAN, before ? before->re_std : NAN, false));
      HistoryPoint latency{k, r.latency_median_ms, false, NAN};
      if (before && before->latency_median_ms > 0) {
        const double ratio = r.latency_median_ms / before->latency_median_ms;
        latency.changed = std::abs(ratio - 1) > o.latency_tolerance &&
                          std::abs(r.latency_median_ms - before->latency_median_ms) > 0.05;
      }
      out[at + 2].points.push_back(latency);
      last[r.key] = &r;
    }
  }
}

void microbench_series(const std::vector<HistoryEntry>& history, const SpeedOptions& o,
                       std::vector<HistorySeries>& out) {
  std::map<std::string, std::size_t> index;
  std::map<std::string, const MicrobenchSeries*> last;
  for (std::size_t k = 0; k < history.size(); ++k) {
    if (history[k].kind != "microbench") continue;
    for (const MicrobenchSeries& b : history[k].benchmarks) {
      if (!index.count(b.name))
        index[b.name] = out.size(), out.push_back({"microbench", b.name, "time", {}});
      const auto& times = o.cpu_time ? b.cpu_ns : b.real_ns;
      HistoryPoint p{k, median(times) / 1e6, false, NAN};
      if (const auto it = last.find(b.name); it != last.end()) {
        const auto& before = o.cpu_time ? it->second->cpu_ns : it->second->real_ns;
        const double m0 = median(before), change = m0 > 0 ? median(times) / m0 - 1 : 0;
        p.p_value = mann_whitney_u(before, times).p_value;
        p.changed =
            std::min(before.size(), times.size()) >= static_cast<std::size_t>(o.min_repetitions) &&
            p.p_value < o.alpha && std::abs(change) > o.min_change;
      }
      out[index[b.name]].points.push_back(p);
      last[b.name] = &b;
    }
  }
}

}  // namespace

std::vector<HistorySeries> history_series(const std::vector<HistoryEntry>& history,
                                          const HistoryOptions& options) {
  std::vector<HistorySeries> out;
  run_series(history, options.quality, out);
  microbench_series(history, options.speed, out);
  return out;
}

LinePlot history_plot(const std::vector<HistoryEntry>& history,
                      const std::vector<HistorySeries>& series, const std::string& kind,
                      const std::string& metric, const std::string& filter) {
  LinePlot plot;
  const bool time = metric == "time" || metric == "latency_ms";
  plot.title = kind == "run" ? fmt::format("{} of each method over commits", metric == "cc" ? "CC"
                                                                             : metric == "re"
                                                                                 ? "RE"
                                                                                 : "Median latency")
                             : "Microbenchmarks over commits (median of the repetitions)";
  plot.x_label = "commit";
  plot.y_label = metric == "cc" ? "CC" : metric == "re" ? "RE" : "time (ms)";
  plot.log_y = time;
  // x: the commits in the order of their first entry (a commit may have a run and microbenchmarks).
  std::vector<std::string> commits;
  std::vector<double> x_of(history.size());
  for (std::size_t k = 0; k < history.size(); ++k) {
    const auto it = std::find(commits.begin(), commits.end(), history[k].commit);
    x_of[k] = static_cast<double>(it - commits.begin());
    if (it == commits.end()) commits.push_back(history[k].commit);
  }
  for (const std::string& c : commits) plot.x_tick_labels.push_back(c.substr(0, 8));
  PlotSeries marks;
  marks.label = "significant change";
  marks.key = "significant change";
  marks.only_points = true;
  for (const HistorySeries& s : series) {
    if (s.kind != kind || s.metric != metric || s.name.find(filter) == std::string::npos) continue;
    PlotSeries line;
    line.label = s.name;
    line.key = s.name.substr(0, s.name.find('/'));  // the method's colour (dnn: its augmentation)
    if (line.key == "dnn") line.key = "dnn (" + s.name.substr(4, s.name.find('/', 4) - 4) + ")";
    line.points = true;
    for (const HistoryPoint& p : s.points) {
      line.x.push_back(x_of[p.entry]), line.y.push_back(p.value);
      if (p.changed) marks.x.push_back(x_of[p.entry]), marks.y.push_back(p.value);
    }
    plot.series.push_back(std::move(line));
  }
  if (!marks.x.empty()) plot.series.push_back(std::move(marks));
  return plot;
}

}  // namespace eitbench
