// The frame of recorded press positions: a stand-in recording whose positions were written in a
// turned and mirrored frame, its frames simulated by the FEM, has that turn and mirror recovered
// from its changes alone; bad input is refused.
#include <gtest/gtest.h>

#include <cmath>

#include "eitbench/jacobian.h"
#include "eitbench/jacobian/constants.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/solvers.h"
#include "test_support.h"

namespace eitbench {
namespace {

struct PressRecording {
  SampleMatrix differences;
  Eigen::MatrixX2d positions;  // in the recording's own frame
};

// Presses on a spiral, simulated where they truly are, written down as p_file = M R(-turn) p.
PressRecording stand_in(const ForwardModel& model, double turn_degrees, bool mirror, int presses) {
  auto inputs = [&](const std::vector<Circle>& c) {
    return model.inputs(model.solve(conductivity_from_circles(model.mesh(), c, 1.0)));
  };
  const Eigen::VectorXd none = inputs({});
  PressRecording r{SampleMatrix(presses, none.size()), Eigen::MatrixX2d(presses, 2)};
  const double a = -turn_degrees * kPi / 180;
  for (int i = 0; i < presses; ++i) {
    const double rho = 0.3 + 0.4 * i / presses, phi = 2.39996 * i;  // the golden angle
    const double x = rho * std::cos(phi), y = rho * std::sin(phi);
    r.differences.row(i) = (inputs({{x, y, 0.15, 0.4}}) - none).transpose();
    const double fx = std::cos(a) * x - std::sin(a) * y, fy = std::sin(a) * x + std::cos(a) * y;
    r.positions.row(i) << fx, mirror ? -fy : fy;
  }
  return r;
}

TEST(PressFrame, RecoversTheTurnAndTheMirrorOfAStandInRecording) {
  const auto model = std::make_shared<const ForwardModel>(testing::disk(16, MeshDensity::coarse));
  const LinearProblem problem = make_linear_problem(model, 1.0, PixelGrid(32, 1.0));
  PressFrameOptions o;
  o.step_degrees = 2;
  for (const auto& [turn, mirror] : {std::pair{100.0, true}, std::pair{282.0, false}}) {
    const PressRecording r = stand_in(*model, turn, mirror, 30);
    const PressFrame f = fit_press_frame(problem, r.differences, r.positions, o);
    EXPECT_EQ(f.mirror, mirror) << turn;
    EXPECT_NEAR(f.rotate_degrees, turn, 2.0) << turn;
    EXPECT_GT(f.cosine, 0.8) << turn;
    EXPECT_LT(f.other_mirror_cosine, f.cosine - 0.2) << turn;
    EXPECT_LT(f.other_turn_cosine, f.cosine - 0.2) << turn;
  }
}

TEST(PressFrame, BadInputIsRefused) {
  const auto model = std::make_shared<const ForwardModel>(testing::disk(16, MeshDensity::coarse));
  const LinearProblem problem = make_linear_problem(model, 1.0, PixelGrid(32, 1.0));
  const PressRecording r = stand_in(*model, 0, false, 4);
  EXPECT_EQ(testing::input_error_at(
                [&] { fit_press_frame(problem, r.differences, r.positions.topRows(3)); }),
            "presses.positions");
  EXPECT_EQ(testing::input_error_at([&] {
              fit_press_frame(problem, r.differences.topRows(2), r.positions.topRows(2));
            }),
            "presses.");
  PressFrameOptions o;
  o.step_degrees = 0;
  EXPECT_EQ(
      testing::input_error_at([&] { fit_press_frame(problem, r.differences, r.positions, o); }),
      "PressFrameOptions.step_degrees");
}

}  // namespace
}  // namespace eitbench
