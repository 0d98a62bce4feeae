#pragma once
// Internal: EITBENCH_SANITIZED is defined when AddressSanitizer is compiled in (gcc says so with
// __SANITIZE_ADDRESS__, clang with __has_feature), and then the sanitizers' interface is included.
#if defined(__SANITIZE_ADDRESS__)
#define EITBENCH_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define EITBENCH_SANITIZED 1
#endif
#endif
#ifdef EITBENCH_SANITIZED
#include <sanitizer/common_interface_defs.h>
#endif
