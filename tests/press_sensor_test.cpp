// Fitting the simulated press to real ones: a stand-in "real" sensor, simulated on a finer mesh
// with wider electrodes and contact impedances spread 0.5x to 2x, records its presses in a frame
// turned and scaled against the model's, each press a disc whose contrast grows with its depth.
// The fit, on the coarser nominal model, recovers the turn, the scale, the disc's radius and its
// contrast per unit depth; bad input is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "eitbench/bench/io/sensor_file.h"
#include "eitbench/jacobian.h"
#include "eitbench/jacobian/constants.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/solvers.h"
#include "test_support.h"

namespace eitbench {
namespace {

struct Truth {
  double turn_degrees = 0, scale = 1, radius = 0.12, contrast_per_depth = 0.15;
};

struct SensorRecording {
  SampleMatrix differences;
  Eigen::MatrixX2d positions;  // in the recording's frame and unit
  Eigen::VectorXd depths;
};

SensorRecording stand_in(const Truth& t, int presses) {
  ForwardOptions o;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> factor(std::log(0.5), std::log(2.0));
  o.contact_impedances.resize(16);
  for (auto& z : o.contact_impedances) z = 0.01 * std::exp(factor(rng));
  const ForwardModel sensor(testing::disk(16, MeshDensity::medium, 0.6), o);
  auto inputs = [&](const std::vector<Circle>& c) {
    return sensor.inputs(sensor.solve(conductivity_from_circles(sensor.mesh(), c, 1.0)));
  };
  const Eigen::VectorXd none = inputs({});
  SensorRecording r{SampleMatrix(presses, none.size()), Eigen::MatrixX2d(presses, 2),
                    Eigen::VectorXd(presses)};
  const double a = -t.turn_degrees * kPi / 180;
  for (int i = 0; i < presses; ++i) {
    const double rho = 0.15 + 0.6 * i / presses, phi = 2.39996 * i;  // the golden angle
    const double x = rho * std::cos(phi), y = rho * std::sin(phi);
    r.depths[i] = 0.5 + (i % 5) * 0.25;
    r.differences.row(i) =
        (inputs({{x, y, t.radius, 1 - t.contrast_per_depth * r.depths[i]}}) - none).transpose();
    // Written down as p_file = R(-turn) p / scale.
    r.positions.row(i) << (std::cos(a) * x - std::sin(a) * y) / t.scale,
        (std::sin(a) * x + std::cos(a) * y) / t.scale;
  }
  return r;
}

// The fit's model: the nominal sensor on the coarse mesh.
LinearProblem nominal_problem() {
  const auto model = std::make_shared<const ForwardModel>(testing::disk(16, MeshDensity::coarse));
  return make_linear_problem(model, 1.0, PixelGrid(32, 1.0));
}

// Positions recorded turned by 37.4 degrees and scaled by 1 / 1.15.
Truth turned_and_scaled() {
  Truth t;
  t.turn_degrees = 37.4;
  t.scale = 1.15;
  return t;
}

// The frame search on a coarse grid of turns: the fit finds the rest.
PressFrame coarse_search(const LinearProblem& problem, const SensorRecording& r) {
  PressFrameOptions o;
  o.step_degrees = 5;
  return fit_press_frame(problem, r.differences, r.positions, o);
}

TEST(PressSensor, RecoversTheFrameAndTheTouchOfAStandInSensor) {
  const LinearProblem problem = nominal_problem();
  const Truth t = turned_and_scaled();
  const SensorRecording r = stand_in(t, 40);
  const PressFrame start = coarse_search(problem, r);
  const PressSensor s = fit_press_sensor(problem, r.differences, r.positions, r.depths, start);
  EXPECT_FALSE(s.mirror);
  EXPECT_TRUE(s.per_depth);
  EXPECT_NEAR(s.rotate_degrees, t.turn_degrees, 1.0);
  EXPECT_NEAR(s.scale, t.scale, 0.03 * t.scale);
  EXPECT_NEAR(s.touch_radius, t.radius, 0.15 * t.radius);
  EXPECT_NEAR(s.contrast, t.contrast_per_depth, 0.2 * t.contrast_per_depth);
  EXPECT_LT(s.relative_residual, 0.5 * s.start_residual);
  EXPECT_LT(s.relative_residual, 0.25);

  // The fit's frame takes each recorded position to where the press truly was.
  const SensorRecording truth = stand_in({}, 40);  // the same presses, recorded as they are
  double worst = 0;
  for (int i = 0; i < 40; ++i)
    worst = std::max(worst, (model_position(r.positions.row(i).transpose(), s.rotate_degrees,
                                            s.mirror, s.scale) -
                             truth.positions.row(i).transpose())
                                .norm());
  EXPECT_LT(worst, 0.03);

  // Without depths, one contrast for every press: their mean's.
  const PressSensor flat = fit_press_sensor(problem, r.differences, r.positions, {}, start);
  EXPECT_FALSE(flat.per_depth);
  EXPECT_NEAR(flat.rotate_degrees, t.turn_degrees, 1.5);
  EXPECT_GT(flat.relative_residual, s.relative_residual);
}

// A few presses the model cannot explain (a slipped probe: another press's frame, ten times
// stronger) pull a least-squares fit; the Huber loss keeps the frame.
TEST(PressSensor, AHuberLossKeepsTheFrameAgainstOutliers) {
  const LinearProblem problem = nominal_problem();
  const Truth t = turned_and_scaled();
  SensorRecording r = stand_in(t, 40);
  for (int i : {3, 17, 29}) r.differences.row(i) = 10 * r.differences.row((i + 20) % 40);
  const PressFrame start = coarse_search(problem, r);
  PressSensorOptions o;
  o.huber = 1;
  const PressSensor robust =
      fit_press_sensor(problem, r.differences, r.positions, r.depths, start, o);
  const PressSensor plain = fit_press_sensor(problem, r.differences, r.positions, r.depths, start);
  EXPECT_NEAR(robust.rotate_degrees, t.turn_degrees, 1.0);
  EXPECT_NEAR(robust.scale, t.scale, 0.03 * t.scale);
  EXPECT_NEAR(robust.contrast, t.contrast_per_depth, 0.2 * t.contrast_per_depth);
  EXPECT_GT(std::abs(plain.contrast - t.contrast_per_depth),
            std::abs(robust.contrast - t.contrast_per_depth));
}

// The map from recorded positions to the model and back are each other's inverse, the mirror
// first: R(a) M (s p).
TEST(PressSensor, ModelAndRecordedPositionsAreInverse) {
  const Eigen::Vector2d p(0.3, 0.4);
  const Eigen::Vector2d q = model_position(p, 30, true, 1.2);
  // M p = (0.3, -0.4), x 1.2 = (0.36, -0.48), turned by 30 degrees counter-clockwise.
  const double c = std::cos(kPi / 6), s = std::sin(kPi / 6);
  EXPECT_NEAR(q.x(), c * 0.36 + s * 0.48, 1e-12);
  EXPECT_NEAR(q.y(), s * 0.36 - c * 0.48, 1e-12);
  EXPECT_LT((recorded_position(q, 30, true, 1.2) - p).norm(), 1e-12);
  EXPECT_LT((recorded_position(model_position(p, 282, false, 0.76), 282, false, 0.76) - p).norm(),
            1e-12);
}

TEST(PressSensor, BadInputIsRefused) {
  const LinearProblem problem = nominal_problem();
  const SensorRecording r = stand_in({}, 4);
  const PressFrame start;
  EXPECT_EQ(testing::input_error_at([&] {
              fit_press_sensor(problem, r.differences, r.positions, r.depths.head(3), start);
            }),
            "presses.depths");
  Eigen::VectorXd negative = r.depths;
  negative[1] = -1;
  EXPECT_EQ(testing::input_error_at(
                [&] { fit_press_sensor(problem, r.differences, r.positions, negative, start); }),
            "presses.depths");
  EXPECT_EQ(testing::input_error_at([&] {
              fit_press_sensor(problem, r.differences.topRows(2), r.positions.topRows(2), {},
                               start);
            }),
            "presses.");
  PressSensorOptions o;
  o.start_radius = 0.9;
  EXPECT_EQ(testing::input_error_at(
                [&] { fit_press_sensor(problem, r.differences, r.positions, {}, start, o); }),
            "PressSensorOptions.start_radius");
}

// The press fit travels in the sensor file; a file with a bad press fit is refused, naming the
// field.
TEST(SensorFilePressFit, RoundTripsAndRefusesBadFields) {
  const auto dir = std::filesystem::temp_directory_path() / "eitbench_press_fit_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "sensor.json").string();
  SensorFile s;
  s.electrodes = 16, s.background = 0.05, s.fitted = false;
  s.contact_impedances = Eigen::VectorXd::Constant(16, 0.01);
  SensorPressFit f;
  f.presses = "cal.h5", f.rotate_degrees = 1.5, f.mirror = true, f.scale = 0.76;
  f.touch_radius = 0.27, f.contrast = 0.22, f.per_depth = true, f.gain = 6e-6;
  s.press_fit = f;
  write_sensor_file(path, s);
  const SensorFile back = read_sensor_file(path);
  ASSERT_TRUE(back.press_fit.has_value());
  EXPECT_FALSE(back.fitted);
  EXPECT_EQ(back.press_fit->presses, "cal.h5");
  EXPECT_TRUE(back.press_fit->mirror);
  EXPECT_DOUBLE_EQ(back.press_fit->scale, 0.76);
  EXPECT_DOUBLE_EQ(back.press_fit->touch_radius, 0.27);
  EXPECT_DOUBLE_EQ(back.press_fit->gain, 6e-6);
  s.press_fit->scale = -1;
  write_sensor_file(path, s);
  EXPECT_EQ(testing::input_error_at([&] { read_sensor_file(path); }), path + ".press_fit.scale");
  // A field of the wrong type is named too, not left to the JSON library.
  s.press_fit->scale = 0.76;
  write_sensor_file(path, s);
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::string flag = "\"per_depth\": true";
  const auto at = text.find(flag);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, flag.size(), "\"per_depth\": \"yes\"");
  std::ofstream(path) << text;
  EXPECT_EQ(testing::input_error_at([&] { read_sensor_file(path); }),
            path + ".press_fit.per_depth");
  std::filesystem::remove_all(dir);
}

// Only a sensor fitted to a frame replaces the forward model's impedances and current; a file of
// a press fit alone holds nominal values, and the caller's stay.
TEST(SensorFilePressFit, OnlyAFittedSensorSetsTheForwardModel) {
  SensorFile s;
  s.electrodes = 2, s.current = 3;
  s.contact_impedances = Eigen::Vector2d(0.1, 0.2);
  ForwardOptions forward;
  forward.current = 1;
  s.fitted = false;
  EXPECT_FALSE(apply_fitted_sensor(s, forward));
  EXPECT_EQ(forward.current, 1);
  EXPECT_EQ(forward.contact_impedances.size(), 0);
  s.fitted = true;
  EXPECT_TRUE(apply_fitted_sensor(s, forward));
  EXPECT_EQ(forward.current, 3);
  EXPECT_EQ(forward.contact_impedances, s.contact_impedances);
}

// A sensor file of another electrode count than the model it would calibrate is refused, naming
// the file, the field and both counts; one of the same count reads as read_sensor_file reads it.
TEST(SensorFilePressFit, AnotherElectrodeCountIsRefused) {
  const auto dir = std::filesystem::temp_directory_path() / "eitbench_sensor_count_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "sensor.json").string();
  SensorFile s;
  s.electrodes = 16, s.background = 0.05;
  s.contact_impedances = Eigen::VectorXd::Constant(16, 0.01);
  write_sensor_file(path, s);
  EXPECT_EQ(read_sensor_file(path, 16, "the mesh has").electrodes, 16);
  EXPECT_EQ(testing::input_error_at([&] { read_sensor_file(path, 32, "the mesh has"); }),
            path + ".electrodes");
  try {
    read_sensor_file(path, 32, "the data have");
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("calibrates 16 electrodes; the data have 32"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace eitbench
