// cuda_support.h on a LibTorch with CUDA (compiled only there: learned/CMakeLists.txt).
#include "cuda_support.h"

#include <ATen/ATen.h>
#include <ATen/Context.h>
#include <ATen/autocast_mode.h>
#include <ATen/cuda/CUDAGraph.h>
#include <c10/cuda/CUDAGuard.h>
#include <c10/cuda/CUDAStream.h>
#include <torch/cuda.h>

#include <stdexcept>

namespace eitbench::cuda {

bool compiled() {
  return true;
}

void set_math(bool tf32, bool cudnn_benchmark) {
  auto& context = at::globalContext();
  context.setAllowTF32CuBLAS(tf32);
  context.setAllowTF32CuDNN(tf32);
  context.setBenchmarkCuDNN(cudnn_benchmark);
}

MathGuard::MathGuard() {
  const auto& context = at::globalContext();
  tf32_cublas_ = context.allowTF32CuBLAS();
  tf32_cudnn_ = context.allowTF32CuDNN();
  benchmark_ = context.benchmarkCuDNN();
}

MathGuard::~MathGuard() {
  auto& context = at::globalContext();
  context.setAllowTF32CuBLAS(tf32_cublas_);
  context.setAllowTF32CuDNN(tf32_cudnn_);
  context.setBenchmarkCuDNN(benchmark_);
}

bool has_fused_adam() {
#ifdef EITBENCH_NO_FUSED_ADAM
  return false;
#else
  return true;
#endif
}

bool fused_adam(const std::vector<torch::Tensor>& params, const std::vector<torch::Tensor>& exp_avg,
                const std::vector<torch::Tensor>& exp_avg_sq,
                const std::vector<torch::Tensor>& steps, const torch::Tensor& lr, double beta1,
                double beta2, double eps) {
#ifdef EITBENCH_NO_FUSED_ADAM
  (void)params, (void)exp_avg, (void)exp_avg_sq, (void)steps, (void)lr, (void)beta1, (void)beta2,
      (void)eps;
  return false;
#else
  const at::NoGradGuard no_grad;
  std::vector<at::Tensor> grads;
  grads.reserve(params.size());
  for (const auto& p : params) {
    // Every parameter takes part in the loss; LibTorch's Adam would skip one that did not.
    if (!p.grad().defined()) throw std::logic_error("fused_adam: a parameter without a gradient");
    grads.push_back(p.grad());
  }
  at::_foreach_add_(steps, 1);
  at::_fused_adam_(params, grads, exp_avg, exp_avg_sq, {}, steps, lr, beta1, beta2,
                   /*weight_decay=*/0.0, eps, /*amsgrad=*/false, /*maximize=*/false);
  return true;
#endif
}

Bf16Autocast::Bf16Autocast(bool on) : on_(on) {
  if (!on_) return;
  was_enabled_ = at::autocast::is_autocast_enabled(at::kCUDA);
  was_caching_ = at::autocast::is_autocast_cache_enabled();
  was_dtype_ = static_cast<int>(at::autocast::get_autocast_dtype(at::kCUDA));
  at::autocast::set_autocast_dtype(at::kCUDA, at::kBFloat16);
  at::autocast::set_autocast_cache_enabled(false);
  at::autocast::set_autocast_enabled(at::kCUDA, true);
}

Bf16Autocast::~Bf16Autocast() {
  if (!on_) return;
  at::autocast::set_autocast_enabled(at::kCUDA, was_enabled_);
  at::autocast::set_autocast_cache_enabled(was_caching_);
  at::autocast::set_autocast_dtype(at::kCUDA, static_cast<at::ScalarType>(was_dtype_));
}

struct Graph::Impl {
  at::cuda::CUDAGraph graph;
  c10::cuda::CUDAStream stream = c10::cuda::getStreamFromPool();
  bool captured = false;
};

Graph::Graph() : impl_(std::make_unique<Impl>()) {}
Graph::~Graph() = default;

// The device-wide synchronisations order the side stream after the current stream's work (the
// static inputs written there) and before what follows: a few per graph, not per step.
void Graph::warm_up(const std::function<void()>& body) {
  torch::cuda::synchronize();
  {
    const c10::cuda::CUDAStreamGuard guard(impl_->stream);
    body();
  }
  torch::cuda::synchronize();
}

void Graph::capture(const std::function<void()>& body) {
  torch::cuda::synchronize();
  {
    const c10::cuda::CUDAStreamGuard guard(impl_->stream);
    impl_->graph.capture_begin();
    try {
      body();
    } catch (...) {  // leave the stream out of capture mode, then report what failed
      try {
        impl_->graph.capture_end();
      } catch (...) {
      }
      throw;
    }
    impl_->graph.capture_end();
  }
  torch::cuda::synchronize();
  impl_->captured = true;
}

void Graph::replay() {
  impl_->graph.replay();
}

bool Graph::captured() const {
  return impl_->captured;
}

}  // namespace eitbench::cuda
