// The LibTorch half of learned/ as one LearnedBackend: the models, the trainers and LibTorch's
// runtime. A program gets it from the module (backend.cpp) or, linking this half, directly.
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
#include "torch_model.h"
#include "trainer_impl.h"

namespace eitbench {
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

class TorchBackend final : public LearnedBackend {
 public:
  std::unique_ptr<LearnedModel::Impl> new_model(const NetworkOptions& network, int electrodes,
                                                std::uint64_t seed) const override {
    return std::make_unique<TorchModel>(network, electrodes, seed);
  }
  std::unique_ptr<LearnedModel::Impl> read_model(const std::string& bytes,
                                                 const std::string& source) const override {
    return TorchModel::from_bytes(bytes, source);
  }
  std::unique_ptr<Trainer::Impl> new_trainer(const NetworkOptions& network,
                                             const TrainingOptions& options, LabelledFrames train,
                                             const LabelledFrames& validation,
                                             const AugmentSetup& sensor) const override {
    return std::make_unique<TorchTrainer>(
        std::make_unique<TrainerState>(network, options, std::move(train), validation, sensor));
  }
  std::unique_ptr<Trainer::Impl> resume_trainer(const std::string& checkpoint,
                                                const std::string& source, LabelledFrames train,
                                                const LabelledFrames& validation,
                                                const AugmentSetup& sensor) const override {
    return TorchTrainer::resume(checkpoint, source, std::move(train), validation, sensor);
  }

  bool cuda_available() const override { return torch::cuda::is_available(); }

  std::string runtime() const override {
    std::string text = "LibTorch " TORCH_VERSION;
    if (!torch::cuda::is_available()) return text + ", CPU";
    const auto gpus = torch::cuda::device_count();
    return text + ", CUDA, " + std::to_string(gpus) + (gpus == 1 ? " GPU" : " GPUs");
  }

  void set_threads(int threads) const override {
    // The limit is the environment's (OMP_THREAD_LIMIT); omp_set_num_threads cannot raise it.
    if (omp_get_thread_limit() < threads)
      throw InputError("OMP_THREAD_LIMIT", "",
                       std::to_string(omp_get_thread_limit()) + " is below the " +
                           std::to_string(threads) +
                           " threads asked for: OpenMP would run fewer, the figures would change "
                           "and OpenBLAS would wait for the missing ones for ever; raise or unset "
                           "it, or ask for fewer threads");
    // LibTorch trains and evaluates on this thread: its OpenMP teams, and OpenBLAS's under them,
    // follow this thread's setting.
    omp_set_dynamic(0);
    torch::set_num_threads(threads);
  }

  int threads() const override { return torch::get_num_threads(); }

  ThreadLayout thread_layout() const override {
    ThreadLayout layout;
    layout.threads = threads();
    layout.dynamic = omp_get_dynamic() != 0;
    cpu_set_t allowed;
    CPU_ZERO(&allowed);
    layout.cpus = sched_getaffinity(0, sizeof allowed, &allowed) == 0 ? CPU_COUNT(&allowed) : 0;
    layout.blas = blas_description();
    return layout;
  }

  double time_matmul(int n, int repeats) const override {
    torch::InferenceMode guard;
    const auto a = torch::rand({n, n}), b = torch::rand({n, n});
    auto c = torch::mm(a, b);  // warm-up: thread pool, caches
    std::vector<double> seconds;
    for (int k = 0; k < std::max(1, repeats); ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      c = torch::mm(a, b);
      seconds.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(seconds.begin(), seconds.end());
    return seconds[seconds.size() / 2];
  }
};

}  // namespace
}  // namespace eitbench

extern "C" __attribute__((visibility("default"))) const eitbench::LearnedBackend*
eitbench_learned_backend() {
  static const eitbench::TorchBackend backend;
  return &backend;
}
