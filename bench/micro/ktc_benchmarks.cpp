// One KTC reconstruction scored under every segmentation rule a run tunes (3-class Otsu and 19
// threshold fractions a class): what a KTC run spends most of its time on, once for every
// candidate, level and sample or tuning tank.
#include <benchmark/benchmark.h>

#include <cmath>

#include "eitbench/bench/ktc/ktc_run.h"

namespace {
using namespace eitbench;

// A smooth image with a resistive and a conductive blob, and a truth with a target near each.
struct KtcScoreFixture {
  Eigen::MatrixXd image{kKtcImageSize, kKtcImageSize};
  ClassImage truth = ClassImage::Zero(kKtcImageSize, kKtcImageSize);

  KtcScoreFixture() {
    for (int i = 0; i < kKtcImageSize; ++i)
      for (int j = 0; j < kKtcImageSize; ++j) {
        image(i, j) = std::exp(-std::hypot(i - 70, j - 90) / 30.0) -
                      0.8 * std::exp(-std::hypot(i - 180, j - 170) / 40.0);
        if (std::hypot(i - 75, j - 95) < 30) truth(i, j) = 1;
        if (std::hypot(i - 175, j - 165) < 35) truth(i, j) = 2;
      }
  }
};

void BM_KtcScoreEveryRule(benchmark::State& state) {
  static const KtcScoreFixture f;
  const KtcScorer scorer(f.truth);
  KtcFrameScores s;
  for (auto _ : state) benchmark::DoNotOptimize((s = score_every_rule(f.image, scorer)).otsu);
  // Otsu's two classes and each fraction's two.
  state.counters["masks"] = static_cast<double>(2 + s.resistive.size() + s.conductive.size());
}

BENCHMARK(BM_KtcScoreEveryRule)->Unit(benchmark::kMillisecond);

}  // namespace
