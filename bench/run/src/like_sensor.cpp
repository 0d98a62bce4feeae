// The simulation like the sensor (docs/real-presses.md#a-pick-without-labels): the simulated
// frames that hold one touch, as the real skin would give them. The noise and the channels' gains
// are measured on the calibration set's repeated references (calibrate --noise's measurement),
// never on its presses' positions nor on the scored set: what a user without a labelled press has.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/sensor_noise.h"
#include "eitbench/jacobian/error.h"
#include "stages.h"

namespace eitbench::run {
namespace {

// Frames with one touch of each half: enough that a median moves by a few hundredths of R.
constexpr Eigen::Index kFrames = 200;

// The simulated set's training samples with exactly one touch, alternately to tune on and to
// score (at most `limit` each), with their labels and the touch as a press. The presets put every
// one-touch sample in the training split; the model-based methods never see that split, and the
// learned model is no candidate of the pick for that reason.
void single_touches(const Dataset& set, Eigen::Index limit, LikeSensor& like) {
  std::vector<Eigen::Index> rows;
  for (std::size_t i = 0; i < set.circles.size() && Eigen::Index(rows.size()) < 2 * limit; ++i)
    if (set.split[i] == Split::train && set.circles[i].size() == 1)
      rows.push_back(static_cast<Eigen::Index>(i));
  const Eigen::Index n = static_cast<Eigen::Index>(rows.size());
  like.validation_frames.resize((n + 1) / 2, set.differences.cols());
  like.validation_labels.resize((n + 1) / 2, set.labels.cols());
  like.test_frames.resize(n / 2, set.differences.cols());
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index r = rows[static_cast<std::size_t>(k)];
    const Circle& c = set.circles[static_cast<std::size_t>(r)].front();
    if (k % 2 == 0) {
      like.validation_frames.row(k / 2) = set.differences.row(r);
      like.validation_labels.row(k / 2) = set.labels.row(r);
      like.validation_touches.push_back({PressTouch{c.x, c.y, c.r}});
    } else {
      like.test_frames.row(k / 2) = set.differences.row(r);
      like.test_touches.push_back({PressTouch{c.x, c.y, c.r}});
    }
  }
}

double median_rms(const SampleMatrix& frames) {
  std::vector<double> rms;
  for (Eigen::Index i = 0; i < frames.rows(); ++i)
    rms.push_back(frames.row(i).norm() / std::sqrt(double(frames.cols())));
  if (rms.empty()) return NAN;
  std::nth_element(rms.begin(), rms.begin() + std::ptrdiff_t(rms.size() / 2), rms.end());
  return rms[rms.size() / 2];
}

// GCV's estimate of the real frames' noise (Tikhonov::noise_estimate) with the identity prior:
// their misfit to the linear model at the lambda GCV takes, the model's error with the noise.
double frames_misfit(const std::shared_ptr<const LinearProblem>& problem,
                     const SampleMatrix& frames) {
  TikhonovOptions o;
  o.prior = Prior::identity;
  o.choice = Criterion::gcv;
  Tikhonov t(problem, o);
  t.fit(frames, SampleMatrix(), nullptr);
  return t.noise_estimate(frames);
}

}  // namespace

std::optional<LikeSensor> like_sensor(const Context& context, const RunData& data,
                                      const std::shared_ptr<const LinearProblem>& problem,
                                      const SampleMatrix& cal_frames) {
  const RunConfig& config = context.config;
  const Dataset cal = read_dataset(config.press_calibration);
  if (cal.references.rows() == 0) {
    context.say(
        "simulation like the sensor: skipped (the calibration set has no reference before each "
        "press: import it with --paired-reference)");
    return std::nullopt;
  }
  const Eigen::VectorXd& model_reference = data.source.reference;
  LikeSensor like;
  try {
    like.noise = measure_sensor_noise(cal, config.press_calibration, 0,
                                      static_cast<int>(cal.references.rows()), model_reference);
  } catch (const InputError& e) {
    context.say(std::string("simulation like the sensor: skipped (") + e.what() + ")");
    return std::nullopt;
  }
  single_touches(data.source, kFrames, like);
  if (like.test_frames.rows() == 0) {
    context.say("simulation like the sensor: skipped (the simulated set has no one-touch frame)");
    return std::nullopt;
  }
  const double unit = model_reference.norm() / std::sqrt(double(model_reference.size()));
  like.misfit = frames_misfit(problem, cal_frames) / unit;
  // A set simulated with --sensor-noise is like the sensor already; the others get streams of
  // their own, apart from the SNR copies' (noisy_copies).
  if (!config.variation.like_sensor()) {
    apply_sensor_noise(like.validation_frames, like.noise, model_reference, config.seed ^ 0x11e5e);
    apply_sensor_noise(like.test_frames, like.noise, model_reference, config.seed ^ 0x7e57);
  }
  like.signal = median_rms(like.test_frames) / unit;
  context.say(fmt::format(
      "simulation like the sensor: {} frames with one touch to tune on and {} to score, with {} "
      "channel gains (spread {:.2f}) and noise ({:.3g} % of the reference's RMS; its frames' "
      "misfit to the model, GCV's estimate, is {:.3g} %); their signal {:.3g} %, the real "
      "frames' {:.3g} %",
      like.validation_frames.rows(), like.test_frames.rows(),
      config.variation.like_sensor() ? "--sensor-noise's" : "the calibration set's",
      like.noise.gain_spread, 100 * like.noise.noise, 100 * like.misfit, 100 * like.signal,
      100 * like.noise.signal));
  return like;
}

double like_sensor_median(const Reconstructor& method, const PixelGrid& grid,
                          const LikeSensor& like, const PressRule& rule) {
  const SampleMatrix images = method.reconstruct_all(like.test_frames);
  std::vector<Eigen::Vector2d> at;
  for (const auto& found : press_touches(images, grid, rule))
    at.push_back(located_press(found, Eigen::Vector2d::Zero()));
  return score_positions(at, like.test_touches).median;
}

}  // namespace eitbench::run
