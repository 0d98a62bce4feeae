// Frames as CSV through read_frames_csv.
#include <sstream>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/csv.h"
#include "fuzz_target.h"

EITBENCH_FUZZ_TARGET({
  std::istringstream in(bytes);
  eitbench::read_frames_csv(in, "fuzz.csv");
})
