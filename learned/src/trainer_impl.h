#pragma once
// The trainer's state (internal to learned/): shared by the training loop (trainer.cpp) and the
// checkpoint (trainer_state.cpp).
#include <torch/torch.h>

#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "eitbench/learned/trainer.h"
#include "network.h"
#include "resident_set.h"
#include "train_step.h"

namespace eitbench {

constexpr double kNoLoss = std::numeric_limits<double>::infinity();

struct Trainer::Impl {
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

  Impl(const NetworkOptions& n, const TrainingOptions& o, LabelledFrames train_set,
       const LabelledFrames& validation, const AugmentSetup& sensor);
  void input_statistics();
  bool choose_residency() const;
  bool choose_graphs() const;  // after residency is chosen
  void make_resident();
  // The rows of `order`'s samples in the resident set's layout, on the device.
  torch::Tensor resident_rows(int epoch, const std::vector<long long>& order) const;
  void make_batch(int epoch, const std::vector<long long>& order, long long index,
                  SampleMatrix& frames, SampleMatrix& labels) const;
  double validate();
  void record_validation(const TrainingRecord& r);
};

// A hash of everything a set's samples depend on (a checkpoint resumes only on its own data).
std::uint64_t fingerprint(const LabelledFrames& set);
// The order of epoch `epoch`'s samples: Fisher-Yates on the (seed, epoch) stream.
std::vector<long long> permutation(long long n, std::uint64_t seed, int epoch);

nlohmann::json options_to_json(const TrainingOptions& options);
TrainingOptions options_from_json(const nlohmann::json& json);
nlohmann::json finite_or_null(double v);
double number_or_infinity(const nlohmann::json& j);

}  // namespace eitbench
