#pragma once
// A benchmark run made in shards (docs/scaling.md). Shard K of N makes its share of the run's
// units of work in <out>/shards/K-of-N/ and, when it has finished, records so there with the run's
// arguments; gather_run_shards checks every shard and brings their stages, models and data into
// <out>, where the whole run, resumed, finds every unit made and joins them.
#include <filesystem>
#include <string>
#include <vector>

namespace eitbench {

// <out>/shards/K-of-N.
std::filesystem::path run_shard_folder(const std::string& out, int index, int count);

// What a finished shard records in its folder (shard.json): which shard, the run's arguments
// (without --shard, --out and --resume), the run's fingerprint and the units it made.
struct RunShardRecord {
  int index = 0, count = 1;
  std::vector<std::string> arguments;
  std::string fingerprint;
  std::vector<std::string> units;
};
void write_run_shard_record(const std::filesystem::path& folder, const RunShardRecord& record);

// Checks the shards of the run in `out`: shards 0..N-1 all there and finished, with one count, one
// set of arguments and one fingerprint; then brings each shard's stage files, model files and
// simulated data into `out` (hard links where it can, else copies). Returns the arguments.
// InputError naming the shard and what is wrong, before anything is brought in.
std::vector<std::string> gather_run_shards(const std::string& out);

}  // namespace eitbench
