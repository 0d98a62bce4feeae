#pragma once
// The learning rate over a training run: a linear warm-up from peak / warmup_steps to the peak,
// then a half cosine from the peak down to final_fraction x peak at the last step of the budget.
// The warm-up keeps Adam's first steps, taken on unreliable second-moment estimates, small; the
// cosine anneals, so that the last steps refine instead of jumping around a minimum. The budget is
// an upper bound: early stopping usually ends the run in the cosine's tail.
#include <string>

namespace eitbench {

enum class ScheduleKind {
  cosine,    // warm-up, then the half cosine
  constant,  // the peak at every step (the paper's plain Adam)
};
ScheduleKind parse_schedule(const std::string& name, const std::string& source = "--schedule");
std::string to_string(ScheduleKind kind);

struct ScheduleOptions {
  ScheduleKind kind = ScheduleKind::cosine;
  double warmup_fraction = 0.02;  // of the budget's steps, for the linear warm-up
  double final_fraction = 0.01;   // the rate at the end of the budget, relative to the peak
};

class LearningRateSchedule {
 public:
  // Throws InputError(source) on a non-positive peak or budget and on fractions outside [0, 1].
  LearningRateSchedule(double peak, long long total_steps, const ScheduleOptions& options,
                       const std::string& source = "schedule");
  // The rate for optimiser step `step` (0-based; steps past the budget get the last rate).
  double rate(long long step) const;
  long long warmup_steps() const { return warmup_; }

 private:
  double peak_;
  long long total_, warmup_;
  ScheduleOptions options_;
};

}  // namespace eitbench
