// eitbench merge: joins the shards of a simulated set (simulate --shard K/N) into the set one
// process writes (docs/scaling.md).
#include <fmt/core.h>

#include <filesystem>
#include <memory>

#include "commands.h"
#include "eitbench/bench/data/dataset_shards.h"
#include "eitbench/jacobian/error.h"

namespace eitbench::cli {

std::function<void()> add_merge_command(CLI::App& app) {
  struct Args {
    std::vector<std::string> shards;
    std::string out;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "merge",
      "Join the shards of a simulated data set (simulate --shard K/N) into the set one process "
      "writes, byte for byte; every shard must be there, of one configuration");
  cmd->add_option("shards", args->shards, "the shard files, in any order")->required();
  cmd->add_option("--out", args->out, "HDF5 file to write")->required();
  return [args] {
    for (const std::string& path : args->shards)
      if (std::filesystem::is_directory(path))
        throw InputError(path, "",
                         "is a folder: merge joins the shard files of `simulate --shard K/N` "
                         "(a benchmark run is not sharded in this version)");
    const ShardMerge merged = merge_dataset_shards(args->shards, args->out);
    fmt::print("wrote {}: {} samples from {} shards\n", args->out, merged.samples, merged.shards);
  };
}

}  // namespace eitbench::cli
