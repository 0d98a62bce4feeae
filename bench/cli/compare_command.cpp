// eitbench compare: two benchmark runs side by side; a non-zero exit on a regression, for CI.
#include <fmt/core.h>

#include <algorithm>
#include <memory>

#include "commands.h"
#include "eitbench/bench/report/compare.h"
#include "options.h"

namespace eitbench::cli {

std::function<void()> add_compare_command(CLI::App& app) {
  struct Args {
    std::string old_path, new_path;
    double tolerance = 0.01, latency_tolerance = 0.5;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "compare",
      "Compare two runs' results.json: changes in quality and speed; exit 1 on a "
      "regression beyond tolerance");
  cmd->add_option("old", args->old_path, "the reference run's results.json")->required();
  cmd->add_option("new", args->new_path, "the new run's results.json")->required();
  cmd->add_option("--tolerance", args->tolerance,
                  "largest acceptable drop in CC or rise in RE (absolute)")
      ->capture_default_str()
      ->check(kNonNegative);
  cmd->add_option("--latency-tolerance", args->latency_tolerance,
                  "largest acceptable relative rise in median latency (0.5: 50 % slower)")
      ->capture_default_str()
      ->check(kNonNegative);
  return [args] {
    const RunResults a = read_results_json(args->old_path), b = read_results_json(args->new_path);
    const Comparison c = compare_results(a, b, args->tolerance, args->latency_tolerance);
    std::vector<std::size_t> width(c.table.front().size(), 0);
    for (const auto& row : c.table)
      for (std::size_t k = 0; k < row.size(); ++k) width[k] = std::max(width[k], row[k].size());
    for (const auto& row : c.table) {
      std::string line;
      for (std::size_t k = 0; k < row.size(); ++k)
        line += fmt::format("{:<{}}  ", row[k], width[k]);
      fmt::print("{}\n", line);
    }
    if (a.machine != b.machine)
      fmt::print(
          "\nnote: the runs come from different machines ({} / {}): compare speed with care\n",
          a.machine.count("cpu") ? a.machine.at("cpu") : "?",
          b.machine.count("cpu") ? b.machine.at("cpu") : "?");
    if (!c.regressions.empty()) {
      fmt::print("\n{} regression(s) beyond tolerance (CC/RE {:g}, latency {:g}):\n",
                 c.regressions.size(), args->tolerance, args->latency_tolerance);
      for (const auto& r : c.regressions) fmt::print("  {}\n", r);
      throw RegressionFound();
    }
    fmt::print("\nno regression beyond tolerance (CC/RE {:g}, latency {:g})\n", args->tolerance,
               args->latency_tolerance);
  };
}

}  // namespace eitbench::cli
