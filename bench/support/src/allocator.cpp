#include "eitbench/bench/support/allocator.h"

#include <malloc.h>

namespace eitbench {

void keep_freed_memory() {
  mallopt(M_MMAP_THRESHOLD, 64 << 20);  // glibc's largest: blocks under 64 MB come from the heap
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
}

}  // namespace eitbench
