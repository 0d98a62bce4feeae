#include "train_step.h"

#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace eitbench {
namespace {

// Graph capture needs a few eager steps first: cuDNN's algorithm search, the allocator's blocks,
// the gradients' and Adam's tensors (PyTorch's own recipe warms up three times).
constexpr int kWarmUps = 3;

// Adam's state map is keyed by the parameter's TensorImpl: as a string in LibTorch 1.x (the
// pointer printed, as c10::guts::to_string prints it), as the pointer itself in 2.x.
template <class Map>
typename Map::key_type state_key(const Map&, const torch::Tensor& param) {
  using Key = typename Map::key_type;
  if constexpr (std::is_same_v<Key, std::string>) {
    std::ostringstream text;
    text << param.unsafeGetTensorImpl();
    return text.str();
  } else {
    return param.unsafeGetTensorImpl();
  }
}

}  // namespace

void adam_update(const std::vector<torch::Tensor>& params,
                 const std::vector<torch::Tensor>& exp_avg,
                 const std::vector<torch::Tensor>& exp_avg_sq, const torch::Tensor& step,
                 const torch::Tensor& lr, double beta1, double beta2, double eps) {
  torch::NoGradGuard no_grad;
  step.add_(1);
  const auto correction1 = torch::pow(beta1, step).neg_().add_(1);
  const auto root_correction2 = torch::pow(beta2, step).neg_().add_(1).sqrt_();
  const auto step_size = lr / correction1;
  for (std::size_t k = 0; k < params.size(); ++k) {
    const auto& grad = params[k].grad();
    if (!grad.defined()) continue;
    exp_avg[k].mul_(beta1).add_(grad, 1 - beta1);
    exp_avg_sq[k].mul_(beta2).addcmul_(grad, grad, 1 - beta2);
    const auto denominator = (exp_avg_sq[k].sqrt() / root_correction2).add_(eps);
    params[k].sub_(exp_avg[k] / denominator * step_size);
  }
}

torch::optim::AdamParamState* adam_state_if_any(torch::optim::Adam& adam,
                                                const torch::Tensor& param) {
  auto& states = adam.state();
  const auto found = states.find(state_key(states, param));
  return found == states.end() ? nullptr
                               : static_cast<torch::optim::AdamParamState*>(found->second.get());
}

torch::optim::AdamParamState& adam_state(torch::optim::Adam& adam, const torch::Tensor& param) {
  if (auto* state = adam_state_if_any(adam, param)) return *state;
  auto made = std::make_unique<torch::optim::AdamParamState>();
  made->step(0);
  made->exp_avg(torch::zeros_like(param, torch::MemoryFormat::Preserve));
  made->exp_avg_sq(torch::zeros_like(param, torch::MemoryFormat::Preserve));
  auto& states = adam.state();
  const auto key = state_key(states, param);
  return static_cast<torch::optim::AdamParamState&>(
      *states.insert({key, std::move(made)}).first->second);
}

std::string resolve_precision(const std::string& precision, const torch::Device& device) {
  if (precision != "auto") return precision;
  return device.is_cuda() ? "tf32" : "fp32";
}

StepRunner::StepRunner(Network net, torch::optim::Adam& adam, const TrainingOptions& options,
                       const torch::Device& device, bool graphs)
    : net_(std::move(net)),
      adam_(adam),
      batch_(options.batch_size),
      graphs_(graphs),
      bf16_(resolve_precision(options.precision, device) == "bf16") {
  const auto on_device = torch::TensorOptions().device(device);
  loss_sum_ = torch::zeros({}, on_device.dtype(torch::kFloat64));
  if (!graphs_) return;
  const auto& group = adam_.param_groups().at(0);
  const auto& o = static_cast<const torch::optim::AdamOptions&>(group.options());
  if (o.weight_decay() != 0 || o.amsgrad())
    throw std::logic_error("StepRunner: the graph path has Adam without weight decay or AMSGrad");
  beta1_ = std::get<0>(o.betas()), beta2_ = std::get<1>(o.betas()), eps_ = o.eps();
  params_ = group.params();
  for (const auto& p : params_) {
    auto& state = adam_state(adam_, p);
    exp_avg_.push_back(state.exp_avg());
    exp_avg_sq_.push_back(state.exp_avg_sq());
    steps_ = state.step();
  }
  // LibTorch's fused kernel where it has one (CUDA): float32 step counts, one a parameter, and
  // a float32 rate, as it reads them; elsewhere adam_update's float64 scalars.
  fused_ = device.is_cuda() && cuda::has_fused_adam();
  const auto scalar = on_device.dtype(fused_ ? torch::kFloat32 : torch::kFloat64);
  if (fused_)
    for (std::size_t k = 0; k < params_.size(); ++k)
      fused_steps_.push_back(torch::full({}, double(steps_), scalar));
  step_count_ = torch::full({}, double(steps_), scalar);
  lr_ = torch::zeros({}, scalar);
  rows_ = torch::zeros({batch_}, on_device.dtype(torch::kInt64));
  if (device.is_cuda()) graph_ = std::make_unique<cuda::Graph>();
}

StepRunner::~StepRunner() = default;

torch::Tensor StepRunner::loss(const torch::Tensor& x, const torch::Tensor& y) {
  const cuda::Bf16Autocast autocast(bf16_);
  return torch::mse_loss(net_->forward(x).to(torch::kFloat32), y);
}

void StepRunner::set_rate(double rate) {
  for (auto& group : adam_.param_groups())
    static_cast<torch::optim::AdamOptions&>(group.options()).lr(rate);
  if (graphs_) lr_.fill_(rate);
}

void StepRunner::tensor_step(const torch::Tensor& x, const torch::Tensor& y) {
  for (const auto& p : params_)
    if (p.grad().defined()) p.grad().zero_();  // in place: the graph's gradients stay put
  const torch::Tensor loss = this->loss(x, y);
  loss.backward();
  if (!fused_ ||
      !cuda::fused_adam(params_, exp_avg_, exp_avg_sq_, fused_steps_, lr_, beta1_, beta2_, eps_))
    adam_update(params_, exp_avg_, exp_avg_sq_, step_count_, lr_, beta1_, beta2_, eps_);
  loss_sum_.add_(loss.detach().to(torch::kFloat64));
}

void StepRunner::step(const torch::Tensor& x, const torch::Tensor& y, double rate) {
  set_rate(rate);
  if (graphs_) {
    tensor_step(x, y);
    ++steps_;
    return;
  }
  adam_.zero_grad();
  const torch::Tensor loss = this->loss(x, y);
  loss.backward();
  adam_.step();
  loss_sum_.add_(loss.detach().to(torch::kFloat64));
}

void StepRunner::step(const ResidentSet& set, const torch::Tensor& rows, long long first,
                      long long end, double rate) {
  // Without a graph, or for an epoch's shorter last batch: the eager step.
  if (!graph_ || end - first != batch_) {
    const auto [x, y] = set.batch(rows, first, end);
    return step(x, y, rate);
  }
  set_rate(rate);
  rows_.copy_(rows.narrow(0, first, batch_));
  const auto body = [&] {
    const auto [x, y] = set.gather(rows_);
    tensor_step(x, y);
  };
  if (warm_ups_ < kWarmUps) {
    graph_->warm_up(body);
    ++warm_ups_;
  } else {
    if (!graph_->captured()) graph_->capture(body);
    graph_->replay();
  }
  ++steps_;
}

void StepRunner::sync_optimizer() {
  if (!graphs_) return;
  for (const auto& p : params_) adam_state(adam_, p).step(steps_);
}

}  // namespace eitbench
