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
// LibTorch's intra-op threads (0: leave its default, one per core).
void set_torch_threads(int threads);
int torch_threads();
// Seconds for one n x n by n x n single-precision product through LibTorch (the median of
// `repeats`, after a warm-up): 2 n^3 / seconds is the machine's GEMM speed.
double time_matmul(int n, int repeats);

}  // namespace eitbench
