// The registry's properties against what each method does: a one-step method's images are one
// linear map of the frame, an iterative one's are not; a pixel-image method draws no circles.
#include <gtest/gtest.h>

#include <algorithm>

#include "eitbench/bench/ktc/tank_post_processing.h"
#include "eitbench/bench/methods/registry.h"
#include "eitbench/jacobian.h"
#include "test_support.h"

namespace eitbench {
namespace {

std::shared_ptr<const LinearProblem> small_problem() {
  static const auto problem = [] {
    const auto model = std::make_shared<const ForwardModel>(testing::disk(16, MeshDensity::coarse));
    return std::make_shared<const LinearProblem>(
        make_linear_problem(model, 1.0, PixelGrid(16, 1.0)));
  }();
  return problem;
}

// A frame of the linear model: a patch of pixels at `value` from `first` on.
Eigen::VectorXd patch_frame(const LinearProblem& p, int first, double value) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(p.unknowns());
  x.segment(first, 12).setConstant(value);
  return p.A * x;
}

bool listed(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

TEST(Registry, AOneStepMethodIsALinearMapAndOnlyItIs) {
  const auto problem = small_problem();
  const Eigen::VectorXd y1 = patch_frame(*problem, 40, 0.6), y2 = patch_frame(*problem, 110, -0.4);
  MethodOptions o;
  o.choose = "fixed";
  o.lambda = 1e-2;  // on each method's relative scale
  o.relative_lambda = true;
  for (const std::string& name : model_based_method_names()) {
    const auto method = make_reconstructor(name, problem, o);
    const Eigen::VectorXd sum = method->reconstruct(y1 + 2 * y2);
    const Eigen::VectorXd parts = method->reconstruct(y1) + 2 * method->reconstruct(y2);
    const double deviation = (sum - parts).norm() / parts.norm();
    // A one-step method applies its map in float32 (about 5e-7 here); an iterative one is
    // further off by orders of magnitude.
    if (find_method(name).one_step)
      EXPECT_LT(deviation, 1e-5) << name;
    else
      EXPECT_GT(deviation, 1e-3) << name;
    EXPECT_EQ(find_method(name).pixel_image, !method->finds_circles()) << name;
  }
  EXPECT_TRUE(listed(method_names_with(&MethodSpec::one_step), "smooth"));
  EXPECT_FALSE(listed(method_names_with(&MethodSpec::pixel_image), "dnn"));
}

// The KTC post-processing network's one-step image takes its methods from the registry: one
// without the property is refused with the list (reconstruct --placement-map reads pixel_image
// alike; PressSet.TheCommandLinesPriorAndElectrodesAreUsed sees it refuse shape-linear).
TEST(Registry, WhatTakesAOneStepMethodRefusesTheOthersNamingThem) {
  const std::string list = joined_method_names_with(&MethodSpec::one_step);
  EXPECT_EQ(list, "tikhonov, noser, laplace, smooth, greit");
  EXPECT_NO_THROW(KtcOneStep({"greit", 0.1}).validate());
  try {
    KtcOneStep{"gn", 0.1}.validate();
    ADD_FAILURE() << "gn accepted as a one-step method";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("(" + list + ")"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace eitbench
