// NumPy .npz (zip, stored or deflated, zip64) through the importer's reader.
#include "eitbench/bench/io/numpy.h"
#include "fuzz_target.h"

EITBENCH_FUZZ_TARGET(eitbench::detail::read_npz(bytes, "fuzz.npz"))
