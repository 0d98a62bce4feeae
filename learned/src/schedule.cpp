#include "eitbench/learned/schedule.h"

#include <algorithm>
#include <cmath>

#include "eitbench/jacobian/error.h"

namespace eitbench {

ScheduleKind parse_schedule(const std::string& name, const std::string& source) {
  if (name == "cosine") return ScheduleKind::cosine;
  if (name == "constant") return ScheduleKind::constant;
  throw InputError(source, "", "unknown schedule '" + name + "' (cosine or constant)");
}

std::string to_string(ScheduleKind kind) {
  return kind == ScheduleKind::cosine ? "cosine" : "constant";
}

void ScheduleOptions::validate() const {
  auto fraction = [](double v, const char* field) {
    if (!(v >= 0 && v <= 1)) throw InputError("ScheduleOptions", field, "must lie in [0, 1]");
  };
  fraction(warmup_fraction, "warmup_fraction");
  fraction(decay_fraction, "decay_fraction");
  fraction(final_fraction, "final_fraction");
  if (warmup_fraction > decay_fraction)
    throw InputError("ScheduleOptions", "warmup_fraction",
                     "the warm-up must end before the decay does");
}

LearningRateSchedule::LearningRateSchedule(double peak, long long total_steps,
                                           const ScheduleOptions& options,
                                           const std::string& source)
    : peak_(peak), total_(total_steps), options_(options) {
  if (!(peak > 0) || !std::isfinite(peak))
    throw InputError(source, "learning_rate", "must be positive and finite");
  if (total_steps < 1) throw InputError(source, "steps", "the budget must be at least one step");
  options.validate();
  auto steps = [&](double f) {
    return std::min(static_cast<long long>(std::llround(f * double(total_))), total_ - 1);
  };
  const bool cosine = options.kind == ScheduleKind::cosine;
  warmup_ = cosine ? steps(options.warmup_fraction) : 0;
  decay_ = cosine ? std::max(warmup_, steps(options.decay_fraction)) : total_;
}

double LearningRateSchedule::rate(long long step) const {
  if (options_.kind == ScheduleKind::constant) return peak_;
  step = std::clamp(step, 0LL, total_ - 1);
  if (step < warmup_) return peak_ * double(step + 1) / double(warmup_ + 1);
  const double floor = options_.final_fraction * peak_;
  if (step >= decay_) return floor;
  const double t = double(step - warmup_) / double(decay_ - warmup_);  // [0, 1) over the cosine
  return floor + (peak_ - floor) * 0.5 * (1 + std::cos(M_PI * t));
}

}  // namespace eitbench
