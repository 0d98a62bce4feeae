#pragma once
// Trainer on LibTorch (internal to learned/): its state, shared by the training loop
// (torch_trainer.cpp) and the checkpoint (trainer_state.cpp), and the Trainer::Impl over it.
#include <torch/torch.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "backend.h"
#include "network.h"
#include "resident_set.h"
#include "train_step.h"
#include "training_json.h"

namespace eitbench {

struct TrainerState {
  NetworkOptions network;
  TrainingOptions options;
  AugmentSetup setup;
  std::shared_ptr<const LabelledFrames> train;  // the augmenter shares it
  LabelledFrames expanded;                      // the |G| N samples, when options.expanded
  std::unique_ptr<OnTheFlyAugmenter> augmenter;
  SampleMatrix validation_frames, validation_labels;
  std::uint64_t train_print = 0, validation_print = 0;
  cuda::MathGuard math;  // the math modes set for training, restored after it
  torch::Device device = torch::kCPU;
  std::unique_ptr<ResidentSet> resident;  // the set on the device, when options.resident allows
  bool graphs = false;                    // the step as a CUDA graph (options.cuda_graphs)
  std::unique_ptr<StepRunner> runner;     // made at the first round (after a resume's load)
  int group_size = 1;
  Network net{nullptr}, best{nullptr};
  std::unique_ptr<torch::optim::Adam> adam;
  std::unique_ptr<LearningRateSchedule> schedule;
  Eigen::VectorXd mean, std;
  long long train_size = 0, steps_per_epoch = 0, steps_per_round = 0, total_steps = 0;
  int total_epochs = 0;

  // Progress: everything a checkpoint stores.
  std::vector<TrainingRecord> history;
  int rounds_done = 0, best_round = 0;
  long long steps_done = 0, samples_done = 0;
  double best_loss = kNoLoss;       // the model kept
  double reference_loss = kNoLoss;  // the last loss that counted as an improvement
  int improved_round = 0;           // ... and its round: early stopping counts from it
  bool stopped_early = false;

  TrainerState(const NetworkOptions& n, const TrainingOptions& o, LabelledFrames train_set,
               const LabelledFrames& validation, const AugmentSetup& sensor);
  void input_statistics();
  bool choose_residency() const;
  bool choose_graphs() const;  // after residency is chosen
  void make_resident();
  // The networks' decoders, and Adam's moments of them, in the layout options.channels_last asks
  // for (the graph path's fused Adam wants each moment laid out as its parameter).
  void lay_out();
  // The rows of `order`'s samples in the resident set's layout, on the device.
  torch::Tensor resident_rows(int epoch, const std::vector<long long>& order) const;
  void make_batch(int epoch, const std::vector<long long>& order, long long index,
                  SampleMatrix& frames, SampleMatrix& labels) const;
  double validate();
  void record_validation(const TrainingRecord& r);
};

class TorchTrainer final : public Trainer::Impl {
 public:
  explicit TorchTrainer(std::unique_ptr<TrainerState> state) : state_(std::move(state)) {}
  // The checkpoint's trainer: InputError(source) for anything it cannot resume from.
  static std::unique_ptr<TorchTrainer> resume(const std::string& checkpoint,
                                              const std::string& source, LabelledFrames train,
                                              const LabelledFrames& validation,
                                              const AugmentSetup& sensor);

  void start_from(const LearnedModel::Impl& model, const std::string& source) override;
  bool done() const override;
  bool converged() const override;
  TrainingRecord run_round(const StepCallback& on_step) override;
  const std::vector<TrainingRecord>& history() const override;
  int best_round() const override;
  int best_epoch() const override;
  long long steps_per_epoch() const override;
  long long steps_per_round() const override;
  long long total_steps() const override;
  int total_epochs() const override;
  long long samples_per_epoch() const override;
  const TrainingOptions& options() const override;
  const LearningRateSchedule& schedule() const override;
  std::string checkpoint() const override;
  std::unique_ptr<LearnedModel::Impl> best_model() const override;
  Eigen::VectorXd input_mean() const override;
  Eigen::VectorXd input_std() const override;
  void batch(int epoch, long long index, SampleMatrix& frames, SampleMatrix& labels) const override;

 private:
  std::unique_ptr<TrainerState> state_;
};

// A hash of everything a set's samples depend on (a checkpoint resumes only on its own data).
std::uint64_t fingerprint(const LabelledFrames& set);
// The order of epoch `epoch`'s samples: Fisher-Yates on the (seed, epoch) stream.
std::vector<long long> permutation(long long n, std::uint64_t seed, int epoch);

nlohmann::json options_to_json(const TrainingOptions& options);
TrainingOptions options_from_json(const nlohmann::json& json);

}  // namespace eitbench
