// A microbenchmark with a deliberate slowdown, for compare's tests: BM_Work does a fixed chain of
// dependent floating-point operations, EITBENCH_SLOWDOWN (a fraction, 0.2: 20 %) more of them when
// that is set. Its JSON is what eitbench_microbench writes.
#include <benchmark/benchmark.h>

#include <cstdlib>

namespace {

void BM_Work(benchmark::State& state) {
  const char* slowdown = std::getenv("EITBENCH_SLOWDOWN");
  const long steps = static_cast<long>(200000 * (1 + (slowdown ? std::atof(slowdown) : 0.0)));
  for (auto _ : state) {
    double x = 1.0;
    for (long k = 0; k < steps; ++k) x = x * 0.999999 + 1e-7;  // each step waits for the last
    benchmark::DoNotOptimize(x);
  }
}
BENCHMARK(BM_Work)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
