// What needs no LibTorch of the trainer's public header: the options' check, the budget's
// arithmetic and the history as JSON.
#include <cmath>

#include "eitbench/jacobian/error.h"
#include "eitbench/learned/trainer.h"
#include "training_json.h"

namespace eitbench {

void TrainingOptions::validate() const {
  auto fail = [](const char* field, const std::string& why) {
    throw InputError("TrainingOptions", field, why);
  };
  if (epochs < 0) fail("epochs", "must not be negative");
  if (steps < 0) fail("steps", "must not be negative");
  if (epochs > 0 && steps > 0) fail("steps", "give epochs or steps as the budget, not both");
  if (batch_size < 2) fail("batch_size", "must be at least 2");
  if (!(learning_rate > 0) || !std::isfinite(learning_rate))
    fail("learning_rate", "must be positive and finite");
  schedule.validate();
  if (validate_every < 1) fail("validate_every", "must be at least one sample");
  if (patience < 0) fail("patience", "must not be negative");
  if (!(min_improvement >= 0 && min_improvement < 1)) fail("min_improvement", "must lie in [0, 1)");
  if (resident != "auto" && resident != "on" && resident != "off")
    fail("resident", "must be auto, on or off, got '" + resident + "'");
  if (!(resident_max_gib > 0) || !std::isfinite(resident_max_gib))
    fail("resident_max_gib", "must be positive and finite");
  std::string resolved;
  try {
    resolved = resolve_device(device, "TrainingOptions");
  } catch (const InputError& e) {
    fail("device", e.message());
  }
  if (precision != "auto" && precision != "fp32" && precision != "tf32" && precision != "bf16")
    fail("precision", "must be auto, fp32, tf32 or bf16, got '" + precision + "'");
  if (resolved == "cpu" && (precision == "tf32" || precision == "bf16"))
    fail("precision", precision + " needs a CUDA device; the CPU trains in fp32");
  if (cuda_graphs != "auto" && cuda_graphs != "on" && cuda_graphs != "off")
    fail("cuda_graphs", "must be auto, on or off, got '" + cuda_graphs + "'");
  if (cuda_graphs == "on" && resolved == "cpu")
    fail("cuda_graphs", "CUDA graphs need a CUDA device");
  if (cuda_graphs == "on" && resident == "off")
    fail("cuda_graphs", "CUDA graphs need the resident training set (resident auto or on)");
  if (channels_last != "on" && channels_last != "off")
    fail("channels_last", "must be on or off, got '" + channels_last + "'");
}

long long steps_per_epoch(long long samples, int batch_size) {
  const long long b = batch_size;
  return std::max(1LL, samples / b + (samples % b >= 2 ? 1 : 0));
}

nlohmann::json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nullptr;
}
double number_or_infinity(const nlohmann::json& j) {
  return j.is_null() ? kNoLoss : j.get<double>();
}

std::string history_to_json(const std::vector<TrainingRecord>& history) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& r : history)
    out.push_back({{"round", r.round},
                   {"epoch", r.epoch},
                   {"steps", r.steps},
                   {"samples", r.samples},
                   {"train_loss", finite_or_null(r.train_loss)},
                   {"validation_loss", finite_or_null(r.validation_loss)},
                   {"learning_rate", r.learning_rate},
                   {"seconds", r.seconds},
                   {"samples_per_second", r.samples_per_second}});
  return out.dump();
}

std::vector<TrainingRecord> history_from_json(const std::string& text, const std::string& source) {
  std::vector<TrainingRecord> out;
  try {
    for (const auto& e : nlohmann::json::parse(text)) {
      TrainingRecord r;
      r.epoch = e.at("epoch").get<int>();
      // Histories written before rounds existed had one entry an epoch.
      r.round = e.value("round", r.epoch);
      r.steps = e.at("steps").get<long long>();
      r.samples = e.at("samples").get<long long>();
      r.train_loss = number_or_infinity(e.at("train_loss"));
      r.validation_loss = number_or_infinity(e.at("validation_loss"));
      r.learning_rate = e.value("learning_rate", 0.0);
      r.seconds = e.at("seconds").get<double>();
      r.samples_per_second = e.at("samples_per_second").get<double>();
      out.push_back(r);
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(source, "history", std::string("unreadable: ") + e.what());
  }
  return out;
}

}  // namespace eitbench
