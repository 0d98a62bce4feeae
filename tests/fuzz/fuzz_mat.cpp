// MATLAB v5 .mat (compressed or not) through the importer's reader.
#include "eitbench/bench/io/matlab.h"
#include "fuzz_target.h"

EITBENCH_FUZZ_TARGET(eitbench::detail::read_mat_v5(bytes, "fuzz.mat"))
