// Paths of the solvers that the image-quality tests do not reach: the linear problem and Tikhonov
// at 8 and 32 electrodes, choosing a hyperparameter by validation (fit) for the iterative and
// trained methods, Gauss-Newton ending on a failed line search, and single precision at the
// smallest lambda a choice can return.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "eitbench/jacobian.h"
#include "eitbench/solvers.h"
#include "test_support.h"

namespace eitbench {
namespace {

struct Problem {
  std::shared_ptr<const ForwardModel> model;
  PixelGrid grid{64, 1.0};
  std::shared_ptr<const LinearProblem> linear;
};

const Problem& problem(int electrodes) {
  static std::map<int, Problem> cache;
  auto it = cache.find(electrodes);
  if (it == cache.end()) {
    Problem p;
    p.model = std::make_shared<const ForwardModel>(testing::disk(electrodes, MeshDensity::medium));
    p.linear = std::make_shared<const LinearProblem>(make_linear_problem(p.model, 1.0, p.grid));
    it = cache.emplace(electrodes, std::move(p)).first;
  }
  return it->second;
}

// Noise-free linear frames y = A x of single-disc touches, one a row.
SampleMatrix linear_frames(const Problem& p, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(-0.5, 0.5), r(0.1, 0.25), c(0.2, 0.8);
  SampleMatrix frames(n, p.linear->measurements());
  for (int k = 0; k < n; ++k) {
    const Eigen::VectorXd image =
        circles_image(p.grid, {{pos(rng), pos(rng), r(rng), c(rng)}}, 1.0);
    frames.row(k) = (p.linear->A * p.linear->from_image(image)).transpose();
  }
  return frames;
}

class SolverElectrodeCount : public ::testing::TestWithParam<int> {};

// A is the forward model's derivative on the label scale: the error of the linear prediction A x
// against the nonlinear difference frame is second order, halving with the contrast. Measured
// at L = 8 and 32: 4.6e-3 of the frame at 1 %, ratio 2.0 between 1 % and 0.5 %; a Jacobian off by
// a few per cent in any column would leave a first-order floor that does not halve.
double linearisation_error(const Problem& p, double contrast) {
  const Eigen::VectorXd x = circles_image(p.grid, {{0.3, 0.2, 0.2, 1.0 - contrast}}, 1.0);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(p.model->mesh().num_triangles());
  const Eigen::VectorXd v0 = p.model->frame(ones);
  const Eigen::VectorXd v1 =
      p.model->frame(ones - p.linear->element_from_pixels * p.linear->from_image(x));
  const Eigen::VectorXd dv = p.model->protocol().reduce(v1 - v0, MeasurementOrder::rotating);
  return (p.linear->A * p.linear->from_image(x) - dv).norm() / dv.norm();
}

TEST_P(SolverElectrodeCount, LinearProblemIsTheForwardModelsDerivative) {
  const int L = GetParam();
  const Problem& p = problem(L);
  ASSERT_EQ(p.linear->measurements(), L * (L - 3) / 2);
  ASSERT_EQ(p.linear->unknowns(), p.grid.num_inside());
  const double at_1 = linearisation_error(p, 0.01), at_half = linearisation_error(p, 0.005);
  EXPECT_LT(at_1, 0.007);
  EXPECT_NEAR(at_1 / at_half, 2.0, 0.01);
}

// At a tiny lambda every prior fits noise-free linear data (measured misfit: at most 3e-9 at L = 8,
// 1e-5 at L = 32; the L = 16 test's bound 1e-4 holds for both), and the batch path gives the
// single-frame images.
TEST_P(SolverElectrodeCount, TikhonovFitsNoiseFreeDataWithEveryPrior) {
  const Problem& p = problem(GetParam());
  const SampleMatrix y = linear_frames(p, 3, 1);
  for (auto prior : {Prior::identity, Prior::noser, Prior::laplace}) {
    TikhonovOptions o;
    o.prior = prior;
    o.single_precision = false;  // tiny lambdas amplify rounding
    Tikhonov t(p.linear, o);
    t.set_lambda(1e-10 * t.scale(), "fixed");
    const SampleMatrix images = t.reconstruct_all(y);
    for (int k = 0; k < y.rows(); ++k) {
      const Eigen::VectorXd x = p.linear->from_image(images.row(k).transpose());
      EXPECT_LT((p.linear->A * x - y.row(k).transpose()).norm() / y.row(k).norm(), 1e-4)
          << t.name();
      EXPECT_LT((t.reconstruct(y.row(k).transpose()) - images.row(k).transpose()).norm(),
                1e-10 * images.row(k).norm())
          << t.name();
    }
  }
}

INSTANTIATE_TEST_SUITE_P(LinearProblem, SolverElectrodeCount, ::testing::Values(8, 32),
                         [](const auto& info) {
                           return std::to_string(info.param) + "electrodes";
                         });

// fit() by validation: the labels are the images the method itself gives at one candidate (set
// directly), and the score is minus the distance to them. Only that candidate scores 0, so fit must
// land on it, at either end of the candidate list or inside it.
ScoreFn distance_score() {
  return [](const Eigen::VectorXd& image, const Eigen::VectorXd& label) {
    return -(image - label).norm();
  };
}

TEST(Fit, GaussNewtonChoosesTheLambdaTheScoreFavours) {
  const Problem& p = problem(16);
  const SampleMatrix y = linear_frames(p, 2, 2);
  for (double target : {1e-5, 1e-1}) {
    GaussNewtonOptions fixed;
    fixed.lambda = target;
    const SampleMatrix labels = GaussNewton(p.linear, fixed).reconstruct_all(y);
    GaussNewtonOptions o;
    o.choice = Criterion::validation;
    GaussNewton gn(p.linear, o);
    gn.fit(y, labels, distance_score());
    EXPECT_EQ(gn.lambda(), target);
    EXPECT_NE(gn.settings().find("validation"), std::string::npos) << gn.settings();
    EXPECT_EQ(gn.reconstruct_all(y), labels);
  }
  // With a fixed choice fit leaves lambda alone.
  GaussNewton gn(p.linear, {});
  gn.fit(y, y, distance_score());
  EXPECT_EQ(gn.lambda(), GaussNewtonOptions{}.lambda);
}

TEST(Fit, GreitChoosesTheLambdaTheScoreFavours) {
  const Problem& p = problem(16);
  const SampleMatrix y = linear_frames(p, 4, 3);
  for (double target : {1e-5, 1e-2, 1.0}) {
    GreitOptions fixed;
    fixed.lambda = target;
    const SampleMatrix labels = Greit(p.linear, fixed).reconstruct_all(y);
    GreitOptions o;
    o.choice = Criterion::validation;
    Greit greit(p.linear, o);
    greit.fit(y, labels, distance_score());
    EXPECT_NE(greit.settings().find("(validation)"), std::string::npos) << greit.settings();
    EXPECT_EQ(greit.reconstruct_all(y), labels) << target;
  }
}

// TV's target is its default alpha (the quick set's validation choice), reached from the largest.
TEST(Fit, TotalVariationChoosesTheAlphaTheScoreFavours) {
  const Problem& p = problem(16);
  const SampleMatrix y = linear_frames(p, 2, 4);
  const double target = TotalVariationOptions{}.alpha;
  const SampleMatrix labels = TotalVariation(p.linear, {}).reconstruct_all(y);
  TotalVariationOptions o;
  o.alpha = 1e-3;
  o.choice = Criterion::validation;
  TotalVariation tv(p.linear, o);
  tv.fit(y, labels, distance_score());
  EXPECT_EQ(tv.alpha(), target);
  EXPECT_NE(tv.settings().find("validation"), std::string::npos) << tv.settings();
  EXPECT_EQ(tv.reconstruct_all(y), labels);
}

// With both tolerances 0 Gauss-Newton iterates until rounding defeats the line search (measured: 72
// steps, Phi flat at 8.009e-8 from step 47): then it reports no_descent, not the iteration limit,
// its objective never rose and ends no higher than a solve at the default tolerance, and the image
// it returns is the one the report describes: its residual, computed here through the forward
// model, is the report's last.
TEST(GaussNewtonPaths, AFailedLineSearchReturnsTheLastAcceptedStep) {
  const Problem& p = problem(16);
  const Eigen::VectorXd y = linear_frames(p, 1, 7).row(0).transpose();
  GaussNewtonOptions o;
  o.tolerance = 0;
  o.residual_tolerance = 0;
  o.max_iterations = 200;
  GaussNewton::Report report, usual;
  const Eigen::VectorXd image = GaussNewton(p.linear, o).solve(y, &report);
  GaussNewton(p.linear, {}).solve(y, &usual);
  EXPECT_EQ(report.termination, Termination::no_descent) << report.message;
  EXPECT_LT(report.iterations, o.max_iterations);
  ASSERT_EQ(report.objective.size(), static_cast<std::size_t>(report.iterations) + 1);
  for (std::size_t k = 1; k < report.objective.size(); ++k)
    EXPECT_LE(report.objective[k], report.objective[k - 1]) << "step " << k;
  EXPECT_LE(report.objective.back(), usual.objective.back());
  ASSERT_TRUE(image.allFinite());
  const Mesh& mesh = p.model->mesh();
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(mesh.num_triangles());
  const Eigen::VectorXd sigma =
      p.linear->element_from_pixels * (1.0 - p.linear->from_image(image).array()).matrix();
  const Eigen::VectorXd dv = p.model->protocol().reduce(
      p.model->frame(sigma) - p.model->frame(ones), MeasurementOrder::rotating);
  EXPECT_NEAR((dv - y).norm(), report.residual.back(), 1e-9 * report.residual.back());
}

// Single precision at the smallest lambda of the grid, which GCV returns on noise-free frames (on
// the simulated data set it picks 1.5-2 decades below the L-curve): the images keep four digits,
// not the seven of working lambdas. Measured relative difference from double: identity 3.2e-5,
// NOSER 7.8e-5, Laplace 2.1e-5 (1e-7 at the grid's middle); the bound is 1.5x the largest.
TEST(Tikhonov, SinglePrecisionAtTheSmallestLambdaAChoiceCanReturn) {
  const Problem& p = problem(16);
  const SampleMatrix y = linear_frames(p, 5, 3);
  for (auto prior : {Prior::identity, Prior::noser, Prior::laplace}) {
    TikhonovOptions o;
    o.prior = prior;
    Tikhonov single(p.linear, o);
    o.single_precision = false;
    Tikhonov exact(p.linear, o);
    const double smallest = exact.lambda_grid().front();
    EXPECT_EQ(exact.choose_gcv(y), smallest) << exact.name();
    single.set_lambda(smallest);
    const SampleMatrix a = single.reconstruct_all(y), b = exact.reconstruct_all(y);
    EXPECT_LT((a - b).norm() / b.norm(), 1.2e-4) << single.name();
  }
}

}  // namespace
}  // namespace eitbench
