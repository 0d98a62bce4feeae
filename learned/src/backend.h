#pragma once
// The line between learned/'s two halves (internal). The public classes (LearnedModel, Trainer,
// the runtime functions) hold no LibTorch: they forward to the interfaces below, which the LibTorch
// half implements (torch_model.h, trainer_impl.h, backend_export.cpp). That half is a module of its
// own, libeitbench_learned_torch.so, loaded on first use: loading LibTorch takes about 0.7 s of a
// process's start on 2 cores, and most commands never train or apply a network.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "eitbench/learned/trainer.h"

namespace eitbench {

// A model: its description (plain data, read by the public class directly) and its network.
struct LearnedModel::Impl {
  virtual ~Impl() = default;
  ModelInfo info;

  virtual std::unique_ptr<Impl> clone() const = 0;  // a deep copy, on the same device
  virtual long long parameters() const = 0;
  virtual std::vector<bool> image_mask() const = 0;
  virtual SampleMatrix reconstruct(const SampleMatrix& frames, int batch) const = 0;
  virtual void to_device(const std::string& device) = 0;
  virtual std::string device() const = 0;
  virtual std::string to_bytes() const = 0;
};

// A training in progress: Trainer's public functions, one for one.
struct Trainer::Impl {
  virtual ~Impl() = default;

  virtual void start_from(const LearnedModel::Impl& model, const std::string& source) = 0;
  virtual bool done() const = 0;
  virtual bool converged() const = 0;
  virtual TrainingRecord run_round(const StepCallback& on_step) = 0;
  virtual const std::vector<TrainingRecord>& history() const = 0;
  virtual int best_round() const = 0;
  virtual int best_epoch() const = 0;
  virtual long long steps_per_epoch() const = 0;
  virtual long long steps_per_round() const = 0;
  virtual long long total_steps() const = 0;
  virtual int total_epochs() const = 0;
  virtual long long samples_per_epoch() const = 0;
  virtual const TrainingOptions& options() const = 0;
  virtual const LearningRateSchedule& schedule() const = 0;
  virtual std::string checkpoint() const = 0;
  virtual std::unique_ptr<LearnedModel::Impl> best_model() const = 0;
  virtual Eigen::VectorXd input_mean() const = 0;
  virtual Eigen::VectorXd input_std() const = 0;
  virtual void batch(int epoch, long long index, SampleMatrix& frames,
                     SampleMatrix& labels) const = 0;
};

// The LibTorch half's entry points: what makes models and trainers, and LibTorch's runtime.
class LearnedBackend {
 public:
  virtual ~LearnedBackend() = default;

  virtual std::unique_ptr<LearnedModel::Impl> new_model(const NetworkOptions& network,
                                                        int electrodes,
                                                        std::uint64_t seed) const = 0;
  virtual std::unique_ptr<LearnedModel::Impl> read_model(const std::string& bytes,
                                                         const std::string& source) const = 0;
  virtual std::unique_ptr<Trainer::Impl> new_trainer(const NetworkOptions& network,
                                                     const TrainingOptions& options,
                                                     LabelledFrames train,
                                                     const LabelledFrames& validation,
                                                     const AugmentSetup& sensor) const = 0;
  virtual std::unique_ptr<Trainer::Impl> resume_trainer(const std::string& checkpoint,
                                                        const std::string& source,
                                                        LabelledFrames train,
                                                        const LabelledFrames& validation,
                                                        const AugmentSetup& sensor) const = 0;

  virtual bool cuda_available() const = 0;
  virtual std::string runtime() const = 0;  // "LibTorch 1.13.0, CPU"
  virtual void set_threads(int threads) const = 0;
  virtual int threads() const = 0;
  virtual ThreadLayout thread_layout() const = 0;
  virtual double time_matmul(int n, int repeats) const = 0;
};

// The LibTorch half, loaded on the first call (std::runtime_error, naming the paths tried, if it
// cannot be). A program that links the half itself (the test suite) gets that one, loading nothing.
const LearnedBackend& learned_backend();

// The module's one exported symbol, an extern "C" function returning its LearnedBackend.
constexpr const char* kLearnedBackendSymbol = "eitbench_learned_backend";

}  // namespace eitbench
