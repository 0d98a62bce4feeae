#pragma once
// One optimiser step of the trainer (internal to learned/). On the CPU, or without the resident
// set, it is LibTorch's eager step with torch::optim::Adam. On a GPU with the resident set, the
// whole step (the batch's gather, forward, backward, Adam, the loss's running sum) is captured
// once as a CUDA graph and replayed: a few hundred kernel launches become one, and the host only
// writes the batch's row indices and the learning rate before each replay. Adam then runs on
// tensors over torch::optim::Adam's own state (LibTorch's fused CUDA kernel, or adam_update where
// there is none), so a checkpoint holds the same state whichever path trained it.
#include <torch/torch.h>

#include <memory>
#include <vector>

#include "cuda_support.h"
#include "eitbench/learned/trainer.h"
#include "network.h"
#include "resident_set.h"

namespace eitbench {

// Adam's step as torch::optim::Adam takes it (no weight decay, no AMSGrad), with the step count
// and the learning rate as 0-dim float64 tensors on the parameters' device: `step` goes up by one
// there and the bias corrections are computed there, so a replayed graph uses the current values.
// exp_avg and exp_avg_sq are each parameter's moments, updated in place.
void adam_update(const std::vector<torch::Tensor>& params,
                 const std::vector<torch::Tensor>& exp_avg,
                 const std::vector<torch::Tensor>& exp_avg_sq, const torch::Tensor& step,
                 const torch::Tensor& lr, double beta1, double beta2, double eps);

// torch::optim::Adam's state of `param`, made (zero moments, step 0) if Adam has not stepped it.
torch::optim::AdamParamState& adam_state(torch::optim::Adam& adam, const torch::Tensor& param);
// The same, or nullptr where Adam has none.
torch::optim::AdamParamState* adam_state_if_any(torch::optim::Adam& adam,
                                                const torch::Tensor& param);

// "fp32", "tf32" or "bf16": TrainingOptions::precision with "auto" resolved for `device`.
std::string resolve_precision(const std::string& precision, const torch::Device& device);

class StepRunner {
 public:
  // `graphs`: capture and replay full batches of options.batch_size rows (CUDA only).
  StepRunner(Network net, torch::optim::Adam& adam, const TrainingOptions& options,
             const torch::Device& device, bool graphs);
  ~StepRunner();

  // One step on the batch (x, y) (eager).
  void step(const torch::Tensor& x, const torch::Tensor& y, double rate);
  // One step on rows[first, end) of the resident set: a full batch replays the graph.
  void step(const ResidentSet& set, const torch::Tensor& rows, long long first, long long end,
            double rate);
  // The sum of the batch losses since reset_loss() (0-dim float64, on the device).
  const torch::Tensor& loss_sum() const { return loss_sum_; }
  void reset_loss() { loss_sum_.zero_(); }
  // Adam's host-side step counters set to the steps taken on the device (what a checkpoint
  // stores); call before the optimiser is saved.
  void sync_optimizer();
  bool graphs() const { return graphs_; }

 private:
  // The batch's MSE, under bf16 autocast when asked for.
  torch::Tensor loss(const torch::Tensor& x, const torch::Tensor& y);
  // Adam's rate: its options (what the eager step and checkpoints read) and, for the graph
  // path, the device scalar the graph reads.
  void set_rate(double rate);
  void tensor_step(const torch::Tensor& x, const torch::Tensor& y);

  Network net_;
  torch::optim::Adam& adam_;
  long long batch_ = 0;
  bool graphs_ = false, bf16_ = false;
  torch::Tensor loss_sum_;
  // The graph path's state: Adam's moments and step, the learning rate, the batch's row indices.
  std::vector<torch::Tensor> params_, exp_avg_, exp_avg_sq_;
  double beta1_ = 0.9, beta2_ = 0.999, eps_ = 1e-8;
  torch::Tensor step_count_, lr_, rows_;
  bool fused_ = false;                      // cuda::fused_adam, with these step counts
  std::vector<torch::Tensor> fused_steps_;  // float32, one a parameter
  long long steps_ = 0;                     // Adam's step count, on the host
  int warm_ups_ = 0;
  std::unique_ptr<cuda::Graph> graph_;
};

}  // namespace eitbench
