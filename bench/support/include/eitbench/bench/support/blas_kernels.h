#pragma once
// OpenBLAS's kernels for the CPU it runs on. The OpenBLAS of Debian 12 (0.3.21) picks them by the
// CPU's model number and, for a model newer than it (such as the 2-core Intel Xeon of
// docs/building.md, family 6 model 207), falls back to its SSE3 "Prescott" kernels, although the
// CPU has AVX2 and AVX-512. It reads OPENBLAS_CORETYPE once, as it loads, before main().
// Measured there: a KTC frame's Gauss-Newton reconstruction 14.1 s with the fallback, 5.6 s with
// the SkylakeX kernels (docs/building.md).
#include <string>

namespace eitbench {

// The kernels OpenBLAS would be told to use on this CPU where it fell back to Prescott's:
// "SkylakeX" with AVX-512 (F, BW, DQ, VL), "Haswell" with AVX2 and FMA; empty where it chose for
// itself, where the CPU has neither, or where the BLAS is not OpenBLAS.
std::string better_blas_kernels();

// Runs the program again (the same process, argv unchanged) with OPENBLAS_CORETYPE set to
// better_blas_kernels() where that is not empty. Does nothing where OPENBLAS_CORETYPE is already
// set (the user's choice, or this function's) or EITBENCH_KEEP_BLAS_KERNELS is set to anything
// (the tests: one choice for their processes and the tool's). Call first in main(), before any
// thread starts; returns only where it did not run the program again.
void use_the_cpus_blas_kernels(char** argv);

// OpenBLAS's kernels in use ("SkylakeX", "Prescott"), or "not OpenBLAS".
std::string blas_kernels();

}  // namespace eitbench
