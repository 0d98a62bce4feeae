// Augmentation speed: expanding a data set by D_16 (32x), and the per-sample cost of on-the-fly
// augmentation, which must stay under 5 % of a training step (the CPU presets train at about
// 1,000 samples/s, so the budget is 50 us a sample).
#include <benchmark/benchmark.h>

#include <random>

#include "eitbench/augment.h"

namespace {
using namespace eitbench;

LabelledFrames random_set(int n, bool circles) {
  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> pos(-0.45, 0.45), radius(0.05, 0.25), cond(0.0001, 0.05);
  const PixelGrid grid(64, 1.0);
  LabelledFrames set;
  set.background = 0.05;  // the labels below are relative to 0.05
  set.frames.resize(n, 104);
  for (auto& x : set.frames.reshaped()) x = normal(rng);
  set.labels.resize(n, 4096);
  for (int i = 0; i < n; ++i) {
    std::vector<Circle> touch;
    for (int k = 0; k < 1 + i % 3; ++k)
      touch.push_back({pos(rng), pos(rng), radius(rng), cond(rng)});
    set.labels.row(i) = circles_image(grid, touch, 0.05).transpose();
    if (circles) set.circles.push_back(touch);
  }
  return set;
}

// Frames only: the paper's 21,833 training frames to 698,656.
void BM_ExpandFrames_21833x32(benchmark::State& state) {
  LabelledFrames set = random_set(1, false);
  std::mt19937 rng(2);
  std::normal_distribution<double> normal;
  set.frames.resize(21833, 104);
  for (auto& x : set.frames.reshaped()) x = normal(rng);
  set.labels.resize(0, 0);
  AugmentSetup setup;
  for (auto _ : state) benchmark::DoNotOptimize(expand_by_group(set, setup).frames.data());
  state.SetItemsProcessed(state.iterations() * 21833 * 32);
}

// Frames and labels; arg 1: labels re-rasterised from circles, 0: bilinear. Per augmented sample.
void BM_ExpandFramesAndLabels(benchmark::State& state) {
  const LabelledFrames set = random_set(200, state.range(0) == 1);
  AugmentSetup setup;
  for (auto _ : state) benchmark::DoNotOptimize(expand_by_group(set, setup).labels.data());
  state.SetItemsProcessed(state.iterations() * 200 * 32);
  state.SetLabel(state.range(0) ? "exact labels (circles)" : "bilinear labels");
}

// One training batch of 512 drawn on the fly.
void BM_OnTheFlyBatch512(benchmark::State& state) {
  AugmentSetup setup;
  const OnTheFlyAugmenter augmenter(
      std::make_shared<const LabelledFrames>(random_set(2048, state.range(0) == 1)), setup, 7);
  std::vector<int> indices(512);
  for (int i = 0; i < 512; ++i) indices[i] = (i * 37) % 2048;
  SampleMatrix frames, labels;
  int epoch = 0;
  for (auto _ : state) {
    augmenter.batch(indices, epoch++, frames, labels);
    benchmark::DoNotOptimize(labels.data());
  }
  state.SetItemsProcessed(state.iterations() * 512);
  state.SetLabel(state.range(0) ? "exact labels (circles)" : "bilinear labels");
}

BENCHMARK(BM_ExpandFrames_21833x32)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ExpandFramesAndLabels)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OnTheFlyBatch512)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
