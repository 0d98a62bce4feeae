#pragma once
// Internal: the finished stages of a run, one JSON file each under <out>/stages/, so that
// --resume skips them. Each file records the provenance of what it holds (provenance.h), and is
// reused only when that matches this run's; otherwise the stage is made again and the log says
// which parts differ. A stage file that cannot be read or decoded is made again too.
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "provenance.h"

namespace eitbench::run {

// The provenance recorded beside a trained model (<model>.provenance.json); empty when the
// record is missing or unreadable.
Provenance model_provenance(const std::string& model_path);

class StageCache {
 public:
  using Say = std::function<void(const std::string&)>;
  // Whether a record made with the provenance `stored`, not the one wanted, holds what the
  // wanted one would make all the same (a rule changed where it decided nothing for this
  // record). Kept, the record is written anew with the wanted provenance.
  using Keep = std::function<bool(const Provenance& stored)>;
  StageCache(std::filesystem::path folder, bool resume, Say say);
  // Decodes the stage `name` through `decode` when the run resumes, the stage finished and its
  // provenance is `wanted`; false otherwise.
  bool find(const std::string& name, const Provenance& wanted,
            const std::function<void(const nlohmann::json&)>& decode,
            const Keep& keep = nullptr) const;
  void save(const std::string& name, const Provenance& provenance,
            const nlohmann::json& value) const;  // atomic

  // A trained model's file and its checkpoint, with a record beside them of what they are
  // trained for (<model>.provenance.json). True when the run resumes and the record matches:
  // the model, if finished, and the checkpoint, if any, are this run's. Otherwise both are
  // removed (saying why) and the record is written anew before training starts, so that nothing
  // made for another configuration is ever picked up.
  bool claim_model(const std::string& label, const std::string& model_path,
                   const Provenance& wanted, const Keep& keep = nullptr) const;

 private:
  std::filesystem::path folder_;
  bool resume_;
  Say say_;
};

}  // namespace eitbench::run
