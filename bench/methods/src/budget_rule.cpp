#include "eitbench/bench/methods/budget_rule.h"

#include <cmath>

#include "eitbench/jacobian/error.h"

namespace eitbench {

void BudgetRule::validate() const {
  if (max_doublings < 0 || max_doublings > 20)
    throw InputError("BudgetRule", "max_doublings", "must lie in 0 ... 20");
  if (!(tolerance >= 0 && tolerance < 1))
    throw InputError("BudgetRule", "tolerance", "must lie in [0, 1)");
}

std::string to_string(TrainingEnd end) {
  switch (end) {
    case TrainingEnd::early_stopping:
      return "early stopping";
    case TrainingEnd::floor:
      return "floor";
    case TrainingEnd::budget:
      return "budget";
    case TrainingEnd::rule:
      return "rule";
    case TrainingEnd::cap:
      return "cap";
  }
  return "?";
}

TrainingEnd parse_training_end(const std::string& name) {
  for (TrainingEnd e : {TrainingEnd::early_stopping, TrainingEnd::floor, TrainingEnd::budget,
                        TrainingEnd::rule, TrainingEnd::cap})
    if (to_string(e) == name) return e;
  throw InputError("TrainingEnd", "name",
                   "unknown end '" + name + "' (early stopping, floor, budget, rule, cap)");
}

bool stopped_with_rate_left(const LearningRateSchedule& schedule, long long steps) {
  if (steps >= schedule.decay_steps()) return false;
  const double floor = schedule.rate(schedule.decay_steps());
  const double peak = schedule.rate(schedule.warmup_steps());
  // A share of the cosine's range, not a multiple of the floor: a floor of 0 would make every
  // stop one with rate left, a floor of half the peak none.
  return !(floor < peak) || schedule.rate(steps) - floor >= kRateLeftShare * (peak - floor);
}

bool converged(TrainingEnd end) {
  return end == TrainingEnd::early_stopping || end == TrainingEnd::rule;
}

bool doubling_paid(const BudgetRule& rule, double previous, double latest) {
  if (!std::isfinite(previous) || !std::isfinite(latest)) return false;
  return latest < previous * (1 - rule.tolerance);
}

bool double_again(const BudgetRule& rule, double previous, double latest, int doublings) {
  return doublings < rule.max_doublings && doubling_paid(rule, previous, latest);
}

}  // namespace eitbench
