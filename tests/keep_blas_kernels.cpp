// The suite's runs of the tool keep the BLAS kernels OpenBLAS chose, as the suite's own process
// does (cmake/test_environment.cmake says why). Set here, as the binary starts, since
// gtest_discover_tests passes the tests one environment entry only; a value already set stands.
#include <cstdlib>

namespace {
const bool kept_blas_kernels = setenv("EITBENCH_KEEP_BLAS_KERNELS", "1", 0) == 0;
}  // namespace
