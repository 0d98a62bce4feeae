#include "eitbench/bench/support/version.h"

namespace eitbench {
const char* program_version() {
  return "eitbench " EITBENCH_VERSION;
}
}  // namespace eitbench
