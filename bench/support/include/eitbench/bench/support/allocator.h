#pragma once
// glibc's allocator, set for eitbench's work: keep freed memory for reuse instead of handing it
// back to the system. Every forward solve, and every training batch, allocates and frees
// megabytes; by default glibc unmaps them and the next call faults them back in page by page
// (data generation: sys time 3.0 s of 19 s, 300 instead of 365 samples/s; LibTorch inference in
// batches of 512: page faults were the largest item of the profile). Call once, early in main(),
// before the work allocates (after use_the_cpus_blas_kernels, which may start the program again).
namespace eitbench {
void keep_freed_memory();
}  // namespace eitbench
