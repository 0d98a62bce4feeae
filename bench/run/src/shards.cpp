#include "eitbench/bench/run/shards.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace fs = std::filesystem;

namespace {

constexpr const char* kFormat = "eitbench-run-shard-1";
constexpr long long kMaxRecordBytes = 1 << 20;

RunShardRecord read_shard_record(const fs::path& path) {
  const std::string file = path.string();
  try {
    const nlohmann::json j = nlohmann::json::parse(read_file_bytes(file, kMaxRecordBytes));
    if (j.at("format").get<std::string>() != kFormat)
      throw InputError(file, "format", "is not " + std::string(kFormat));
    RunShardRecord r;
    for (const char* key : {"index", "count"})
      if (!j.at(key).is_number_integer()) throw InputError(file, key, "must be a whole number");
    r.index = j.at("index").get<int>(), r.count = j.at("count").get<int>();
    r.arguments = j.at("arguments").get<std::vector<std::string>>();
    r.fingerprint = j.at("fingerprint").get<std::string>();
    for (const auto& u : j.at("units"))
      r.units.push_back({u.at("unit").get<std::string>(), u.at("seconds").get<double>()});
    r.setup_seconds = j.at("setup_seconds").get<double>();
    r.seconds = j.at("seconds").get<double>();
    return r;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, "", std::string("not a shard record: ") + e.what());
  }
}

// The finished shards' records by index; InputError for a missing, unfinished or foreign one.
std::map<int, RunShardRecord> finished_shards(const std::string& out) {
  const fs::path root = fs::path(out) / "shards";
  if (!fs::is_directory(root))
    throw InputError(out, "", "holds no shards (run --shard K/N --out " + out + " makes them)");
  std::map<int, RunShardRecord> shards;
  int count = 0;
  for (const auto& entry : fs::directory_iterator(root)) {
    int k = 0, n = 0;
    char tail = 0;
    if (!entry.is_directory() ||
        std::sscanf(entry.path().filename().c_str(), "%d-of-%d%c", &k, &n, &tail) != 2 ||
        !(n >= 1 && k >= 0 && k < n))
      continue;  // not a shard's folder
    if (count != 0 && n != count)
      throw InputError(entry.path().string(), "",
                       fmt::format("is a shard of {}, another is of {}: shards of two runs with "
                                   "different counts are in {}",
                                   n, count, root.string()));
    count = n;
    const fs::path record = entry.path() / "shard.json";
    if (!fs::exists(record))
      throw InputError(entry.path().string(), "",
                       "has not finished (no shard.json): run it again with --resume");
    RunShardRecord r = read_shard_record(record);
    if (r.index != k || r.count != n)
      throw InputError(record.string(), "index", "does not match its folder's name");
    shards.emplace(k, std::move(r));
  }
  if (shards.empty()) throw InputError(root.string(), "", "holds no finished shard");
  std::string missing;
  for (int k = 0; k < count; ++k)
    if (!shards.count(k)) missing += (missing.empty() ? "" : ", ") + std::to_string(k);
  if (!missing.empty())
    throw InputError(root.string(), "",
                     fmt::format("shard(s) {} of {} missing (run --shard K/{} --out {})", missing,
                                 count, count, out));
  const RunShardRecord& first = shards.begin()->second;
  for (const auto& [k, r] : shards) {
    const std::string where = run_shard_folder(out, k, count).string();
    if (r.arguments != first.arguments)
      throw InputError(where, "arguments", "differ from shard 0's: the shards are of two runs");
    if (r.fingerprint != first.fingerprint)
      throw InputError(where, "fingerprint",
                       "differs from shard 0's (another program or data): the shards are of two "
                       "runs");
  }
  return shards;
}

// `from` into `to` as a hard link, or a copy where links cannot be made; replaces what is there.
void bring(const fs::path& from, const fs::path& to) {
  std::error_code error;
  fs::remove(to, error);
  fs::create_hard_link(from, to, error);
  if (error) fs::copy_file(from, to, fs::copy_options::overwrite_existing);
}

}  // namespace

fs::path run_shard_folder(const std::string& out, int index, int count) {
  return fs::path(out) / "shards" / fmt::format("{}-of-{}", index, count);
}

void write_run_shard_record(const fs::path& folder, const RunShardRecord& r) {
  nlohmann::json units = nlohmann::json::array();
  for (const auto& u : r.units) units.push_back({{"unit", u.name}, {"seconds", u.seconds}});
  const nlohmann::json j = {{"format", kFormat},
                            {"index", r.index},
                            {"count", r.count},
                            {"arguments", r.arguments},
                            {"fingerprint", r.fingerprint},
                            {"units", units},
                            {"setup_seconds", r.setup_seconds},
                            {"seconds", r.seconds}};
  write_text_atomically((folder / "shard.json").string(),
                        [&](std::ostream& out) { out << j.dump(2) << '\n'; });
}

std::vector<RunShardRecord> gather_run_shards(const std::string& out) {
  const std::map<int, RunShardRecord> shards = finished_shards(out);
  const int count = shards.begin()->second.count;
  for (const char* sub : {"stages", "models"}) fs::create_directories(fs::path(out) / sub);
  for (const auto& [k, r] : shards) {
    const fs::path folder = run_shard_folder(out, k, count);
    for (const char* sub : {"stages", "models"})
      if (fs::is_directory(folder / sub))
        for (const auto& entry : fs::directory_iterator(folder / sub))
          if (entry.is_regular_file())
            bring(entry.path(), fs::path(out) / sub / entry.path().filename());
  }
  // Every shard simulated the same set (same preset, seed and program): shard 0's serves.
  const fs::path data = run_shard_folder(out, 0, count) / "data.h5";
  if (fs::exists(data)) bring(data, fs::path(out) / "data.h5");
  std::vector<RunShardRecord> records;
  for (const auto& [k, r] : shards) records.push_back(r);
  return records;
}

std::vector<std::string> run_shard_arguments(const std::string& out) {
  return finished_shards(out).begin()->second.arguments;
}

std::string describe_balance(const std::vector<RunShardRecord>& shards) {
  if (shards.empty()) return "no shards";
  double low = INFINITY, high = 0, sum = 0, setup_low = INFINITY, setup_high = 0;
  for (const RunShardRecord& r : shards) {
    low = std::min(low, r.seconds), high = std::max(high, r.seconds), sum += r.seconds;
    setup_low = std::min(setup_low, r.setup_seconds);
    setup_high = std::max(setup_high, r.setup_seconds);
  }
  const double mean = sum / static_cast<double>(shards.size());
  return fmt::format(
      "{} shards, {:.0f}-{:.0f} s each (slowest / mean {:.2f}); set-up {:.0f}-{:.0f} s of each",
      shards.size(), low, high, mean > 0 ? high / mean : 1.0, setup_low, setup_high);
}

}  // namespace eitbench
