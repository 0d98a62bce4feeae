// eitbench compare: two benchmark runs side by side (results.json), or two microbenchmark runs
// (Google Benchmark JSON); a non-zero exit on a regression, for CI.
#include <fmt/core.h>

#include <algorithm>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "eitbench/bench/report/compare.h"
#include "eitbench/bench/report/microbench.h"
#include "eitbench/jacobian/error.h"
#include "options.h"

namespace eitbench::cli {
namespace {

struct CompareArgs {
  std::string old_path, new_path;
  QualityOptions quality;
  SpeedOptions speed;
};

void print_table(const Comparison& c) {
  std::vector<std::size_t> width(c.table.front().size(), 0);
  for (const auto& row : c.table)
    for (std::size_t k = 0; k < row.size(); ++k) width[k] = std::max(width[k], row[k].size());
  for (const auto& row : c.table) {
    std::string line;
    for (std::size_t k = 0; k < row.size(); ++k) line += fmt::format("{:<{}}  ", row[k], width[k]);
    fmt::print("{}\n", line);
  }
}

void finish(const Comparison& c, const std::string& rule) {
  if (!c.regressions.empty()) {
    fmt::print("\n{} regression(s) ({}):\n", c.regressions.size(), rule);
    for (const auto& r : c.regressions) fmt::print("  {}\n", r);
    throw RegressionFound();
  }
  fmt::print("\nno regression ({})\n", rule);
}

std::string context_value(const MicrobenchRun& run, const char* key) {
  const auto it = run.context.find(key);
  return it == run.context.end() ? "?" : it->second;
}

void compare_speed(const CompareArgs& args, const nlohmann::json& a, const nlohmann::json& b) {
  const MicrobenchRun old_run = parse_microbench_json(a, args.old_path),
                      new_run = parse_microbench_json(b, args.new_path);
  const Comparison c = compare_microbench(old_run, new_run, args.speed);
  print_table(c);
  for (const char* key : {"host_name", "num_cpus", "mhz_per_cpu"})
    if (context_value(old_run, key) != context_value(new_run, key))
      fmt::print("\nnote: the runs come from different machines ({} {} / {}): compare with care\n",
                 key, context_value(old_run, key), context_value(new_run, key));
  finish(c, fmt::format("a change counts at Mann-Whitney p < {:g} and beyond {:g} %",
                        args.speed.alpha, 100 * args.speed.min_change));
}

void compare_runs(const CompareArgs& args, const nlohmann::json& old_doc,
                  const nlohmann::json& new_doc) {
  const RunResults a = parse_results_json(old_doc, args.old_path),
                   b = parse_results_json(new_doc, args.new_path);
  const Comparison c = compare_results(a, b, args.quality);
  print_table(c);
  if (a.machine != b.machine)
    fmt::print("\nnote: the runs come from different machines ({} / {}): compare speed with care\n",
               a.machine.count("cpu") ? a.machine.at("cpu") : "?",
               b.machine.count("cpu") ? b.machine.at("cpu") : "?");
  finish(c,
         fmt::format("CC/RE beyond {:g} and, with per-frame scores, signed-rank p < {:g}; "
                     "latency beyond {:g}",
                     args.quality.tolerance, args.quality.alpha, args.quality.latency_tolerance));
}

}  // namespace

std::function<void()> add_compare_command(CLI::App& app) {
  auto args = std::make_shared<CompareArgs>();
  auto* cmd = app.add_subcommand(
      "compare",
      "Compare two runs: results.json of 'run' (quality and latency), or the Google Benchmark JSON "
      "of the microbenchmarks (speed, Mann-Whitney U over repetitions); exit 1 on a regression");
  cmd->add_option("old", args->old_path, "the reference: results.json, or microbenchmark JSON")
      ->required();
  cmd->add_option("new", args->new_path, "the new run, of the same kind")->required();
  cmd->add_option("--tolerance", args->quality.tolerance,
                  "runs: largest acceptable drop in CC or rise in RE (absolute)")
      ->capture_default_str()
      ->check(kNonNegative);
  cmd->add_option("--latency-tolerance", args->quality.latency_tolerance,
                  "runs: largest acceptable relative rise in median latency (0.5: 50 % slower)")
      ->capture_default_str()
      ->check(kNonNegative);
  cmd->add_option("--alpha", args->quality.alpha,
                  "significance level of both tests (the paired signed-rank test over test "
                  "frames, Mann-Whitney over repetitions)")
      ->capture_default_str()
      ->check(CLI::Range(1e-12, 0.5));
  cmd->add_option("--min-change", args->speed.min_change,
                  "microbenchmarks: smallest relative change of the median that counts (0.05: 5 %)")
      ->capture_default_str()
      ->check(kNonNegative);
  cmd->add_option("--min-repetitions", args->speed.min_repetitions,
                  "microbenchmarks: fewer repetitions than this are reported, not decided")
      ->capture_default_str()
      ->check(CLI::Range(2, 1000000));
  cmd->add_flag("--cpu-time", args->speed.cpu_time,
                "microbenchmarks: compare CPU time, not wall-clock time");
  return [args] {
    args->speed.alpha = args->quality.alpha;
    const nlohmann::json a = read_json_file(args->old_path), b = read_json_file(args->new_path);
    const bool speed_a = is_microbench_json(a), speed_b = is_microbench_json(b);
    if (speed_a != speed_b)
      throw InputError(speed_a ? args->new_path : args->old_path, "",
                       fmt::format("is {} while {} is {}: compare two of a kind",
                                   speed_b ? "microbenchmark JSON" : "not microbenchmark JSON",
                                   speed_a ? args->old_path : args->new_path,
                                   speed_a ? "microbenchmark JSON" : "not"));
    if (speed_a)
      compare_speed(*args, a, b);
    else
      compare_runs(*args, a, b);
  };
}

}  // namespace eitbench::cli
