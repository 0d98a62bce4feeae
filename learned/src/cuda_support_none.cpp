// cuda_support.h in a build whose LibTorch has no CUDA: nothing to set, nothing to capture. The
// trainer never asks for a graph or bf16 here (TrainingOptions::validate refuses them without a
// GPU); these throw if it ever did.
#include <stdexcept>
#include <string>

#include "cuda_support.h"

namespace eitbench::cuda {
namespace {

[[noreturn]] void no_cuda(const char* what) {
  throw std::logic_error(std::string(what) + ": this build's LibTorch has no CUDA");
}

}  // namespace

bool compiled() {
  return false;
}

void set_math(bool, bool) {}
MathGuard::MathGuard() = default;
MathGuard::~MathGuard() = default;

bool has_fused_adam() {
  return false;
}
bool fused_adam(const std::vector<torch::Tensor>&, const std::vector<torch::Tensor>&,
                const std::vector<torch::Tensor>&, const std::vector<torch::Tensor>&,
                const torch::Tensor&, double, double, double) {
  return false;
}

Bf16Autocast::Bf16Autocast(bool on) : on_(on) {
  if (on_) no_cuda("bf16 autocast");
}
Bf16Autocast::~Bf16Autocast() = default;

struct Graph::Impl {};
Graph::Graph() {
  no_cuda("CUDA graph");
}
Graph::~Graph() = default;
void Graph::warm_up(const std::function<void()>&) {
  no_cuda("CUDA graph");
}
void Graph::capture(const std::function<void()>&) {
  no_cuda("CUDA graph");
}
void Graph::replay() {
  no_cuda("CUDA graph");
}
bool Graph::captured() const {
  return false;
}

}  // namespace eitbench::cuda
