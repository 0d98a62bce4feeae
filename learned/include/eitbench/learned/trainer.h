#pragma once
// Training the learned reconstructor: MSE loss, Adam, validation every epoch, the best model kept,
// a budget in epochs or optimiser steps, optional early stopping, and checkpoints that resume to
// exactly where an uninterrupted run would have gone (the batch order, the augmentation and
// dropout's random numbers are functions of (seed, epoch), not of a running state).
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "eitbench/augment/augmented_set.h"
#include "eitbench/learned/learned_model.h"

namespace eitbench {

struct TrainingOptions {
  AugmentGroup augment = AugmentGroup::none;
  // Materialise the |G| N augmented samples (an epoch sees each sample under every element)
  // instead of drawing one element per sample and epoch on the fly (an epoch is N samples).
  bool expanded = false;
  int epochs = 0;               // the budget: epochs, or
  long long steps = 0;          // optimiser steps; neither given: 20 epochs
  int batch_size = 128;         // the paper: 512
  double learning_rate = 1e-3;  // the paper: 1e-4
  int patience = 0;  // stop after this many epochs without a better validation loss; 0: never
  std::uint64_t seed = 1;
  std::string device = "cpu";  // cpu | cuda (see resolve_device)
};

struct EpochRecord {
  int epoch = 0;               // 1-based
  long long steps = 0;         // optimiser steps so far
  long long samples = 0;       // training samples seen so far
  double train_loss = 0;       // mean batch MSE over the epoch (training mode: dropout on)
  double validation_loss = 0;  // MSE over the validation set (evaluation mode)
  double seconds = 0;          // this epoch's training time (without validation)
  double samples_per_second = 0;
};

// The history as JSON text (an array of epochs, the fields above by name; non-finite losses as
// null), and back: how the model file, the checkpoint and bench/'s results.json store it.
// history_from_json throws InputError(source, "history") on anything else.
std::string history_to_json(const std::vector<EpochRecord>& history);
std::vector<EpochRecord> history_from_json(const std::string& text, const std::string& source);

// Called after each optimiser step: (step within the epoch, steps in the epoch, batch loss).
using StepCallback = std::function<void(long long, long long, double)>;

class Trainer {
 public:
  // The sensor (electrodes, layout = reduced, image size, radius) comes from `sensor`; its group
  // is replaced by options.augment. The trainer keeps its own training set (move it in to avoid a
  // copy). Throws InputError on empty or unlabelled sets and on shapes that disagree with
  // `network`.
  Trainer(const NetworkOptions& network, const TrainingOptions& options, LabelledFrames train,
          const LabelledFrames& validation, const AugmentSetup& sensor);
  // Continues the run saved in `checkpoint` (bytes of checkpoint()) on the same data: InputError
  // names `source` when the bytes are not a checkpoint or the data differ from the run's.
  static std::unique_ptr<Trainer> resume(const std::string& checkpoint, const std::string& source,
                                         LabelledFrames train, const LabelledFrames& validation,
                                         const AugmentSetup& sensor);
  ~Trainer();

  bool done() const;  // the budget is spent or early stopping triggered
  // Trains one epoch (or what the step budget leaves of it), then validates; the best model so far
  // is kept by validation loss.
  EpochRecord run_epoch(const StepCallback& on_step = {});
  const std::vector<EpochRecord>& history() const;
  int best_epoch() const;
  long long steps_per_epoch() const;
  long long total_steps() const;  // the budget in steps (epochs x steps per epoch, or --steps)
  int total_epochs() const;       // the epochs the budget needs
  const TrainingOptions& options() const;

  // Everything needed to resume, as bytes (bench/ writes them to disk atomically).
  std::string checkpoint() const;
  // The best model by validation loss (the current one before any epoch), with ModelInfo filled.
  LearnedModel best_model() const;
  // The input normalisation: mean and standard deviation of the augmented training set.
  Eigen::VectorXd input_mean() const;
  Eigen::VectorXd input_std() const;
  // Batch `index` of `epoch` (1-based) as the network receives it, before normalisation.
  void batch(int epoch, long long index, SampleMatrix& frames, SampleMatrix& labels) const;

 private:
  struct Impl;
  explicit Trainer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace eitbench
