// eitbench_microbench's entry point: Google Benchmark's, with the regression defaults.
#include <benchmark/benchmark.h>

#include "regression_defaults.h"

int main(int argc, char** argv) {
  std::vector<char*> args =
      eitbench::micro::with_regression_defaults(argc, argv, "eitbench_microbench.json");
  int count = static_cast<int>(args.size()) - 1;
  benchmark::Initialize(&count, args.data());
  if (benchmark::ReportUnrecognizedArguments(count, args.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
