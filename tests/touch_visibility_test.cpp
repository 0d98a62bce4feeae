// How visible a true touch is: its share of the frame's change by the FEM, against what follows
// from the definition (a lone touch carries its whole frame, a touch of no contrast nothing) and
// a symmetry (two mirror-image touches carry the same share); the model's misfit at the circles
// that made the frames on its own mesh is zero, and bad input is refused.
#include <gtest/gtest.h>

#include <cmath>

#include "eitbench/bench/methods/touch_signal.h"
#include "eitbench/jacobian.h"
#include "test_support.h"

namespace eitbench {
namespace {

using testing::kBackground;

Circle touch(double x, double y, double r, double contrast) {
  return {x, y, r, kBackground * (1 - contrast)};
}

// The frames the model itself makes: differences of its inputs from the empty sensor's.
SampleMatrix own_frames(const ForwardModel& model, const std::vector<std::vector<Circle>>& all) {
  auto inputs = [&](const std::vector<Circle>& c) {
    return model.inputs(model.solve(conductivity_from_circles(model.mesh(), c, kBackground)));
  };
  const Eigen::VectorXd none = inputs({});
  SampleMatrix frames(static_cast<Eigen::Index>(all.size()),
                      model.measurement_protocol().input_size());
  for (std::size_t i = 0; i < all.size(); ++i)
    frames.row(static_cast<Eigen::Index>(i)) = (inputs(all[i]) - none).transpose();
  return frames;
}

TEST(TouchVisibility, SharesFollowFromTheDefinitionAndTheSymmetry) {
  const ForwardModel model(testing::disk(16, MeshDensity::coarse));
  // Mirror images in the x axis: the disk's mesh and electrodes are symmetric about it only up
  // to the mesh, so the two shares agree to the mesh's asymmetry.
  const std::vector<std::vector<Circle>> circles = {
      {touch(0.4, 0.2, 0.2, 0.8)},
      {touch(0.0, 0.6, 0.2, 0.7), touch(0.0, -0.6, 0.2, 0.7)},
      {touch(0.5, 0.0, 0.2, 0.9), touch(-0.3, 0.3, 0.1, 1e-6)},
      {}};
  const SampleMatrix frames = own_frames(model, circles);
  const TouchVisibility v = touch_visibility(model, circles, frames, kBackground);
  ASSERT_EQ(v.signals.size(), 4u);
  ASSERT_EQ(v.signals[0].size(), 1u);
  EXPECT_NEAR(v.signals[0][0], 1.0, 1e-12);  // a lone touch is the whole change
  ASSERT_EQ(v.signals[1].size(), 2u);
  EXPECT_GT(v.signals[1][0], 0.3);
  EXPECT_LT(v.signals[1][0], 1.0);
  EXPECT_NEAR(v.signals[1][0], v.signals[1][1], 0.05 * v.signals[1][0]);
  EXPECT_LT(v.signals[2][1], 1e-5);  // no contrast: nothing to see
  EXPECT_GT(v.signals[2][0], 0.99);
  EXPECT_TRUE(v.signals[3].empty());
  // Frames made by the model itself: it fits them at their circles exactly.
  for (int i = 0; i < 3; ++i) EXPECT_LT(v.model_error[static_cast<std::size_t>(i)], 1e-10);
  EXPECT_TRUE(std::isnan(v.model_error[3]));  // no change to compare with
  // A frame off by 10 % of itself is off by 10 %.
  SampleMatrix off = frames;
  off.row(0) *= 1 / 1.1;
  EXPECT_NEAR(touch_visibility(model, circles, off, kBackground).model_error[0], 0.1, 1e-9);
}

TEST(TouchVisibility, BadInputIsRefused) {
  const ForwardModel model(testing::disk(16, MeshDensity::coarse));
  const std::vector<std::vector<Circle>> circles = {{touch(0.4, 0.2, 0.2, 0.8)}};
  const SampleMatrix frames = own_frames(model, circles);
  EXPECT_EQ(testing::input_error_at([&] { touch_visibility(model, circles, frames, 0.0); }),
            "touch_visibility.background");
  EXPECT_EQ(testing::input_error_at(
                [&] { touch_visibility(model, circles, frames.leftCols(10), kBackground); }),
            "touch_visibility.frames");
  EXPECT_EQ(testing::input_error_at([&] { with_signals(touches_of(circles, kBackground), {}); }),
            "with_signals.signals");
}

}  // namespace
}  // namespace eitbench
