#include "eitbench/learned/runtime.h"

#include <torch/torch.h>
#include <torch/version.h>

#include <algorithm>
#include <chrono>
#include <vector>

#include "eitbench/jacobian/error.h"

namespace eitbench {

bool cuda_available() {
  return torch::cuda::is_available();
}

std::string torch_runtime() {
  std::string text = "LibTorch " TORCH_VERSION;
  if (!torch::cuda::is_available()) return text + ", CPU";
  const auto gpus = torch::cuda::device_count();
  return text + ", CUDA, " + std::to_string(gpus) + (gpus == 1 ? " GPU" : " GPUs");
}

std::string resolve_device(const std::string& name, const std::string& source) {
  if (name == "cpu") return "cpu";
  if (name == "auto") return cuda_available() ? "cuda" : "cpu";
  if (name == "cuda") {
    if (!cuda_available())
      throw InputError(source, "",
                       "CUDA is not available (this LibTorch has no CUDA, or no GPU "
                       "is present); use cpu or auto");
    return "cuda";
  }
  throw InputError(source, "", "unknown device '" + name + "' (auto, cpu or cuda)");
}

void set_torch_threads(int threads) {
  if (threads > 0) torch::set_num_threads(threads);
}

int torch_threads() {
  return torch::get_num_threads();
}

double time_matmul(int n, int repeats) {
  torch::InferenceMode guard;
  const auto a = torch::rand({n, n}), b = torch::rand({n, n});
  auto c = torch::mm(a, b);  // warm-up: thread pool, caches
  std::vector<double> seconds;
  for (int k = 0; k < std::max(1, repeats); ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    c = torch::mm(a, b);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(seconds.begin(), seconds.end());
  return seconds[seconds.size() / 2];
}

}  // namespace eitbench
