// Frames with missing values: a method given NaN where values are missing reconstructs exactly as
// the same method built from scratch on a protocol that never had those values (another protocol,
// another Jacobian: an independent construction), for the one-step and the iterative methods; the
// noise weights are the whitened least squares they stand for; and bad frames are refused.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>

#include "eitbench/bench/methods/registry.h"
#include "eitbench/jacobian.h"
#include "eitbench/solvers.h"
#include "test_support.h"

namespace eitbench {
namespace {

// The opposite protocol (192 channels, all inputs) and the same without every channel that uses
// electrodes 0 or 1, as a board with those electrodes broken would read.
struct Pair {
  MeasurementProtocol full = opposite_protocol(16);
  std::vector<bool> kept;
  MeasurementProtocol reduced{"reduced", 16, without_01(full, kept)};

  static std::vector<Channel> without_01(const MeasurementProtocol& p, std::vector<bool>& kept) {
    std::vector<Channel> out;
    for (const Channel& c : p.channels()) {
      const bool uses =
          c.drive_plus < 2 || c.drive_minus < 2 || c.meas_plus < 2 || c.meas_minus < 2;
      kept.push_back(!uses);
      if (!uses) out.push_back(c);
    }
    return out;
  }
};

std::shared_ptr<const LinearProblem> problem_on(const MeasurementProtocol& p,
                                                const PixelGrid& grid) {
  ForwardOptions o;
  o.protocol = std::make_shared<MeasurementProtocol>(p);
  auto model = std::make_shared<const ForwardModel>(testing::disk(16, MeshDensity::coarse), o);
  return std::make_shared<const LinearProblem>(make_linear_problem(model, 1.0, grid));
}

// A noise level per input, uneven (0.5 to 2, repeating), for the weighted data term.
Eigen::VectorXd uneven_noise(int m) {
  Eigen::VectorXd noise(m);
  for (int i = 0; i < m; ++i) noise[i] = 0.5 + (i % 7) * 0.25;
  return noise;
}

TEST(MissingValues, EqualsTheMethodOnAProtocolWithoutThoseValues) {
  const Pair pair;
  const PixelGrid grid(32, 1.0);
  const auto full = problem_on(pair.full, grid), reduced = problem_on(pair.reduced, grid);
  ASSERT_LT(reduced->measurements(), full->measurements());
  // A frame from a conductivity with an inclusion, on the full protocol; NaN where the reduced
  // protocol has no channel.
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  Eigen::VectorXd sigma = Eigen::VectorXd::Ones(mesh.num_triangles());
  for (int t = 0; t < mesh.num_triangles(); ++t)
    if ((triangle_centroid(mesh, t) - Eigen::Vector2d(0.3, 0.2)).norm() < 0.25) sigma[t] = 0.5;
  const Eigen::VectorXd dv =
      full->model->inputs(sigma) - full->model->inputs(Eigen::VectorXd::Ones(mesh.num_triangles()));
  Eigen::VectorXd with_gaps = dv, kept_values(reduced->measurements());
  for (int i = 0, k = 0; i < dv.size(); ++i) {
    if (pair.kept[static_cast<std::size_t>(i)])
      kept_values[k++] = dv[i];
    else
      with_gaps[i] = std::nan("");
  }
  for (const std::string method : {"tikhonov", "noser", "laplace", "gn"}) {
    MethodOptions o;
    o.choose = "fixed";
    o.lambda = 1e-2;
    o.relative_lambda = true;
    const MissingValues missing(full, method, [&](std::shared_ptr<const LinearProblem> p) {
      return make_reconstructor(method, std::move(p), o);
    });
    const Eigen::VectorXd a = missing.reconstruct(with_gaps);
    const Eigen::VectorXd b = make_reconstructor(method, reduced, o)->reconstruct(kept_values);
    EXPECT_LT((a - b).norm(), 1e-6 * b.norm()) << method;
    // The full frame, every value present, is another image.
    EXPECT_GT((missing.reconstruct(dv) - a).norm(), 1e-3 * a.norm()) << method;
  }
}

TEST(MissingValues, NoiseWeightsAreWhitenedLeastSquares) {
  const PixelGrid grid(24, 1.0);
  const auto full = problem_on(opposite_protocol(16), grid);
  const int m = full->measurements();
  const Eigen::VectorXd noise = uneven_noise(m);
  Eigen::VectorXd frame = full->A * Eigen::VectorXd::Random(full->unknowns()) * 1e-3;
  frame[3] = frame[40] = std::nan("");
  const double lambda = 0.05;
  MethodOptions o;
  o.choose = "fixed";
  o.lambda = lambda;
  o.relative_lambda = true;
  const MissingValues missing(
      full, "tikhonov",
      [&](std::shared_ptr<const LinearProblem> p) {
        return make_reconstructor("tikhonov", std::move(p), o);
      },
      noise);
  // x = argmin ||W (A x - y)||^2 + lambda s ||x||^2 over the present rows, W = diag(1 / noise),
  // s the mean eigenvalue of (W A)(W A)^T: the normal equations, solved directly.
  std::vector<int> rows;
  for (int i = 0; i < m; ++i)
    if (!std::isnan(frame[i])) rows.push_back(i);
  Eigen::MatrixXd WA(static_cast<Eigen::Index>(rows.size()), full->unknowns());
  Eigen::VectorXd Wy(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t k = 0; k < rows.size(); ++k) {
    WA.row(static_cast<Eigen::Index>(k)) = full->A.row(rows[k]) / noise[rows[k]];
    Wy[static_cast<Eigen::Index>(k)] = frame[rows[k]] / noise[rows[k]];
  }
  const double scale = (WA * WA.transpose()).trace() / static_cast<double>(rows.size());
  const Eigen::MatrixXd H =
      WA.transpose() * WA + lambda * scale * Eigen::MatrixXd::Identity(WA.cols(), WA.cols());
  const Eigen::VectorXd x = H.ldlt().solve(WA.transpose() * Wy);
  const Eigen::VectorXd image = missing.reconstruct(frame);
  EXPECT_LT((full->from_image(image) - x).norm(), 1e-4 * x.norm());
  // Scaling every noise value alike changes nothing: the lambda is relative.
  const MissingValues scaled(
      full, "tikhonov",
      [&](std::shared_ptr<const LinearProblem> p) {
        return make_reconstructor("tikhonov", std::move(p), o);
      },
      10 * noise);
  EXPECT_LT((scaled.reconstruct(frame) - image).norm(), 1e-4 * image.norm());
}

// GREIT's noise model makes each value's noise proportional to its own signal, N = diag(Y Y^T):
// weighted rows W give D Y^T W (W (Y Y^T + lambda N) W)^-1 W y, the unweighted image. This is why
// reconstruct refuses --noise-weights for greit rather than silently doing nothing.
TEST(MissingValues, NoiseWeightsLeaveGreitUnchanged) {
  const PixelGrid grid(24, 1.0);
  const auto full = problem_on(opposite_protocol(16), grid);
  const int m = full->measurements();
  const Eigen::VectorXd noise = uneven_noise(m);
  const Eigen::VectorXd frame = full->A * Eigen::VectorXd::Random(full->unknowns()) * 1e-3;
  MethodOptions o;
  o.choose = "fixed";
  o.lambda = 0.05;
  o.relative_lambda = true;
  const auto greit = [&](std::shared_ptr<const LinearProblem> p) {
    return make_reconstructor("greit", std::move(p), o);
  };
  const Eigen::VectorXd plain = MissingValues(full, "greit", greit).reconstruct(frame);
  const Eigen::VectorXd weighed = MissingValues(full, "greit", greit, noise).reconstruct(frame);
  EXPECT_LT((weighed - plain).norm(), 1e-4 * plain.norm());
  // The same weights do change Tikhonov's image: the test can tell.
  const auto tikhonov = [&](std::shared_ptr<const LinearProblem> p) {
    return make_reconstructor("tikhonov", std::move(p), o);
  };
  const Eigen::VectorXd t_plain = MissingValues(full, "tikhonov", tikhonov).reconstruct(frame);
  const Eigen::VectorXd t_weighed =
      MissingValues(full, "tikhonov", tikhonov, noise).reconstruct(frame);
  EXPECT_GT((t_weighed - t_plain).norm(), 1e-2 * t_plain.norm());
}

TEST(MissingValues, BatchesGroupFramesByTheirMissingValuesAndBadFramesAreRefused) {
  const PixelGrid grid(24, 1.0);
  const auto full = problem_on(opposite_protocol(16), grid);
  MethodOptions o;
  o.choose = "fixed";
  o.lambda = 1e-2;
  o.relative_lambda = true;
  const MissingValues missing(full, "noser", [&](std::shared_ptr<const LinearProblem> p) {
    return make_reconstructor("noser", std::move(p), o);
  });
  SampleMatrix frames = SampleMatrix::Random(5, full->measurements()) * 1e-3;
  frames(1, 7) = frames(3, 7) = std::nan("");
  frames(4, 100) = std::nan("");
  const SampleMatrix images = missing.reconstruct_all(frames);
  for (Eigen::Index r = 0; r < frames.rows(); ++r)
    EXPECT_LT((images.row(r).transpose() - missing.reconstruct(frames.row(r).transpose())).norm(),
              1e-6 * images.row(r).norm())
        << r;
  EXPECT_NE(missing.settings().find("on 191 values"), std::string::npos) << missing.settings();
  Eigen::VectorXd bad = frames.row(0).transpose();
  bad[2] = INFINITY;
  EXPECT_EQ(testing::input_error_at([&] { missing.reconstruct(bad); }), "frame.value 2");
  bad.setConstant(std::nan(""));
  EXPECT_EQ(testing::input_error_at([&] { missing.reconstruct(bad); }), "frame.");
  EXPECT_EQ(testing::input_error_at([&] { missing.reconstruct(Eigen::VectorXd::Zero(3)); }),
            "frame.");
}

}  // namespace
}  // namespace eitbench
