#pragma once
// Joining a simulated set's shards (simulate --shard K/N, docs/scaling.md) into the set one
// process writes.
#include <string>
#include <vector>

namespace eitbench {

struct ShardMerge {
  int shards = 0;
  long long samples = 0;
};

// Joins the shard files of one set, given in any order, into `out`: the arrays of the set one
// process simulates, value for value, and its attributes without the shard's (the file's chunks
// may differ). Every shard 0 .. N-1
// must be there once, each made with the same configuration (every attribute, the reference,
// the program that made it), its rows following the one before. Checks every shard before
// writing anything (InputError naming the file and what differs, or the missing shards); reads
// one shard at a time, so memory holds one shard, not the set.
ShardMerge merge_dataset_shards(const std::vector<std::string>& shards, const std::string& out);

// Where shard `index` of `count` of the set `out` is kept while the shards are made (MPI ranks):
// "set.h5" -> "set.shard-2-of-4.h5".
std::string shard_file_name(const std::string& out, int index, int count);

}  // namespace eitbench
