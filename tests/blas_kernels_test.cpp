// The tool runs itself again with OpenBLAS's kernels for the CPU where OpenBLAS 0.3.21 fell back to
// its SSE3 ones (bench/support/blas_kernels.h). The suite keeps OpenBLAS's own choice
// (EITBENCH_KEEP_BLAS_KERNELS, cmake/test_environment.cmake); these tests run the tool without it.
#include <gtest/gtest.h>

#include <cstdlib>

#include "cli_fixture.h"
#include "eitbench/bench/support/blas_kernels.h"

namespace eitbench {
namespace {

class BlasKernels : public Cli {
 protected:
  // The kernels `eitbench --version` reports under `environment`.
  std::string kernels_under(const std::string& environment) const {
    const Result r = run_after("env -u OPENBLAS_CORETYPE " + environment + " ", "--version");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const std::string key = "BLAS kernels: ";
    const auto at = r.output.find(key);
    if (at == std::string::npos) return "(none reported)";
    return r.output.substr(at + key.size(), r.output.find(';', at) - at - key.size());
  }
};

TEST_F(BlasKernels, TheToolTakesTheCpusKernelsWhereOpenBlasFellBack) {
  if (std::getenv("OPENBLAS_CORETYPE")) GTEST_SKIP() << "OPENBLAS_CORETYPE is set for the tests";
  const std::string own = blas_kernels();  // this process: OpenBLAS's own choice
  if (own == "not OpenBLAS") GTEST_SKIP() << "the BLAS is not OpenBLAS";
  const std::string better = better_blas_kernels();
  EXPECT_EQ(kernels_under("EITBENCH_KEEP_BLAS_KERNELS=1"), own);
  EXPECT_EQ(kernels_under("-u EITBENCH_KEEP_BLAS_KERNELS"), better.empty() ? own : better);
  if (own == "Prescott") {
    __builtin_cpu_init();
    // The fallback on a CPU with AVX2 is what is replaced.
    EXPECT_EQ(better.empty(), !__builtin_cpu_supports("avx2")) << better;
  } else {
    EXPECT_EQ(better, "");  // OpenBLAS knew the CPU
  }
}

TEST_F(BlasKernels, TheUsersSettingStandsAndTheArgumentsPassThrough) {
  if (blas_kernels() == "not OpenBLAS") GTEST_SKIP() << "the BLAS is not OpenBLAS";
  // Prescott's kernels run on any x86-64: the user's choice, not replaced.
  EXPECT_EQ(kernels_under("-u EITBENCH_KEEP_BLAS_KERNELS OPENBLAS_CORETYPE=Prescott"), "Prescott");
  // A command run again keeps its arguments and its exit code.
  const Result r = run_after("env -u OPENBLAS_CORETYPE -u EITBENCH_KEEP_BLAS_KERNELS ",
                             "info " + path("no_such_file.h5"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no_such_file.h5"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace eitbench
