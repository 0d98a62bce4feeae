#pragma once
// Internal: the finished stages of a run, one JSON file each under <out>/stages/, so that
// --resume skips them. A stage file that cannot be read or decoded is run again.
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

namespace eitbench::run {

class StageCache {
 public:
  StageCache(std::filesystem::path folder, bool resume);
  // Decodes the stage `name` through `decode` when the run resumes and the stage finished;
  // false otherwise (also when decode throws a JSON error: an older or damaged file).
  bool find(const std::string& name,
            const std::function<void(const nlohmann::json&)>& decode) const;
  void save(const std::string& name, const nlohmann::json& value) const;  // atomic

 private:
  std::filesystem::path folder_;
  bool resume_;
};

}  // namespace eitbench::run
