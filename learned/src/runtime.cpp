#include "eitbench/learned/runtime.h"

#include <dlfcn.h>
#include <omp.h>
#include <sched.h>
#include <torch/torch.h>
#include <torch/version.h>

#include <algorithm>
#include <chrono>
#include <string>
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
  if (threads <= 0) return;
  // The limit is the environment's (OMP_THREAD_LIMIT); omp_set_num_threads cannot raise it.
  if (omp_get_thread_limit() < threads)
    throw InputError("OMP_THREAD_LIMIT", "",
                     std::to_string(omp_get_thread_limit()) + " is below the " +
                         std::to_string(threads) +
                         " threads asked for: OpenMP would run fewer, the figures would change and "
                         "OpenBLAS would wait for the missing ones for ever; raise or unset it, or "
                         "ask for fewer threads");
  // LibTorch trains and evaluates on this thread: its OpenMP teams, and OpenBLAS's under them,
  // follow this thread's setting.
  omp_set_dynamic(0);
  torch::set_num_threads(threads);
}

int torch_threads() {
  return torch::get_num_threads();
}

namespace {

// OpenBLAS's openblas_get_config where it is the BLAS loaded ("OpenBLAS 0.3.21 DYNAMIC_ARCH
// NO_AFFINITY Zen MAX_THREADS=64"), else what the dynamic linker resolved sgemm_ from.
std::string blas_description() {
  using Config = char* (*)();
  if (const auto config = reinterpret_cast<Config>(dlsym(RTLD_DEFAULT, "openblas_get_config")))
    return config();
  Dl_info info{};
  if (void* sgemm = dlsym(RTLD_DEFAULT, "sgemm_"); sgemm && dladdr(sgemm, &info) && info.dli_fname)
    return info.dli_fname;
  return "unknown";
}

}  // namespace

ThreadLayout thread_layout() {
  ThreadLayout layout;
  layout.threads = torch_threads();
  layout.dynamic = omp_get_dynamic() != 0;
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  layout.cpus = sched_getaffinity(0, sizeof allowed, &allowed) == 0 ? CPU_COUNT(&allowed) : 0;
  layout.blas = blas_description();
  return layout;
}

std::string ThreadLayout::describe() const {
  return std::to_string(threads) + (threads == 1 ? " thread" : " threads") + ", OpenMP dynamic " +
         (dynamic ? "on" : "off") + ", " + std::to_string(cpus) + (cpus == 1 ? " CPU" : " CPUs") +
         " allowed; " + blas;
}

std::string ThreadLayout::warning() const {
  if (cpus <= 0 || threads <= cpus) return "";
  return std::to_string(threads) + " threads on " + std::to_string(cpus) +
         (cpus == 1 ? " CPU" : " CPUs") +
         " this process may use (a launcher's binding or taskset): the figures are the "
         "same, the training far slower; bind each process to as many cores as threads "
         "(mpirun --bind-to none, or --map-by slot:PE=N) or ask for fewer threads";
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
