#include "eitbench/learned/runtime.h"

#include "backend.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

bool cuda_available() {
  return learned_backend().cuda_available();
}

std::string torch_runtime() {
  return learned_backend().runtime();
}

std::string resolve_device(const std::string& name, const std::string& source) {
  if (name == "cpu") return "cpu";  // without loading LibTorch
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
  if (threads > 0) learned_backend().set_threads(threads);
}

int torch_threads() {
  return learned_backend().threads();
}

ThreadLayout thread_layout() {
  return learned_backend().thread_layout();
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
  return learned_backend().time_matmul(n, repeats);
}

}  // namespace eitbench
