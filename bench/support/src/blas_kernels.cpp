#include "eitbench/bench/support/blas_kernels.h"

#include <dlfcn.h>
#include <unistd.h>

#include <strings.h>
#include <cstdlib>

namespace eitbench {
namespace {

// OpenBLAS's own report of its kernels, looked up at run time: libblas.so.3 may be another BLAS.
const char* openblas_core_name() {
  using CoreName = char* (*)();
  const auto name = reinterpret_cast<CoreName>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  return name ? name() : nullptr;
}

}  // namespace

std::string better_blas_kernels() {
  const char* now = openblas_core_name();
  if (!now || strcasecmp(now, "Prescott") != 0) return "";
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl"))
    return "SkylakeX";
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return "Haswell";
  return "";
}

void use_the_cpus_blas_kernels(char** argv) {
  if (std::getenv("OPENBLAS_CORETYPE") || std::getenv("EITBENCH_KEEP_BLAS_KERNELS")) return;
  const std::string kernels = better_blas_kernels();
  if (kernels.empty()) return;
  if (setenv("OPENBLAS_CORETYPE", kernels.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);  // returns only where it failed: then on with Prescott's
  unsetenv("OPENBLAS_CORETYPE");
}

std::string blas_kernels() {
  const char* now = openblas_core_name();
  return now ? now : "not OpenBLAS";
}

}  // namespace eitbench
