#include "eitbench/bench/data/sensor_noise.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "eitbench/bench/data/measurements.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/random.h"

namespace eitbench {
namespace {

double median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2) return *mid;
  return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

// 1.4826 x the median absolute deviation: the standard deviation of a normal sample, and a few
// outliers (a glitch, a press caught in a reference) do not move it.
double robust_sd(const Eigen::VectorXd& x) {
  std::vector<double> v(x.data(), x.data() + x.size());
  const double m = median(v);
  for (double& e : v) e = std::abs(e - m);
  return 1.4826 * median(v);
}

double rms(const Eigen::VectorXd& v) {
  return std::sqrt(v.squaredNorm() / v.size());
}

}  // namespace

SensorNoise measure_sensor_noise(const Dataset& set, const std::string& path, int first, int last,
                                 const Eigen::VectorXd& model_reference) {
  if (set.references.rows() == 0)
    throw InputError(path, "references",
                     "the set has no reference recorded before each frame (import "
                     "--paired-reference): its noise is measured on repeated references");
  if (last - first < 3)
    throw InputError(path, "references",
                     fmt::format("frames {}:{} hold {} references; the noise needs at least 3",
                                 first, last, std::max(0, last - first)));
  const MeasurementProtocol protocol = measurement_protocol(set);
  const SampleMatrix refs = set.references.middleRows(first, last - first);
  const Eigen::VectorXd mean = refs.colwise().mean().transpose();
  const double unit = rms(mean);
  if (!(unit > 0)) throw InputError(path, "references", "the mean reference is zero");

  SensorNoise n;
  n.frames = fmt::format("{} (frames {}:{})", path, first, last);
  n.references = last - first;
  // Consecutive references' differences: a difference frame's noise, input by input.
  const Eigen::Index steps = refs.rows() - 1;
  Eigen::MatrixXd d(steps, protocol.input_size());
  for (Eigen::Index k = 0; k < steps; ++k)
    d.row(k) = protocol.to_inputs((refs.row(k + 1) - refs.row(k)).transpose()).transpose();
  n.inputs.resize(d.cols());
  for (Eigen::Index i = 0; i < d.cols(); ++i) n.inputs(i) = robust_sd(d.col(i)) / unit;
  n.noise = rms(n.inputs);
  if (!(n.noise > 0))
    throw InputError(path, "references",
                     "consecutive references are equal on most steps of every value (quantised "
                     "or copied references): there is no noise to measure");
  // An input whose references rarely move is quantised, not noiseless: as a weight, 1/0 would
  // let it alone decide the image. Its level is kept at a tenth of the median moving input's at
  // least (the median of them all is 0 where most inputs are quantised, and would floor nothing).
  std::vector<double> levels;
  for (double v : n.inputs)
    if (v > 0) levels.push_back(v);
  n.inputs = n.inputs.cwiseMax(0.1 * median(levels));
  // The drift: each channel's spread over the recording beyond one frame's noise.
  double drift2 = 0;
  for (Eigen::Index c = 0; c < refs.cols(); ++c) {
    const Eigen::VectorXd step = refs.col(c).tail(steps) - refs.col(c).head(steps);
    const double frame_var = std::pow(robust_sd(step), 2) / 2;
    const double total_var = (refs.col(c).array() - mean(c)).square().mean();
    drift2 += std::max(0.0, total_var - frame_var);
  }
  n.drift = std::sqrt(drift2 / refs.cols()) / unit;
  std::vector<double> power;
  for (int k = first; k < last; ++k) power.push_back(set.differences.row(k).squaredNorm());
  n.signal = std::sqrt(median(power) / set.differences.cols()) / unit;

  if (model_reference.size() == mean.size()) {
    const double scale = calibrate_to_model(mean, model_reference).scale;
    // A channel the model puts at exactly zero has no ratio: NaN, written as null.
    n.gains = Eigen::VectorXd::Constant(mean.size(), NAN);
    for (Eigen::Index c = 0; c < mean.size(); ++c)
      if (model_reference(c) != 0) n.gains(c) = scale * mean(c) / model_reference(c);
    const double floor = 0.1 * rms(model_reference);
    double spread2 = 0;
    int counted = 0;
    for (Eigen::Index c = 0; c < mean.size(); ++c)
      if (std::abs(model_reference(c)) > floor) spread2 += std::pow(n.gains(c) - 1, 2), ++counted;
    n.gain_spread = counted ? std::sqrt(spread2 / counted) : 0;
  }
  return n;
}

double noise_in_units_of(const SensorNoise& noise, const Eigen::VectorXd& reference) {
  return noise.noise * rms(reference);
}

void apply_sensor_noise(SampleMatrix& differences, const SensorNoise& noise,
                        const Eigen::VectorXd& model_reference, std::uint64_t seed) {
  const double sigma = noise_in_units_of(noise, model_reference);
  const bool gained = noise.gains.size() == differences.cols();
  for (Eigen::Index i = 0; i < differences.rows(); ++i) {
    RandomStream rng(seed, static_cast<std::uint64_t>(i));
    for (Eigen::Index j = 0; j < differences.cols(); ++j) {
      const double gain = gained && std::isfinite(noise.gains(j)) ? noise.gains(j) : 1.0;
      differences(i, j) = gain * differences(i, j) + sigma * rng.normal();
    }
  }
}

}  // namespace eitbench
