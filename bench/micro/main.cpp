// eitbench_microbench's entry point: Google Benchmark's, with the regression defaults.
#include "regression_defaults.h"

int main(int argc, char** argv) {
  return eitbench::micro::run_microbenchmarks(argc, argv, "eitbench_microbench.json");
}
