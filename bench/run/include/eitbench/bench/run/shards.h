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
// (without --shard, --out and --resume), the run's fingerprint, and how long its set-up (data,
// model), each unit it made and the whole shard took, in seconds.
struct RunShardRecord {
  struct Unit {
    std::string name;
    double seconds = 0;
  };
  int index = 0, count = 1;
  std::vector<std::string> arguments;
  std::string fingerprint;
  std::vector<Unit> units;
  double setup_seconds = 0, seconds = 0;
};
void write_run_shard_record(const std::filesystem::path& folder, const RunShardRecord& record);

// Checks the shards of the run in `out`: shards 0..N-1 all there and finished, with one count, one
// set of arguments and one fingerprint; then brings each shard's stage files, model files and
// simulated data into `out` (hard links where it can, else copies). Returns the shards' records,
// by index. InputError naming the shard and what is wrong, before anything is brought in.
std::vector<RunShardRecord> gather_run_shards(const std::string& out);
// The arguments the finished shards of the run in `out` were made with, after the same checks as
// gather_run_shards, bringing nothing in.
std::vector<std::string> run_shard_arguments(const std::string& out);
// "3 shards, 41-62 s each (slowest / mean 1.21); set-up 6-8 s of each": the shards' balance.
std::string describe_balance(const std::vector<RunShardRecord>& shards);

}  // namespace eitbench
