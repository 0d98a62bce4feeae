// A benchmark run's results.json, as compare reads it.
#include "eitbench/bench/report/results.h"
#include "fuzz_target.h"

EITBENCH_FUZZ_TARGET(eitbench::parse_results_json(bytes, "fuzz.json"))
