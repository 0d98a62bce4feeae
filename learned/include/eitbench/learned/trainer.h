#pragma once
// Training the learned reconstructor: MSE loss, Adam under a learning-rate schedule, validation at
// a fixed interval of samples seen (a "round"), the best model kept, early stopping when the
// validation loss stops improving (the budget is only an upper bound), and checkpoints that resume
// to exactly where an uninterrupted run would have gone (the batch order and the augmentation are
// functions of (seed, epoch), dropout's random numbers of (seed, round), not of a running state).
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "eitbench/augment/augmented_set.h"
#include "eitbench/learned/learned_model.h"
#include "eitbench/learned/schedule.h"

namespace eitbench {

struct TrainingOptions {
  AugmentGroup augment = AugmentGroup::none;
  // Materialise the |G| N augmented samples (an epoch sees each sample under every element)
  // instead of drawing one element per sample and epoch on the fly (an epoch is N samples).
  bool expanded = false;
  // The budget, an upper bound: epochs or optimiser steps, at most one of them given (> 0);
  // neither given: 20 epochs. Neither may be negative.
  int epochs = 0;
  long long steps = 0;
  int batch_size = 128;         // at least 2 (BatchNorm); the paper: 512
  double learning_rate = 1e-2;  // the schedule's peak, positive (the paper: 1e-4, constant)
  ScheduleOptions schedule;     // warm-up and cosine over the budget
  // Training samples between two validations (rounded up to whole steps), at least 1: validation
  // and the checkpoint cost the same whatever the epoch's size.
  long long validate_every = 16384;
  // Early stopping: stop after `patience` (>= 0) validations without a validation loss
  // min_improvement (relative, in [0, 1)) below the last one that counted as an improvement; 0:
  // train to the budget. The model kept is the best validation loss of the run either way.
  int patience = 0;
  double min_improvement = 5e-3;
  // Early stopping only once the schedule's cosine has reached its floor: rounds without
  // improvement before it do not end the run. A training continued from a model with a fresh
  // schedule (the budget rule's doubling) first loses ground at the peak rate and regains it only
  // as the rate anneals; stopped before, it would be judged at the rate least able to refine it.
  // A constant schedule has no floor before its budget's end: with this set, it runs to the end.
  bool patience_after_decay = false;
  std::uint64_t seed = 1;
  std::string device = "cpu";  // auto | cpu | cuda (see resolve_device)
  // Keep the training set on the device, every sample under every group element as float32, so
  // that a batch is one gather there and a step never waits for the host: "on", "off", or
  // "auto" (on for a GPU when it fits in resident_max_gib, off on the CPU). The batches, and so
  // the training, are the same either way; it costs N |G| (inputs + pixels) 4 bytes.
  std::string resident = "auto";
  double resident_max_gib = 24;  // positive; "on" beyond it is an error, "auto" falls back
  // Arithmetic on a GPU: "fp32" (float32 throughout), "tf32" (float32 storage, TF32 tensor-core
  // products in matrix products and convolutions), "bf16" (autocast: products and convolutions
  // in bfloat16; the loss, the optimiser and the weights in float32), or "auto": tf32 on a GPU,
  // fp32 on the CPU. The CPU has fp32 only. cuDNN's benchmark mode is on for any GPU run.
  std::string precision = "auto";
  // The training step as a CUDA graph, captured once and replayed (a few hundred kernel launches
  // become one): "on", "off", or "auto" (on for a GPU with the resident set). It needs both. Adam
  // then runs on device tensors over the same state; dropout draws from the same generator, but
  // not the same numbers as the eager step, so the two paths train alike, not bit for bit.
  std::string cuda_graphs = "auto";
  // The decoder's activations and convolution weights in channels-last (NHWC) memory: "on" or
  // "off". The same arithmetic in another layout, so the training differs only in rounding. On a
  // GPU it spares cuDNN's transposes; "off" until a GPU measurement shows it pays (docs/gpu.md).
  std::string channels_last = "off";

