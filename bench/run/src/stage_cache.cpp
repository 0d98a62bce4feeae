#include "stage_cache.h"

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/methods/training_run.h"
#include "eitbench/jacobian/error.h"

namespace eitbench::run {
namespace fs = std::filesystem;
namespace {

// The provenance a record holds; empty when the record is missing, unreadable or from before
// records had one.
Provenance read_provenance(const nlohmann::json& record) {
  Provenance p;
  if (record.is_object() && record.contains("provenance") && record["provenance"].is_object())
    for (const auto& [key, value] : record["provenance"].items())
      if (value.is_string()) p[key] = value.get<std::string>();
  return p;
}

nlohmann::json read_stage_record(const fs::path& path) {
  try {
    return nlohmann::json::parse(read_file_bytes(path.string(), 1LL << 30));
  } catch (const nlohmann::json::exception&) {
  } catch (const InputError&) {
  }
  return nlohmann::json();
}

std::string why_again(const Provenance& stored, const Provenance& wanted) {
  return stored.empty() ? "it has no record of what made it"
                        : "it was made with other " + differing_parts(stored, wanted);
}

void write_record(const fs::path& path, const nlohmann::json& record) {
  write_text_atomically(path.string(), [&](std::ostream& o) { o << record.dump() << '\n'; });
}

fs::path model_record(const std::string& model_path) {
  return model_path + ".provenance.json";
}

}  // namespace

Provenance model_provenance(const std::string& model_path) {
  return read_provenance(read_stage_record(model_record(model_path)));
}

StageCache::StageCache(fs::path folder, bool resume, Say say)
    : folder_(std::move(folder)), resume_(resume), say_(std::move(say)) {
  fs::create_directories(folder_);
}

bool StageCache::find(const std::string& name, const Provenance& wanted,
                      const std::function<void(const nlohmann::json&)>& decode,
                      const Keep& keep) const {
  const fs::path p = folder_ / (name + ".json");
  if (!resume_ || !fs::exists(p)) return false;
  nlohmann::json record = read_stage_record(p);
  const Provenance stored = read_provenance(record);
  const bool kept = stored != wanted && !stored.empty() && keep && keep(stored);
  if (stored != wanted && !kept) {
    say_(name + ": made again: " + why_again(stored, wanted));
    return false;
  }
  try {
    decode(record.at("value"));
    if (kept) {
      say_(name + ": kept: made with other " + differing_parts(stored, wanted) +
           ", which decide it alike");
      record["provenance"] = wanted;
      write_record(p, record);
    }
    return true;
  } catch (const nlohmann::json::exception&) {
  } catch (const InputError&) {
  }
  say_(name + ": made again: its record cannot be read");
  return false;
}

void StageCache::save(const std::string& name, const Provenance& provenance,
                      const nlohmann::json& value) const {
  write_record(folder_ / (name + ".json"), {{"provenance", provenance}, {"value", value}});
}

bool StageCache::claim_model(const std::string& label, const std::string& model_path,
                             const Provenance& wanted, const Keep& keep) const {
  const fs::path record = model_record(model_path);
  const bool left = fs::exists(model_path) || fs::exists(checkpoint_path(model_path));
  if (resume_ && fs::exists(record)) {
    const Provenance stored = model_provenance(model_path);
    if (stored == wanted) return true;
    if (!stored.empty() && fs::exists(model_path) && !fs::exists(checkpoint_path(model_path)) &&
        keep && keep(stored)) {
      say_(label + ": kept: trained with other " + differing_parts(stored, wanted) +
           ", which decide it alike");
      write_record(record, {{"provenance", wanted}});
      return true;
    }
    if (left) say_(label + ": trained again: " + why_again(stored, wanted));
  } else if (resume_ && left) {
    say_(label + ": trained again: " + why_again({}, wanted));
  }
  fs::remove(model_path);
  remove_training_files(model_path);  // its checkpoint and stage record: another training's
  write_record(record, {{"provenance", wanted}});
  return false;
}

}  // namespace eitbench::run
