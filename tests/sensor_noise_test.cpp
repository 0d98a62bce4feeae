// The sensor's noise measured on unlabelled frames (calibrate --noise) against a recording whose
// noise, drift, gains and signal were drawn by the test: each level must come back.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <utility>
#include <vector>

#include "eitbench/bench/data/sensor_noise.h"
#include "eitbench/bench/io/sensor_file.h"
#include "eitbench/jacobian/error.h"
#include "test_support.h"

namespace eitbench {
namespace {

struct NoiseRecording {
  Dataset set;
  Eigen::VectorXd base;   // the untouched sensor's frame, without noise or drift
  double sigma = 0;       // each channel's noise, one frame
  double drift_rms = 0;   // each channel's drift, RMS over the recording
  double signal_rms = 0;  // each difference frame's RMS
};

// N references of the adjacent protocol: base + a linear drift from -a to a on every channel +
// white noise; each difference frame is a fixed pattern of RMS `signal` plus the noise of two
// frames (its own and its reference's), as a pressed frame minus its reference has.
NoiseRecording recording(int n, double sigma, double drift, double signal, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  NoiseRecording r;
  r.set.electrodes = 16;
  const MeasurementProtocol protocol = measurement_protocol(r.set);
  const int c = protocol.size();
  r.base = Eigen::VectorXd::Constant(c, 1.0);
  for (int k = 0; k < c; ++k) r.base(k) += 0.5 * std::sin(0.7 * k);
  r.sigma = sigma, r.drift_rms = drift / std::sqrt(3.0), r.signal_rms = signal;
  r.set.references.resize(n, c);
  r.set.differences.resize(n, protocol.input_size());
  Eigen::VectorXd pattern(protocol.input_size());
  for (Eigen::Index i = 0; i < pattern.size(); ++i) pattern(i) = std::cos(0.3 * i) + 0.2;
  pattern *= signal / std::sqrt(pattern.squaredNorm() / pattern.size());
  for (int f = 0; f < n; ++f) {
    const double ramp = drift * (2.0 * f / (n - 1) - 1);
    for (int k = 0; k < c; ++k) r.set.references(f, k) = r.base(k) + ramp + sigma * normal(rng);
    Eigen::VectorXd noise(c);
    for (int k = 0; k < c; ++k) noise(k) = sigma * std::sqrt(2.0) * normal(rng);
    r.set.differences.row(f) = (pattern + protocol.to_inputs(noise)).transpose();
  }
  r.set.frames = r.set.references;
  r.set.reference = r.set.references.colwise().mean().transpose();
  return r;
}

double rms(const Eigen::VectorXd& v) {
  return std::sqrt(v.squaredNorm() / v.size());
}

TEST(SensorNoise, RecoversTheNoiseTheDriftAndTheSignalOfARecording) {
  const NoiseRecording r = recording(600, 0.01, 0.05, 0.1, 1);
  const SensorNoise n = measure_sensor_noise(r.set, "rec.h5", 0, 600, Eigen::VectorXd());
  const double unit = rms(r.set.reference);
  EXPECT_EQ(n.references, 600);
  // A difference frame's noise is two frames': sqrt(2) sigma on every input.
  EXPECT_NEAR(n.noise * unit / (std::sqrt(2.0) * r.sigma), 1, 0.03);
  EXPECT_NEAR(n.drift * unit / r.drift_rms, 1, 0.05);
  // The differences carry the noise too: their RMS is sqrt(signal^2 + 2 sigma^2).
  EXPECT_NEAR(n.signal * unit / std::hypot(r.signal_rms, std::sqrt(2.0) * r.sigma), 1, 0.01);
  EXPECT_NEAR(n.snr_db(),
              20 * std::log10(std::hypot(r.signal_rms, std::sqrt(2.0) * r.sigma) /
                              (std::sqrt(2.0) * r.sigma)),
              0.3);
  EXPECT_EQ(n.gains.size(), 0);  // no model given
}

// Each input has its own level, of which the noise is the RMS: a channel whose references wander
// ten times as much stands out by that factor, and a channel whose references never move (a
// quantised one) is held at a tenth of the median input's level rather than at zero: as a weight,
// one over zero would let it alone decide the image.
TEST(SensorNoise, EachInputHasItsOwnLevel) {
  NoiseRecording r = recording(600, 0.01, 0, 0.1, 6);
  const MeasurementProtocol protocol = measurement_protocol(r.set);
  // Raw channels that are inputs: a unit on the channel shows up in exactly one input.
  std::vector<std::pair<int, int>> channel_input;
  for (int c = 0; c < protocol.size() && channel_input.size() < 2; ++c) {
    const Eigen::VectorXd in = protocol.to_inputs(Eigen::VectorXd::Unit(protocol.size(), c));
    Eigen::Index j = 0;
    if (in.cwiseAbs().maxCoeff(&j) == 1) channel_input.emplace_back(c, static_cast<int>(j));
  }
  ASSERT_EQ(channel_input.size(), 2u);
  const auto [noisy, noisy_input] = channel_input[0];
  const auto [still, still_input] = channel_input[1];
  std::mt19937 rng(9);
  std::normal_distribution<double> extra(0, std::sqrt(99.0) * r.sigma);  // sqrt(1 + 99) = 10
  for (Eigen::Index f = 0; f < r.set.references.rows(); ++f)
    r.set.references(f, noisy) += extra(rng);
  r.set.references.col(still).setConstant(1.0);
  const SensorNoise n = measure_sensor_noise(r.set, "rec.h5", 0, 600, {});
  ASSERT_EQ(n.inputs.size(), protocol.input_size());
  const double unit = rms(r.set.references.colwise().mean().transpose());
  EXPECT_NEAR(n.inputs(noisy_input) * unit / (std::sqrt(2.0) * 10 * r.sigma), 1, 0.1);
  std::vector<double> levels(n.inputs.data(), n.inputs.data() + n.inputs.size());
  std::nth_element(levels.begin(), levels.begin() + levels.size() / 2, levels.end());
  const double median = levels[levels.size() / 2];
  EXPECT_NEAR(median * unit / (std::sqrt(2.0) * r.sigma), 1, 0.05);
  EXPECT_NEAR(n.inputs(still_input) / median, 0.1, 0.01);
  // The noise is the RMS of the levels as measured, before the quantised input's floor.
  const double measured = n.inputs.squaredNorm() - std::pow(n.inputs(still_input), 2);
  EXPECT_NEAR(n.noise, std::sqrt(measured / n.inputs.size()), 1e-15);
}

// References quantised on most channels (a coarse converter: most values never move): the
// floor is a tenth of the moving inputs' median, so no level is 0 and the sensor file that
// calibrate writes reads back (a level of 0 is refused there).
TEST(SensorNoise, MostlyQuantisedReferencesKeepEveryLevelPositive) {
  NoiseRecording r = recording(600, 0.01, 0, 0.1, 6);
  const Eigen::Index channels = r.set.references.cols();
  for (Eigen::Index c = 0; c < channels; ++c)
    if (c % 4 != 0) r.set.references.col(c).setConstant(r.base[c]);
  const SensorNoise n = measure_sensor_noise(r.set, "rec.h5", 0, 600, {});
  ASSERT_GT(n.noise, 0);
  ASSERT_GT((n.inputs.array() == n.inputs.minCoeff()).count(), n.inputs.size() / 2)
      << "most inputs quantised";
  EXPECT_GT(n.inputs.minCoeff(), 0);
  const auto dir = std::filesystem::temp_directory_path() / "eitbench_sensor_noise_quantised";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "sensor.json").string();
  SensorFile s;
  s.electrodes = 16, s.background = 1, s.contact_impedances = Eigen::VectorXd::Constant(16, 0.01);
  s.noise = n;
  write_sensor_file(path, s);
  EXPECT_EQ(read_sensor_file(path).noise->inputs, n.inputs);
}

TEST(SensorNoise, AGlitchInAReferenceDoesNotSetTheNoise) {
  NoiseRecording r = recording(600, 0.01, 0, 0.1, 2);
  const double clean = measure_sensor_noise(r.set, "rec.h5", 0, 600, {}).noise;
  r.set.references.row(300) *= 1.5;  // one reference caught mid-press
  const double glitched = measure_sensor_noise(r.set, "rec.h5", 0, 600, {}).noise;
  EXPECT_NEAR(glitched / clean, 1, 0.02);
}

TEST(SensorNoise, TheGainsAreEachChannelsRatioToTheModel) {
  NoiseRecording r = recording(50, 1e-9, 0, 0.1, 3);  // nearly noise-free: the mean is the base
  Eigen::VectorXd gain(r.base.size());
  for (Eigen::Index k = 0; k < gain.size(); ++k) gain(k) = 1 + 0.1 * std::cos(1.3 * k);
  const Eigen::VectorXd model = 3.0 * r.base.cwiseQuotient(gain);  // other units, other gains
  const SensorNoise n = measure_sensor_noise(r.set, "rec.h5", 0, 50, model);
  ASSERT_EQ(n.gains.size(), gain.size());
  // Up to the common scale the fit chooses, each channel's gain comes back.
  const Eigen::VectorXd ratio = n.gains.cwiseQuotient(gain);
  EXPECT_LT((ratio.array() - ratio.mean()).abs().maxCoeff(), 1e-8);
  EXPECT_NEAR(ratio.mean(), 1, 0.01);
  EXPECT_GT(n.gain_spread, 0.05);
}

TEST(SensorNoise, TheLevelsFollowTheFramesUnits) {
  const NoiseRecording r = recording(100, 0.01, 0, 0.1, 4);
  const SensorNoise n = measure_sensor_noise(r.set, "rec.h5", 0, 100, {});
  NoiseRecording scaled = r;
  scaled.set.references *= 7, scaled.set.differences *= 7, scaled.set.reference *= 7;
  const SensorNoise m = measure_sensor_noise(scaled.set, "rec.h5", 0, 100, {});
  EXPECT_NEAR(m.noise / n.noise, 1, 1e-12);  // relative to the reference: no unit
  // Back in the frames' units: a difference frame's noise as drawn, sqrt(2) sigma, in each unit.
  EXPECT_NEAR(noise_in_units_of(n, r.set.reference) / (std::sqrt(2.0) * r.sigma), 1, 0.05);
  EXPECT_NEAR(noise_in_units_of(m, scaled.set.reference) / (7 * std::sqrt(2.0) * r.sigma), 1, 0.05);
}

TEST(SensorNoise, ASetWithoutPairedReferencesOrTooFewIsRefused) {
  using testing::input_error_at;
  NoiseRecording r = recording(10, 0.01, 0, 0.1, 5);
  EXPECT_EQ(input_error_at([&] { measure_sensor_noise(r.set, "rec.h5", 4, 6, {}); }),
            "rec.h5.references");
  // Equal references (copied, or quantised coarser than the noise) show no noise to measure.
  NoiseRecording copied = recording(10, 0, 0, 0.1, 5);
  EXPECT_EQ(input_error_at([&] { measure_sensor_noise(copied.set, "rec.h5", 0, 10, {}); }),
            "rec.h5.references");
  r.set.references.resize(0, r.set.references.cols());
  EXPECT_EQ(input_error_at([&] { measure_sensor_noise(r.set, "rec.h5", 0, 10, {}); }),
            "rec.h5.references");
}

TEST(SensorNoise, TheSensorFileKeepsItAndRefusesANegativeLevel) {
  const auto dir = std::filesystem::temp_directory_path() / "eitbench_sensor_noise_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "sensor.json").string();
  SensorFile s;
  s.electrodes = 16, s.background = 1, s.contact_impedances = Eigen::VectorXd::Constant(16, 0.01);
  SensorNoise n;
  n.frames = "rec.h5 (frames 0:500)", n.references = 500;
  n.noise = 0.002, n.drift = 0.01, n.signal = 0.02, n.gain_spread = 0.3;
  n.gains = Eigen::VectorXd::LinSpaced(192, 0.5, 1.5);
  n.inputs = Eigen::VectorXd::LinSpaced(192, 0.001, 0.003);
  s.noise = n;
  write_sensor_file(path, s);
  const SensorFile back = read_sensor_file(path);
  ASSERT_TRUE(back.noise.has_value());
  EXPECT_EQ(back.noise->frames, n.frames);
  EXPECT_EQ(back.noise->references, 500);
  EXPECT_DOUBLE_EQ(back.noise->noise, 0.002);
  EXPECT_DOUBLE_EQ(back.noise->drift, 0.01);
  EXPECT_NEAR(back.noise->snr_db(), 20, 1e-9);
  EXPECT_EQ(back.noise->gains, n.gains);
  EXPECT_EQ(back.noise->inputs, n.inputs);
  s.noise->inputs(7) = 0;  // a weight of 1/0
  write_sensor_file(path, s);
  EXPECT_EQ(testing::input_error_at([&] { read_sensor_file(path); }), path + ".noise.inputs");
  s.noise->inputs.resize(0);  // files written before: no level per input
  write_sensor_file(path, s);
  EXPECT_EQ(read_sensor_file(path).noise->inputs.size(), 0);
  s.noise->noise = -1;
  write_sensor_file(path, s);
  EXPECT_EQ(testing::input_error_at([&] { read_sensor_file(path); }), path + ".noise.noise");
  std::filesystem::remove_all(dir);
}

// The simulation like the sensor draws its frames with apply_sensor_noise: each value times its
// channel's gain (1 where there is none), plus white noise at the measured level in the units of
// the model's reference; each row from its own stream.
TEST(SensorNoise, SimulatedFramesGetTheMeasuredGainsAndNoise) {
  const int rows = 400, cols = 12;
  SampleMatrix frames(rows, cols);
  for (Eigen::Index i = 0; i < frames.size(); ++i) frames.data()[i] = std::sin(0.37 * i);
  Eigen::VectorXd reference = Eigen::VectorXd::Constant(cols, 2.0);  // RMS 2
  SensorNoise n;
  n.gains = Eigen::VectorXd::LinSpaced(cols, 0.5, 1.5);
  n.gains(3) = NAN;  // a channel the model puts at zero: no gain
  SampleMatrix gained = frames;
  apply_sensor_noise(gained, n, reference, 1);  // noise 0: the gains alone
  for (int j = 0; j < cols; ++j) {
    const double g = j == 3 ? 1.0 : n.gains(j);
    EXPECT_TRUE(gained.col(j).isApprox(g * frames.col(j))) << j;
  }
  n.noise = 0.01;  // of the reference's RMS: 0.02 in the frames' units
  SampleMatrix noisy = frames;
  apply_sensor_noise(noisy, n, reference, 1);
  const double rms = std::sqrt((noisy - gained).squaredNorm() / double(noisy.size()));
  EXPECT_NEAR(rms, 0.02, 0.02 * 0.05);
  SampleMatrix first = frames.topRows(5);
  apply_sensor_noise(first, n, reference, 1);
  EXPECT_EQ(first, noisy.topRows(5));  // row i's noise does not depend on the others
  SampleMatrix other = frames;
  apply_sensor_noise(other, n, reference, 2);
  EXPECT_NE(other, noisy);
  n.gains.resize(cols + 1);  // another protocol's channels: no gains at all
  n.gains.setConstant(3.0);
  SampleMatrix ungained = frames;
  n.noise = 0;
  apply_sensor_noise(ungained, n, reference, 1);
  EXPECT_EQ(ungained, frames);
}

}  // namespace
}  // namespace eitbench
