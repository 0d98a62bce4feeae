// eitbench history: a JSON-lines history of benchmark and microbenchmark runs over commits
// (`add`), its tables and figures (`show`); the figures mark the significant changes.
#include <fmt/core.h>

#include <ctime>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "eitbench/bench/report/gnuplot.h"
#include "eitbench/bench/report/history.h"
#include "eitbench/jacobian/error.h"
#include "options.h"

namespace eitbench::cli {
namespace {

struct HistoryArgs {
  std::string file, commit, history = "eitbench-history.jsonl", out, snr = "inf", filter;
  bool replace = false;
  HistoryOptions options;
};

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  char text[32];
  std::tm tm{};
  gmtime_r(&now, &tm);
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

void add(const HistoryArgs& a) {
  if (a.commit.empty() || a.commit.find_first_of(" \t\n") != std::string::npos)
    throw InputError("--commit", "", "must be one word (a SHA or a tag), not '" + a.commit + "'");
  const nlohmann::json doc = read_json_file(a.file);
  const HistoryEntry entry =
      is_microbench_json(doc)
          ? history_entry(parse_microbench_json(doc, a.file), a.commit, utc_now(), a.file)
          : history_entry(parse_results_json(doc, a.file), a.commit, utc_now(), a.file);
  add_to_history(a.history, entry, a.replace);
  fmt::print("added {} ({}: {} {}) to {}\n", a.commit, entry.kind,
             entry.kind == "run" ? entry.rows.size() : entry.benchmarks.size(),
             entry.kind == "run" ? "rows" : "benchmarks", a.history);
}

// A table a metric: a row a series, a column a commit; '*' marks a significant change.
void print_metric(const std::vector<HistoryEntry>& history,
                  const std::vector<HistorySeries>& series, const std::string& kind,
                  const std::string& metric, const std::string& filter) {
  std::vector<std::size_t> columns;  // the entries of this kind
  for (std::size_t k = 0; k < history.size(); ++k)
    if (history[k].kind == kind) columns.push_back(k);
  if (columns.empty()) return;
  std::size_t name_width = 6;
  for (const auto& s : series) name_width = std::max(name_width, s.name.size());
  fmt::print("\n{} {}\n{:<{}}", kind, metric, "series", name_width);
  for (std::size_t k : columns) fmt::print("  {:>10}", history[k].commit.substr(0, 8));
  fmt::print("\n");
  for (const auto& s : series) {
    if (s.kind != kind || s.metric != metric || s.name.find(filter) == std::string::npos) continue;
    fmt::print("{:<{}}", s.name, name_width);
    for (std::size_t k : columns) {
      std::string cell = "-";
      for (const auto& p : s.points)
        if (p.entry == k) cell = fmt::format("{:.4g}{}", p.value, p.changed ? "*" : " ");
      fmt::print("  {:>10}", cell);
    }
    fmt::print("\n");
  }
}

void show(const HistoryArgs& a) {
  const std::vector<HistoryEntry> history = read_history(a.history);
  if (history.empty())
    throw InputError(a.history, "", "no history yet: add a run with 'eitbench history add'");
  const std::vector<HistorySeries> series = history_series(history, a.options);
  const std::string run_filter = a.filter.empty() ? "/" + a.snr : a.filter;
  for (const char* metric : {"cc", "re", "latency_ms"})
    print_metric(history, series, "run", metric, run_filter);
  print_metric(history, series, "microbench", "time", a.filter);
  fmt::print(
      "\n* a significant change from the commit before (runs: Welch's z on the means, p < "
      "{:g}, beyond {:g}; latency beyond {:g} %; microbenchmarks: Mann-Whitney, p < {:g}, "
      "beyond {:g} %)\n",
      a.options.quality.alpha, a.options.quality.tolerance,
      100 * a.options.quality.latency_tolerance, a.options.speed.alpha,
      100 * a.options.speed.min_change);
  if (a.out.empty()) return;
  std::filesystem::create_directories(a.out);
  int drawn = 0, written = 0;
  auto figure = [&](const std::string& kind, const std::string& metric, const std::string& name,
                    const std::string& filter) {
    const LinePlot plot = history_plot(history, series, kind, metric, filter);
    if (plot.series.empty()) return;
    ++written;
    drawn += write_plot(plot, (std::filesystem::path(a.out) / name).string());
  };
  figure("run", "cc", "history_cc.png", run_filter);
  figure("run", "re", "history_re.png", run_filter);
  figure("run", "latency_ms", "history_latency.png", run_filter);
  figure("microbench", "time", "history_microbench.png", a.filter);
  fmt::print("wrote {} figure(s) to {} ({} drawn{})\n", written, a.out, drawn,
             drawn < written ? "; without gnuplot only their .dat and .gp" : "");
}

}  // namespace

std::function<void()> add_history_command(CLI::App& app) {
  auto args = std::make_shared<HistoryArgs>();
  auto* cmd = app.add_subcommand(
      "history",
      "A history of runs over commits: add a run's results.json or microbenchmark "
      "JSON, show each metric over the commits with its significant changes");
  cmd->require_subcommand(1);
  auto* add_cmd = cmd->add_subcommand("add", "Append a run to the history (one JSON line)");
  add_cmd->add_option("results", args->file, "results.json of 'run', or microbenchmark JSON")
      ->required()
      ->check(CLI::ExistingFile);
  add_cmd->add_option("--commit", args->commit, "the commit (SHA or tag) the run was made at")
      ->required();
  add_cmd->add_flag("--replace", args->replace,
                    "replace an entry of the same kind for the same commit");
  auto* show_cmd =
      cmd->add_subcommand("show", "Tables of each metric over the commits, and figures (--out)");
  show_cmd->add_option("--out", args->out,
                       "folder for the figures: history_cc, history_re, history_latency, "
                       "history_microbench (.png, .svg, .dat, .gp)");
  show_cmd->add_option("--snr", args->snr, "runs: the rows at this SNR (inf: noise-free)")
      ->capture_default_str();
  show_cmd->add_option("--filter", args->filter,
                       "only series whose name contains this (noser, BM_Forward); replaces --snr");
  show_cmd->add_option("--alpha", args->options.quality.alpha, "significance level")
      ->capture_default_str()
      ->check(CLI::Range(1e-12, 0.5));
  show_cmd
      ->add_option("--tolerance", args->options.quality.tolerance,
                   "runs: smallest change of CC or RE that counts")
      ->capture_default_str()
      ->check(kNonNegative);
  show_cmd
      ->add_option("--min-change", args->options.speed.min_change,
                   "microbenchmarks: smallest relative change that counts")
      ->capture_default_str()
      ->check(kNonNegative);
  for (auto* sub : {add_cmd, show_cmd})
    sub->add_option("--history", args->history, "the history file (JSON lines)")
        ->capture_default_str();
  return [args, add_cmd] {
    args->options.speed.alpha = args->options.quality.alpha;
    if (add_cmd->parsed())
      add(*args);
    else
      show(*args);
  };
}

}  // namespace eitbench::cli
