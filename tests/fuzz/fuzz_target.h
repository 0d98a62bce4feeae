#pragma once
// libFuzzer targets: each feeds its input to one parser. Bad input must end in InputError (the
// program's "message, exit 2"); anything else escaping — another exception, a crash, a sanitizer
// report — is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "eitbench/jacobian/error.h"

#define EITBENCH_FUZZ_TARGET(body)                                                    \
  extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { \
    const std::string bytes(reinterpret_cast<const char*>(data), size);               \
    try {                                                                             \
      body;                                                                           \
    } catch (const eitbench::InputError&) {                                           \
    }                                                                                 \
    return 0;                                                                         \
  }
