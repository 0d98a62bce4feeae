// NumPy .npy through the importer's reader.
#include "eitbench/bench/io/numpy.h"
#include "fuzz_target.h"

EITBENCH_FUZZ_TARGET(eitbench::detail::read_npy(bytes, "fuzz.npy", ""))
