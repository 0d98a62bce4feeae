#pragma once
// What the trainer needs from CUDA beyond LibTorch's portable API (internal to learned/): the
// cuBLAS/cuDNN math modes, bf16 autocast and CUDA graphs. cuda_support.cpp implements it where
// the LibTorch found has CUDA (the PyTorch wheel's, scripts/gpu-build.sh); in a CPU build
// cuda_support_none.cpp says that it has none, and its guards and graphs refuse to start.
#include <torch/types.h>

#include <functional>
#include <memory>
#include <vector>

namespace eitbench::cuda {

// Whether this build's LibTorch has CUDA (not whether a GPU is present: see cuda_available()).
bool compiled();

// TF32 tensor-core products in cuBLAS and cuDNN (float32 storage, a 10-bit mantissa in the
// products), and cuDNN's benchmark mode: the fastest algorithm for each shape, found at its first
// use. Global to the process, as LibTorch's own settings are.
void set_math(bool tf32, bool cudnn_benchmark);

// The math modes as they were when the guard was made, restored when it goes. The trainer holds
// one, so what runs after training (scoring, timing) runs in the modes it found, whatever was
// trained before in the process.
class MathGuard {
 public:
  MathGuard();
  ~MathGuard();
  MathGuard(const MathGuard&) = delete;
  MathGuard& operator=(const MathGuard&) = delete;

 private:
  bool tf32_cublas_ = false, tf32_cudnn_ = true, benchmark_ = false;
};

// bf16 autocast on CUDA while the guard lives (nothing when `on` is false): matrix products and
// convolutions in bfloat16, reductions and the loss in float32. Its cast cache is off, as graph
// capture requires; the previous state is restored.
class Bf16Autocast {
 public:
  explicit Bf16Autocast(bool on);
  ~Bf16Autocast();
  Bf16Autocast(const Bf16Autocast&) = delete;
  Bf16Autocast& operator=(const Bf16Autocast&) = delete;

 private:
  bool on_ = false, was_enabled_ = false, was_caching_ = true;
  int was_dtype_ = 0;  // the previous autocast dtype, as a c10::ScalarType
};

// Adam's step (no weight decay, no AMSGrad) on every parameter by LibTorch's fused CUDA kernel:
// one multi-tensor launch where the per-parameter form takes about nine. `steps` (one float32 0-dim
// tensor a parameter) go up by one first; `lr` is a float32 0-dim tensor on the device, read when
// the kernel runs, so a replayed graph takes the current rate. False, with nothing done, where
// this build has no fused kernel (a CPU LibTorch, or EITBENCH_FUSED_ADAM=OFF).
bool fused_adam(const std::vector<torch::Tensor>& params, const std::vector<torch::Tensor>& exp_avg,
                const std::vector<torch::Tensor>& exp_avg_sq,
                const std::vector<torch::Tensor>& steps, const torch::Tensor& lr, double beta1,
                double beta2, double eps);
bool has_fused_adam();

// A CUDA graph of one call of `body`: warmed up, then captured, on a side stream of its own
// (capture needs a stream other than the default), and replayed on the current stream. Everything
// `body` touches must stay at the same addresses between replays: static inputs, written before
// each replay.
class Graph {
 public:
  Graph();
  ~Graph();
  // Runs `body` on the side stream, after and before a device synchronisation: a warm-up call
  // (cuDNN's algorithm search, the allocator's first blocks) that does real work.
  void warm_up(const std::function<void()>& body);
  // Records `body` without running it; replay() runs it.
  void capture(const std::function<void()>& body);
  void replay();
  bool captured() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace eitbench::cuda