  // Throws InputError("TrainingOptions", field) for a value out of range or a device this
  // machine does not have, and ScheduleOptions::validate()'s error for the schedule.
  void validate() const;
};

// One round: the steps since the previous validation, then a validation.
struct TrainingRecord {
  int round = 0;               // 1-based
  int epoch = 0;               // the epoch the round ended in (1-based)
  long long steps = 0;         // optimiser steps so far
  long long samples = 0;       // training samples seen so far
  double train_loss = 0;       // mean batch MSE over the round (training mode: dropout on)
  double validation_loss = 0;  // MSE over the validation set (evaluation mode)
  double learning_rate = 0;    // at the round's last step
  double seconds = 0;          // this round's training time (without validation)
  double samples_per_second = 0;
};

// The history as JSON text (an array of rounds, the fields above by name; non-finite losses as
// null), and back: how the model file, the checkpoint and bench/'s results.json store it.
// history_from_json throws InputError(source, "history") on anything else.
std::string history_to_json(const std::vector<TrainingRecord>& history);
std::vector<TrainingRecord> history_from_json(const std::string& text, const std::string& source);

// Optimiser steps in an epoch of `samples` samples: full batches, plus the remainder as one more
// batch when it holds at least 2 samples (BatchNorm needs 2).
long long steps_per_epoch(long long samples, int batch_size);

// Called at most 64 times a round, and after its last step: (step within the round, steps in the
// round, the mean batch loss since the previous call). Not after every step: reading a loss
// forces a device sync, which would dominate a GPU step of a small network.
using StepCallback = std::function<void(long long, long long, double)>;

class Trainer {
 public:
  // The sensor (electrodes, layout = reduced, image size, radius) comes from `sensor`; its group
  // is replaced by options.augment. The trainer keeps its own training set (move it in to avoid a
  // copy). Validates both options structs; throws InputError on empty or unlabelled sets and on
  // shapes that disagree with `network`.
  Trainer(const NetworkOptions& network, const TrainingOptions& options, LabelledFrames train,
          const LabelledFrames& validation, const AugmentSetup& sensor);
  // Continues the run saved in `checkpoint` (bytes of checkpoint()) on the same data: InputError
  // names `source` when the bytes are not a checkpoint or the data differ from the run's.
  static std::unique_ptr<Trainer> resume(const std::string& checkpoint, const std::string& source,
                                         LabelledFrames train, const LabelledFrames& validation,
                                         const AugmentSetup& sensor);
  ~Trainer();
  // Fine-tuning: the training starts from `model`'s weights and keeps its input normalisation (a
  // few real frames are no basis for new statistics) in place of a fresh network. Call before the
  // first round. InputError(source, "network") when the model's shape is not this training's.
  void start_from(const LearnedModel& model, const std::string& source);

  bool done() const;       // the budget is spent or early stopping triggered
  bool converged() const;  // stopped by early stopping, not by the budget
  // Trains one round (validate_every samples, or what the budget leaves), then validates; the
  // best model so far is kept by validation loss.
  TrainingRecord run_round(const StepCallback& on_step = {});
  const std::vector<TrainingRecord>& history() const;
  int best_round() const;  // 0 before the first round
  int best_epoch() const;  // the epoch the best round ended in
  long long steps_per_epoch() const;
  long long steps_per_round() const;
  long long total_steps() const;  // the budget in steps (epochs x steps per epoch, or steps)
  int total_epochs() const;       // the epochs the budget needs
  long long samples_per_epoch() const;
  const TrainingOptions& options() const;
  const LearningRateSchedule& schedule() const;

  // Everything needed to resume, as bytes (bench/ writes them to disk atomically).
  std::string checkpoint() const;
  // The best model by validation loss (the current one before any round), with ModelInfo filled.
  LearnedModel best_model() const;
  // The input normalisation: mean and standard deviation of the augmented training set.
  Eigen::VectorXd input_mean() const;
  Eigen::VectorXd input_std() const;
  // Batch `index` of `epoch` (1-based) as the network receives it, before normalisation.
  void batch(int epoch, long long index, SampleMatrix& frames, SampleMatrix& labels) const;

  struct Impl;  // what the LibTorch module implements (learned/src/backend.h)

 private:
  explicit Trainer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace eitbench
