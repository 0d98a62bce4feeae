// eitbench merge: joins shards (docs/scaling.md): a simulated set's shard files (simulate --shard
// K/N) into the set one process writes, or a benchmark run's shards (run --shard K/N --out RUN)
// into the run one process makes.
#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <memory>

#include "commands.h"
#include "eitbench/bench/data/dataset_shards.h"
#include "eitbench/bench/run/shards.h"
#include "eitbench/jacobian/error.h"

namespace eitbench::cli {
namespace {

// The run in `folder` made from its shards' stages: the shards' arguments, resumed there, the
// shards gathered under the folder's lock and checked against the run (run --merge-shards).
void merge_run(const std::string& folder) {
  std::vector<std::string> arguments = run_shard_arguments(folder);
  arguments.insert(arguments.begin(), "run");
  arguments.insert(arguments.end(), {"--out", folder, "--resume", "--merge-shards"});
  CLI::App app;
  const auto run = add_run_command(app);
  std::reverse(arguments.begin(), arguments.end());  // CLI11 takes them last first
  try {
    app.parse(arguments);
  } catch (const CLI::ParseError& e) {
    throw InputError(folder, "arguments",
                     std::string("the shards' run arguments do not parse: ") + e.what());
  }
  run();
}

}  // namespace

std::function<void()> add_merge_command(CLI::App& app) {
  struct Args {
    std::vector<std::string> inputs;
    std::string out;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "merge",
      "Join shards into what one process makes: a simulated set's shard files (simulate --shard "
      "K/N) into the set, array for array, or a benchmark run's folder (run --shard K/N --out RUN) "
      "into its results and report; every shard must be there, of one configuration");
  cmd->add_option("inputs", args->inputs,
                  "the shard files, in any order; or the run's folder (RUN)")
      ->required();
  cmd->add_option("--out", args->out, "with shard files: the HDF5 file to write");
  return [args] {
    const bool folder = std::filesystem::is_directory(args->inputs.front());
    if (folder) {
      if (args->inputs.size() != 1 || !args->out.empty())
        throw InputError(args->inputs.front(), "",
                         "is a run's folder: merge it alone, without --out (the run's results "
                         "and report are written there)");
      return merge_run(args->inputs.front());
    }
    if (args->out.empty())
      throw InputError("--out", "", "merging shard files needs --out, the set to write");
    for (const std::string& path : args->inputs)
      if (std::filesystem::is_directory(path))
        throw InputError(path, "", "is a folder: give shard files, or one run folder alone");
    const ShardMerge merged = merge_dataset_shards(args->inputs, args->out);
    fmt::print("wrote {}: {} samples from {} shards\n", args->out, merged.samples, merged.shards);
  };
}

}  // namespace eitbench::cli
