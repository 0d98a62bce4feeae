// Calibration: the background conductivity and each electrode's contact impedance recovered from
// the empty sensor's frame that they simulate.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "eitbench/bench/data/noise.h"
#include "eitbench/jacobian.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/solvers/calibration.h"
#include "test_support.h"

namespace eitbench {
namespace {

struct Sensor {
  double background = 0.05;
  Eigen::VectorXd impedances;
};

// Impedances drawn per electrode between 0.5x and 2x the nominal 0.01 (log-uniform).
Sensor drawn_sensor(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> factor(std::log(0.5), std::log(2.0));
  Sensor s;
  s.impedances.resize(16);
  for (int e = 0; e < 16; ++e) s.impedances[e] = 0.01 * std::exp(factor(rng));
  return s;
}

Eigen::VectorXd empty_frame(const Mesh& mesh, const Sensor& s) {
  ForwardOptions o;
  o.contact_impedances = s.impedances;
  return ForwardModel(mesh, o).frame(Eigen::VectorXd::Constant(mesh.num_triangles(), s.background),
                                     MeasurementOrder::rotating);
}

double worst_ratio(const Eigen::VectorXd& fitted, const Eigen::VectorXd& truth) {
  return (fitted.array() / truth.array() - 1).abs().maxCoeff();
}

TEST(ContactCalibration, RecoversImpedancesAndBackgroundFromTheirFrame) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  const Sensor truth = drawn_sensor(3);
  const Eigen::VectorXd frame = empty_frame(mesh, truth);
  // Start from the nominal sensor, the background off by 2x.
  const Calibration c = calibrate(mesh, {}, 0.1, frame, MeasurementOrder::rotating);
  std::printf("noise-free: background %.3g %%, worst impedance %.3g %%, %d iterations\n",
              100 * std::abs(c.background / truth.background - 1),
              100 * worst_ratio(c.contact_impedances, truth.impedances), c.iterations);
  EXPECT_LT(std::abs(c.background / truth.background - 1), 1e-6);
  EXPECT_LT(worst_ratio(c.contact_impedances, truth.impedances), 1e-3);
  EXPECT_LT(c.relative_residual, 1e-8);
}

// At 50 dB (white noise relative to the frame's mean power), on five drawn sensors: how close
// the fit comes is printed, and the background must be within 1 %.
TEST(ContactCalibration, At50dB) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const Sensor truth = drawn_sensor(seed);
    SampleMatrix frame = empty_frame(mesh, truth).transpose();
    add_noise(frame, 50, seed);
    const Calibration c =
        calibrate(mesh, {}, 0.1, frame.row(0).transpose(), MeasurementOrder::rotating);
    std::printf("50 dB, sensor %u: background %.3f %%, worst impedance %.1f %%\n", seed,
                100 * std::abs(c.background / truth.background - 1),
                100 * worst_ratio(c.contact_impedances, truth.impedances));
    EXPECT_LT(std::abs(c.background / truth.background - 1), 0.01) << "sensor " << seed;
  }
}

TEST(ContactCalibration, BadReferenceIsRefused) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  EXPECT_THROW(calibrate(mesh, {}, 1, Eigen::VectorXd::Ones(207), MeasurementOrder::rotating),
               InputError);
  Eigen::VectorXd nan = Eigen::VectorXd::Ones(208);
  nan[3] = NAN;
  EXPECT_THROW(calibrate(mesh, {}, 1, nan, MeasurementOrder::rotating), InputError);
  EXPECT_THROW(calibrate(mesh, {}, -1, Eigen::VectorXd::Ones(208), MeasurementOrder::rotating),
               InputError);
  CalibrationOptions bad;
  bad.max_factor = 1;
  EXPECT_THROW(calibrate(mesh, {}, 1, Eigen::VectorXd::Ones(208), MeasurementOrder::rotating, bad),
               InputError);
}

}  // namespace
}  // namespace eitbench
