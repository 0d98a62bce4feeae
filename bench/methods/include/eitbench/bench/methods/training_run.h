#pragma once
// One training run as the command line and the benchmark run do it: progress on the terminal, a
// checkpoint after every round (atomic), resumable after a kill, the budget rule's doublings, and
// at the end the model file and its loss curves (CSV and PNG).
#include <string>
#include <vector>

#include "eitbench/augment/augmented_set.h"
#include "eitbench/bench/methods/budget_rule.h"
#include "eitbench/learned.h"

namespace eitbench {

struct TrainingRun {
  std::string out;      // the model file; its checkpoint is out + ".checkpoint"
  bool resume = false;  // continue from the checkpoint (InputError when there is none)
  bool quiet = false;   // no progress
  std::string label = "train";
  bool curves = true;  // <stem>_loss.csv and <stem>_loss.png beside out
  // When the training ends (budget_rule.h): the options' budget, then doublings. Each doubling
  // keeps the best model so far in <out>.stage (and <out>.stage.json), so a kill loses one stage
  // at most.
  BudgetRule rule;
};

struct TrainingResult {
  LearnedModel model;                   // the best by validation loss
  std::vector<TrainingRecord> history;  // one entry a round (validation)
  int best_round = 0, best_epoch = 0;
  bool converged = false;  // the model ended the training, not the budget (converged(end))
  TrainingEnd end = TrainingEnd::budget;
  int doublings = 0;               // taken
  std::vector<double> stage_best;  // the best validation loss after each stage
  long long total_steps = 0;       // the budget in steps at the end (doubled each stage)
  long long steps_per_epoch = 0, samples_per_epoch = 0;
  double seconds = 0;  // training and validation, this session
  bool resumed = false;
};

std::string checkpoint_path(const std::string& model_path);
// Whether a training into model_path left something to resume: a checkpoint, or the record of the
// budget rule's stages finished so far.
bool resumable(const std::string& model_path);
// Removes what a training into model_path left to resume (its checkpoint and stage record), so
// that a training started afresh can never be resumed onto another training's stages.
void remove_training_files(const std::string& model_path);
// Whether a finished training's record (the model's ModelInfo::training) holds the decisions the
// budget rule as it is now takes for the same options, after a rule whose rate-left edge
// (stopped_with_rate_left) lay lower: only a first stage that early stopping ended between the
// two edges is decided otherwise now (doubled, or called "floor"). False for a record without
// the rule's fields or one that cannot be read: such a model is trained again.
bool decided_as_now(const LearnedModel& model, const TrainingOptions& options);
// <out's folder>/<out's stem>_loss.csv (and .png).
std::string loss_curve_path(const std::string& model_path, const std::string& extension);

TrainingResult train_and_save(const NetworkOptions& network, const TrainingOptions& options,
                              LabelledFrames train, const LabelledFrames& validation,
                              const AugmentSetup& sensor, const TrainingRun& run);

}  // namespace eitbench
