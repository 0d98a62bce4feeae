#include "stage_cache.h"

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/jacobian/error.h"

namespace eitbench::run {
namespace fs = std::filesystem;

StageCache::StageCache(fs::path folder, bool resume) : folder_(std::move(folder)), resume_(resume) {
  fs::create_directories(folder_);
}

bool StageCache::find(const std::string& name,
                      const std::function<void(const nlohmann::json&)>& decode) const {
  const fs::path p = folder_ / (name + ".json");
  if (!resume_ || !fs::exists(p)) return false;
  try {
    decode(nlohmann::json::parse(read_file_bytes(p.string(), 1LL << 30)));
    return true;
  } catch (const nlohmann::json::exception&) {
    return false;
  } catch (const InputError&) {
    return false;  // unreadable or empty: the stage runs again
  }
}

void StageCache::save(const std::string& name, const nlohmann::json& value) const {
  write_text_atomically((folder_ / (name + ".json")).string(),
                        [&](std::ostream& o) { o << value.dump() << '\n'; });
}

}  // namespace eitbench::run
