// The learned reconstructor's speed (issue 6): training throughput with on-the-fly D_L
// augmentation and its GFLOP/s against this machine's single-precision GEMM, and inference latency
// for one frame and for a batch of 512. Arg 0: the small model, 1: paper.
#include <benchmark/benchmark.h>

#include <cstdlib>

#include "eitbench/augment.h"
#include "eitbench/bench/support/allocator.h"
#include "eitbench/jacobian.h"
#include "eitbench/jacobian/random.h"
#include "eitbench/learned.h"
#include "regression_defaults.h"

namespace {
using namespace eitbench;

// Random circles with their exact labels; random frames (speed does not depend on the physics).
LabelledFrames synthetic(int n, std::uint64_t seed) {
  LabelledFrames set;
  set.background = 0.05;  // the labels below are relative to 0.05
  const PixelGrid grid(64, 1.0);
  set.frames.resize(n, 104);
  set.labels.resize(n, grid.num_pixels());
  RandomStream random(seed, 0);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 104; ++k) set.frames(i, k) = random.normal();
    std::vector<Circle> circles;
    const double r = random.uniform(0.1, 0.3), a = random.uniform(0, 2 * M_PI),
                 d = random.uniform(0, 0.9 - r);
    circles.push_back({d * std::cos(a), d * std::sin(a), r, 0.01});
    set.labels.row(i) = circles_image(grid, circles, 0.05).transpose();
    set.circles.push_back(circles);
  }
  return set;
}

ModelSize size_of(const benchmark::State& state) {
  return state.range(0) == 0 ? ModelSize::small : ModelSize::paper;
}

void BM_MatmulPeak(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  double seconds = 0;
  for (auto _ : state) seconds = time_matmul(n, 5);
  state.counters["GFLOP/s"] = 2.0 * n * n * n / seconds / 1e9;
  state.counters["threads"] = torch_threads();
}

void BM_TrainingThroughput(benchmark::State& state) {
  const ModelSize size = size_of(state);
  const NetworkOptions network = NetworkOptions::preset(size, 104, 64);
  TrainingOptions options;
  options.augment = AugmentGroup::dihedral;
  options.batch_size = static_cast<int>(state.range(1));
  options.epochs = 1000000;
  const int samples = 8 * options.batch_size;  // 8 steps an epoch, and a round
  options.validate_every = samples;
  AugmentSetup sensor;
  Trainer trainer(network, options, synthetic(samples, 1), synthetic(16, 2), sensor);
  trainer.run_round();  // warm-up
  double per_second = 0;
  for (auto _ : state) per_second = trainer.run_round().samples_per_second;
  state.counters["samples/s"] = per_second;
  // A training step costs about 3 forward passes (forward, and backward's two products).
  state.counters["GFLOP/s"] = 3 * forward_flops(network) * per_second / 1e9;
}

void BM_Inference(benchmark::State& state) {
  const NetworkOptions network = NetworkOptions::preset(size_of(state), 104, 64);
  const LearnedModel model(network, 16, 1);
  const SampleMatrix frames = synthetic(static_cast<int>(state.range(1)), 3).frames;
  for (auto _ : state) benchmark::DoNotOptimize(model.reconstruct(frames).data());
  state.counters["frames/s"] = benchmark::Counter(static_cast<double>(frames.rows()),
                                                  benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK(BM_MatmulPeak)
    ->Arg(1024)
    ->Arg(2048)
    ->Arg(4096)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
// One training step's throughput: {model (0 small, 1 paper), batch}.
BENCHMARK(BM_TrainingThroughput)
    ->Args({0, 128})
    ->Args({0, 512})
    ->Args({1, 128})
    ->Args({1, 512})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);
BENCHMARK(BM_Inference)
    ->Args({0, 1})
    ->Args({0, 512})
    ->Args({1, 1})
    ->Args({1, 512})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

// LibTorch's default here is one thread (it counts what it takes for physical cores wrongly on
// this VM); the CLI's default is 2. EITBENCH_THREADS=N measures another count.
int main(int argc, char** argv) {
  eitbench::keep_freed_memory();
  const char* threads = std::getenv("EITBENCH_THREADS");
  eitbench::set_torch_threads(threads ? std::atoi(threads) : 2);
  return eitbench::micro::run_microbenchmarks(argc, argv, "eitbench_learned_bench.json");
}
