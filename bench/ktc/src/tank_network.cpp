#include "eitbench/bench/ktc/tank_network.h"

#include <cmath>
#include <random>

#include "eitbench/bench/ktc/tank_augmentation.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/learned/trainer.h"

namespace eitbench {
namespace {

constexpr int kLevels = 7;

// Frames as the network takes them: a missing value (NaN) is given as 0, no change, in training
// and in use alike.
SampleMatrix zero_missing(const SampleMatrix& frames) {
  return frames.unaryExpr([](double v) { return std::isfinite(v) ? v : 0.0; });
}

}  // namespace

void KtcNetworkOptions::validate() const {
  const auto fail = [](const std::string& field, const std::string& message) {
    throw InputError("KtcNetworkOptions", field, message);
  };
  if (steps < 1) fail("steps", "must be at least 1");
  if (batch_size < 2) fail("batch_size", "must be at least 2");
  if (!(learning_rate > 0) || !std::isfinite(learning_rate))
    fail("learning_rate", "must be positive");
  if (validate_every < 1) fail("validate_every", "must be at least 1");
  if (patience < 0) fail("patience", "must not be negative");
  if (!(threshold > 0 && threshold < 1)) fail("threshold", "must lie in (0, 1)");
}

LabelledFrames ktc_level_frames(const KtcSimulatedSet& tanks, const CurrentPatterns& patterns,
                                bool group, std::uint64_t seed) {
  const KtcSimulatedSet set =
      group ? augment_ktc_set(tanks, patterns, ktc_group(patterns), {}) : tanks;
  const auto n = static_cast<Eigen::Index>(set.labels.size());
  if (n == 0 || set.frames.rows() != n)
    throw InputError("KtcSimulatedSet", "labels", "one label image a frame, at least one");
  const Eigen::Index grid = set.labels[0].rows();
  LabelledFrames out;
  out.frames.resize(n, set.frames.cols());
  out.labels.resize(n, grid * grid);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> level(1, kLevels);
  for (Eigen::Index k = 0; k < n; ++k) {
    out.frames.row(k) = ktc_level_frame(set.frames.row(k).transpose(), patterns, level(rng));
    for (Eigen::Index i = 0; i < grid; ++i)
      for (Eigen::Index j = 0; j < grid; ++j) {
        const int c = set.labels[k](i, j);
        out.labels(k, i * grid + j) = c == 2 ? 1.0 : c == 1 ? -1.0 : 0.0;
      }
  }
  return out;
}

LabelledFrames ktc_network_frames(const KtcSimulatedSet& tanks, const CurrentPatterns& patterns,
                                  bool group, std::uint64_t seed) {
  LabelledFrames out = ktc_level_frames(tanks, patterns, group, seed);
  out.frames = zero_missing(out.frames);
  return out;
}

AugmentSetup ktc_network_setup(const CurrentPatterns& patterns, int grid) {
  AugmentSetup setup;
  setup.group = AugmentGroup::none;
  setup.electrodes = patterns.electrodes();
  setup.image_size = grid;
  setup.protocol = std::make_shared<MeasurementProtocol>("ktc", patterns);
  return setup;
}

NetworkOptions ktc_network_options(const KtcNetworkOptions& o, int inputs, int grid) {
  return NetworkOptions::preset(o.size, inputs, grid);
}

TrainingOptions ktc_training_options(const KtcNetworkOptions& o) {
  TrainingOptions training;
  training.steps = o.steps;
  training.batch_size = o.batch_size;
  training.learning_rate = o.learning_rate;
  training.validate_every = o.validate_every;
  training.seed = o.seed;
  training.patience = o.patience;
  training.device = o.device;
  return training;
}

LearnedModel train_ktc_network(const KtcSimulatedSet& train, const KtcSimulatedSet& validation,
                               const CurrentPatterns& patterns, const KtcNetworkOptions& o) {
  o.validate();
  const LabelledFrames t = ktc_network_frames(train, patterns, o.group, o.seed);
  const LabelledFrames v = ktc_network_frames(validation, patterns, false, o.seed + 1);
  const int grid = static_cast<int>(train.labels.at(0).rows());
  Trainer trainer(ktc_network_options(o, static_cast<int>(t.frames.cols()), grid),
                  ktc_training_options(o), t, v, ktc_network_setup(patterns, grid));
  while (!trainer.done()) trainer.run_round();
  return trainer.best_model();
}

ClassImage ktc_network_classes(const LearnedModel& model, const Eigen::VectorXd& change,
                               double threshold) {
  return ktc_output_classes(model.reconstruct(zero_missing(change.transpose())).row(0).transpose(),
                            threshold);
}

ClassImage ktc_output_classes(const Eigen::VectorXd& output, double threshold) {
  const int n = static_cast<int>(std::lround(std::sqrt(static_cast<double>(output.size()))));
  ClassImage out = ClassImage::Zero(kKtcImageSize, kKtcImageSize);
  for (int i = 0; i < kKtcImageSize; ++i)
    for (int j = 0; j < kKtcImageSize; ++j) {  // the pixel of the network's grid under (i, j)
      const double x = output((i * n / kKtcImageSize) * n + j * n / kKtcImageSize);
      out(i, j) = x >= threshold ? 2 : x <= -threshold ? 1 : 0;
    }
  return out;
}

}  // namespace eitbench
