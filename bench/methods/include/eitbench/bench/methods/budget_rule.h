#pragma once
// When a learned model's training ends (docs/learned.md#the-budget). A budget tied to the plain
// set's epochs ends an augmented model's training early: its cosine schedule reaches the floor at
// 60 % of the budget, and early stopping then ends a run the learning rate can no longer move.
// The rule: train with the budget. When early stopping ended it with rate left (below), the
// budget sufficed. Otherwise continue from the best model with a fresh schedule, run down to its
// floor, over as many steps again, so that the total doubles, and double again while the
// last doubling lowered the best validation loss by more than a tolerance, at most max_doublings
// times. Both arms of a comparison follow it.
#include <string>

#include "eitbench/learned/schedule.h"

namespace eitbench {

struct BudgetRule {
  // 0: train once, the budget as given (the early stopping inside it ends the training).
  int max_doublings = 0;
  // A doubling is taken again while the last one lowered the best validation loss by more than
  // this share of it; in [0, 1).
  double tolerance = 0.01;

  // InputError("BudgetRule", field) for a value out of range.
  void validate() const;
};

// Whether early stopping, ending a stage after `steps` optimiser steps, left the learning rate
// able to move the model: the rate then is above the schedule's floor by at least
// kRateLeftShare of the cosine's range from the peak to the floor, that is before the cosine's
// last fifth, where the annealing lowers the validation loss most and a stop may be the
// schedule's doing rather than the model's. (At 1/99 of the range, twice the default floor, the
// standard preset's D16 on 2,800 frames stopped at 1.4 % of the range while its validation loss
// still fell 3.6 % in ten rounds, and ranked below the same model on 1,400 frames.) A schedule
// without decay (constant) has rate left at any step before its end.
constexpr double kRateLeftShare = 0.1;
bool stopped_with_rate_left(const LearningRateSchedule& schedule, long long steps);

// How a training under the rule ended.
enum class TrainingEnd {
  early_stopping,  // early stopping with rate left (stopped_with_rate_left)
  floor,   // one stage (no doubling allowed), early stopping at the floor: the schedule may have
           // ended it, so it is not counted as converged
  budget,  // one stage, its budget spent: the budget ended it, not the model
  rule,    // the last doubling lowered the best validation loss by at most the tolerance
  cap,     // max_doublings reached while the last doubling still gained more: budget-bound
};
std::string to_string(TrainingEnd end);
// early stopping | floor | budget | rule | cap; InputError("TrainingEnd", "name") otherwise.
TrainingEnd parse_training_end(const std::string& name);
// Whether the model, not the budget, ended the training (early stopping or the rule).
bool converged(TrainingEnd end);

// The rule's decision after a doubling: double again when fewer than max_doublings doublings were
// taken and `latest` (the best validation loss so far) lies more than tolerance below `previous`
// (the best before the last doubling). Non-finite losses never double. The first doubling is
// taken whenever one is allowed and early stopping did not end the first stage with rate left
// (training_run.h): only it can tell whether the budget sufficed.
bool double_again(const BudgetRule& rule, double previous, double latest, int doublings);
// Whether a doubling lowered the best validation loss from `previous` to `latest` by more than
// the tolerance (false for non-finite losses): past the cap, a doubling that still paid ends the
// training as `cap`, one that did not as `rule`.
bool doubling_paid(const BudgetRule& rule, double previous, double latest);

}  // namespace eitbench
