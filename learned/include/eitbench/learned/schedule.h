#pragma once
// The learning rate over a training run: a linear warm-up from peak / warmup_steps to the peak,
// then a half cosine from the peak down to final_fraction x peak at decay_fraction of the budget,
// then that floor to the budget's end. The warm-up keeps Adam's first steps, taken on unreliable
// second-moment estimates, small; the cosine anneals, so that the last steps refine instead of
// jumping around a minimum. The floor is where a model converges: once validation stops improving
// there, early stopping ends the run before the budget (an upper bound), and the run counts as
// converged. A cosine over the whole budget would keep improving validation a little every round
// up to its last step, so that every run ended by the budget.
#include <string>

namespace eitbench {

enum class ScheduleKind {
  cosine,    // warm-up, then the half cosine
  constant,  // the peak at every step (the paper's plain Adam)
};
ScheduleKind parse_schedule(const std::string& name, const std::string& source = "ScheduleKind");
std::string to_string(ScheduleKind kind);

struct ScheduleOptions {
  ScheduleKind kind = ScheduleKind::cosine;
  // Each in [0, 1], the warm-up no longer than the decay.
  double warmup_fraction = 0.02;  // of the budget's steps, for the linear warm-up
  double decay_fraction = 0.6;    // of the budget's steps, where the cosine reaches the floor
  double final_fraction = 0.01;   // the floor, relative to the peak

  // Throws InputError("ScheduleOptions", field) for a value out of range.
  void validate() const;
};

class LearningRateSchedule {
 public:
  // Throws InputError(source) on a non-positive peak or budget, and options.validate()'s error.
  LearningRateSchedule(double peak, long long total_steps, const ScheduleOptions& options,
                       const std::string& source = "LearningRateSchedule");
  // The rate for optimiser step `step` (0-based; steps past the budget get the last rate).
  double rate(long long step) const;
  long long warmup_steps() const { return warmup_; }
  long long decay_steps() const { return decay_; }  // the first step at the floor

 private:
  double peak_;
  long long total_, warmup_, decay_;
  ScheduleOptions options_;
};

}  // namespace eitbench
