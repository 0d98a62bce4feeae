#include "eitbench/bench/version.h"

namespace eitbench {
const char* program_version() {
  return "eitbench " EITBENCH_VERSION;
}
}  // namespace eitbench
