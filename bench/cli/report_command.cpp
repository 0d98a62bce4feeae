// eitbench report: re-draws a finished run's report and figures from its stored results, without
// running anything again (after a change to the report, or for a run copied from elsewhere).
#include <fmt/core.h>

#include <filesystem>
#include <memory>
#include <optional>

#include "commands.h"
#include "eitbench/bench/io/folder_lock.h"
#include "eitbench/bench/report/figures.h"
#include "eitbench/bench/report/report.h"
#include "eitbench/bench/report/run_store.h"
#include "eitbench/jacobian/input_file.h"

namespace eitbench::cli {

std::function<void()> add_report_command(CLI::App& app) {
  struct Args {
    std::string folder;
    bool quiet = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "report",
      "Re-draw a benchmark run's report.md, results.csv and figures from its results.json and "
      "reconstructions.npy (the pick made again by this version's rule)");
  cmd->add_option("folder", args->folder, "the run's output folder (eitbench run --out)")
      ->required();
  cmd->add_flag("--quiet", args->quiet, "no summary table");
  return [args] {
    require_input_folder(args->folder);
    // Not while a run (or another report) writes there; a folder that is no run is left as it is.
    std::optional<FolderLock> lock;
    if (std::filesystem::exists(std::filesystem::path(args->folder) / "results.json"))
      lock.emplace(args->folder);
    const RunResults results = draw_run_report(args->folder, args->quiet);
    if (!args->quiet)
      fmt::print("{}\n{}\n\nwrote {}/report.md, results.csv{}\n", summary_table(results),
                 results.recommendation, args->folder,
                 can_draw_figures() ? " and the figures" : " (no figures: this build draws none)");
  };
}

}  // namespace eitbench::cli
