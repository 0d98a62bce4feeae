#pragma once
// Where and how LibTorch runs: the device, its threads, and the machine's matrix-multiply speed
// (the yardstick for training's GFLOP/s).
#include <string>

namespace eitbench {

// "auto" (CUDA when LibTorch has it and a GPU is present, else CPU), "cpu" or "cuda".
// InputError(source) when CUDA is asked for and not available.
std::string resolve_device(const std::string& name, const std::string& source = "device");
// True when this LibTorch build can use a GPU now.
bool cuda_available();
// "LibTorch 1.13.1, CPU" or "LibTorch 2.11.0, CUDA, 1 GPU": what --version reports.
std::string torch_runtime();
// LibTorch's intra-op threads (0: leave its default, one per core). A learned model's figures
// depend on the count (each thread sums its share of a reduction), so it is fixed here whatever the
// launcher's environment says: OpenMP's dynamic adjustment (OMP_DYNAMIC), which would hand LibTorch
// a team sized by the load and hang OpenBLAS, which waits for every thread it asked for, is turned
// off. InputError("OMP_THREAD_LIMIT") when the environment caps OpenMP below `threads`.
void set_torch_threads(int threads);
int torch_threads();

// The threads a process computes with, as recorded beside its figures (docs/scaling.md).
struct ThreadLayout {
  int threads = 0;      // LibTorch's intra-op threads (OpenMP)
  bool dynamic = true;  // OpenMP may run fewer (off after set_torch_threads)
  int cpus = 0;         // CPUs this thread may run on (the affinity a launcher or taskset gave)
  std::string blas;     // the BLAS's own description: OpenBLAS names its version and kernels
  // One line for the record: "2 threads, OpenMP dynamic off, 2 CPUs; OpenBLAS 0.3.21 ...".
  std::string describe() const;
  // Non-empty when more threads than CPUs: the same figures, much slower (they spin-wait for a
  // core).
  std::string warning() const;
};
ThreadLayout thread_layout();
// Seconds for one n x n by n x n single-precision product through LibTorch (the median of
// `repeats`, after a warm-up): 2 n^3 / seconds is the machine's GEMM speed.
double time_matmul(int n, int repeats);

}  // namespace eitbench
