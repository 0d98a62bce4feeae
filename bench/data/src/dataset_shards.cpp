#include "eitbench/bench/data/dataset_shards.h"

#include <fmt/core.h>

#include <map>
#include <utility>

#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

// A shard as the first pass keeps it: where it is, its place, and what it says of the whole set
// (its attributes and reference, without its rows).
struct ShardEntry {
  std::string path;
  Shard shard;
  long long rows = 0;
  bool circles = false;
  Dataset header;
};

ShardEntry entry_of(const std::string& path, const Dataset& d) {
  ShardEntry e{path, d.shard, d.size(), !d.circles.empty(), d};
  Dataset& h = e.header;
  h.frames.resize(0, d.frames.cols());
  h.differences.resize(0, d.differences.cols());
  h.labels.resize(0, d.labels.cols());
  h.circles.clear(), h.touches.clear(), h.split.clear();
  h.references.resize(0, d.frames.cols());
  h.shard = {};
  return e;
}

// The first field in which two shards' configurations differ, or "" when none does.
std::string differing_field(const ShardEntry& x, const ShardEntry& y) {
  const Dataset &a = x.header, &b = y.header;
  const std::pair<const char*, bool> fields[] = {
      {"shard_count", x.shard.count == y.shard.count},
      {"shard_total", x.shard.total == y.shard.total},
      {"program", a.program == b.program},
      {"preset", a.preset == b.preset},
      {"seed", a.seed == b.seed},
      {"simulation_mesh", a.simulation_mesh == b.simulation_mesh},
      {"simulation_triangles", a.simulation_triangles == b.simulation_triangles},
      {"electrodes", a.electrodes == b.electrodes},
      {"radius", a.radius == b.radius},
      {"background_conductivity", a.background == b.background},
      {"contact_impedance", a.contact_impedance == b.contact_impedance},
      {"current", a.current == b.current},
      {"electrode_coverage", a.electrode_coverage == b.electrode_coverage},
      {"image_size", a.image_size == b.image_size},
      {"augmentation", a.augmentation == b.augmentation},
      {"sensor_mesh", a.sensor_mesh == b.sensor_mesh},
      {"protocol", a.protocol == b.protocol && a.protocol_channels == b.protocol_channels &&
                       a.magnitude == b.magnitude},
      {"reference", a.reference == b.reference},
      {"labels", a.has_labels() == b.has_labels()},
      {"circles", x.circles == y.circles},
  };
  for (const auto& [name, same] : fields)
    if (!same) return name;
  return "";
}

// Every shard 0 .. N-1 once, each starting where the one before ends, together the whole set.
void check_complete(const std::map<int, ShardEntry>& by_index) {
  const Shard& any = by_index.begin()->second.shard;
  std::string missing;
  for (int k = 0; k < any.count; ++k)
    if (!by_index.count(k)) missing += (missing.empty() ? "" : ", ") + std::to_string(k);
  if (!missing.empty())
    throw InputError("merge", "",
                     fmt::format("shard(s) {} of {} missing (each is a file of simulate --shard "
                                 "K/{})",
                                 missing, any.count, any.count));
  long long next = 0;
  for (const auto& [k, e] : by_index) {
    if (e.shard.first != next)
      throw InputError(
          e.path, "shard_first",
          fmt::format("is {}, but shard {} should start at row {}", e.shard.first, k, next));
    next += e.rows;
  }
  if (next != any.total)
    throw InputError(by_index.rbegin()->second.path, "shard_total",
                     fmt::format("is {}, but the shards hold {} rows", any.total, next));
}

}  // namespace

ShardMerge merge_dataset_shards(const std::vector<std::string>& shards, const std::string& out) {
  if (shards.empty()) throw InputError("merge", "", "no shard files given");
  // First pass: every shard's place and configuration, one shard in memory at a time.
  std::map<int, ShardEntry> by_index;
  for (const std::string& path : shards) {
    const Dataset d = read_dataset_or_shard(path);
    if (d.shard.whole())
      throw InputError(path, "", "is a whole data set, not a shard (simulate --shard K/N)");
    ShardEntry e = entry_of(path, d);
    if (!by_index.empty()) {
      const ShardEntry& first = by_index.begin()->second;
      const std::string field = differing_field(first, e);
      if (!field.empty())
        throw InputError(path, field,
                         "differs from " + first.path + "'s: the shards are of different sets");
    }
    if (by_index.count(e.shard.index))
      throw InputError(path, "shard_index",
                       fmt::format("shard {} is given twice (also as {})", e.shard.index,
                                   by_index.at(e.shard.index).path));
    by_index.emplace(e.shard.index, std::move(e));
  }
  check_complete(by_index);

  // Second pass: the rows, in order.
  const ShardEntry& first = by_index.begin()->second;
  DatasetWriter writer(out, first.header, first.header.has_labels(), first.circles);
  for (const auto& [k, e] : by_index) {
    const Dataset d = read_dataset_or_shard(e.path);
    const ShardEntry again = entry_of(e.path, d);  // the file may have changed since the check
    if (again.shard.index != k || again.shard.first != e.shard.first || again.rows != e.rows ||
        !differing_field(first, again).empty())
      throw InputError(e.path, "", "changed while the shards were being merged");
    writer.append(d);
  }
  writer.commit();
  return {first.shard.count, first.shard.total};
}

std::string shard_file_name(const std::string& out, int index, int count) {
  const bool h5 = out.size() > 3 && out.compare(out.size() - 3, 3, ".h5") == 0;
  return fmt::format("{}.shard-{}-of-{}.h5", h5 ? out.substr(0, out.size() - 3) : out, index,
                     count);
}

}  // namespace eitbench
