// The CEM forward model against independent references: the analytic point-electrode solution,
// reciprocity, conservation of current, the scaling law and the sensor's symmetry.
#include <gtest/gtest.h>

#include <random>

#include "eitbench/jacobian.h"
#include "test_support.h"

namespace eitbench {
namespace {

// Point electrodes on a homogeneous unit disk (issue 2): current I into electrode a, out of b.
double analytic_voltage(int L, int a, int b, int m, double current, double sigma) {
  auto s = [L](int j) { return std::sin(M_PI * std::abs(j) / L); };
  return current / (M_PI * sigma) * std::log(s(m - b) * s(m + 1 - a) / (s(m - a) * s(m + 1 - b)));
}

TEST(ForwardModel, AnalyticFormulaMatchesTheIssuesExample) {
  EXPECT_NEAR(analytic_voltage(16, 0, 1, 2, 1.0, 1.0), -0.0958, 5e-5);
}

TEST(ForwardModel, SmallElectrodesConvergeToThePointElectrodeSolution) {
  const int L = 16;
  const double current = 2.0, sigma = 0.5;
  Eigen::VectorXd analytic(13);
  for (int k = 0; k < 13; ++k) analytic[k] = analytic_voltage(L, 0, 1, 2 + k, current, sigma);
  std::vector<double> errors;
  for (auto density : {MeshDensity::coarse, MeshDensity::medium, MeshDensity::fine}) {
    const Mesh& mesh = testing::disk(L, density, 0.02);  // electrodes cover 2 % of the rim
    const ForwardModel model(mesh, {current, 0.01});
    const Eigen::VectorXd v = model.frame(Eigen::VectorXd::Constant(mesh.num_triangles(), sigma));
    errors.push_back((v.head(13) - analytic).norm() / analytic.norm());
  }
  EXPECT_LT(errors[1], errors[0]);
  EXPECT_LT(errors[2], errors[1]);
  EXPECT_LT(errors[2], 0.005);
  RecordProperty("relative_error_fine", std::to_string(errors[2]));
}

TEST(ForwardModel, FramesAreReciprocal) {
  for (int L : {8, 16, 32}) {
    const Mesh& mesh = testing::disk(L, MeshDensity::coarse);
    const ForwardModel model(mesh);
    const Eigen::VectorXd v = model.frame(testing::random_conductivity(mesh.num_triangles(), L));
    EXPECT_LT(model.protocol().reciprocity_error(v, MeasurementOrder::rotating), 1e-10)
        << "L = " << L;
  }
}

TEST(ForwardModel, CurrentsFollowThePatternAndSumToZero) {
  const Mesh& mesh = testing::disk(16, MeshDensity::medium);
  const ForwardModel model(mesh, {0.7, 0.02});
  const ForwardSolution s = model.solve(testing::random_conductivity(mesh.num_triangles(), 1));
  const Eigen::MatrixXd I = model.electrode_currents(s);
  for (int d = 0; d < 16; ++d) {
    EXPECT_NEAR(I.col(d).sum(), 0.0, 1e-12);
    for (int e = 0; e < 16; ++e) {
      const double expected = e == d ? 0.7 : e == (d + 1) % 16 ? -0.7 : 0.0;
      EXPECT_NEAR(I(e, d), expected, 1e-10) << "electrode " << e << ", drive " << d;
    }
  }
}

TEST(ForwardModel, ScalingConductivityScalesVoltagesInversely) {
  // v(c sigma, z / c) = v(sigma, z) / c exactly: the contact impedance is a boundary resistance
  // and must scale with the bulk for the law to hold.
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  const Eigen::VectorXd sigma = testing::random_conductivity(mesh.num_triangles(), 2);
  const double c = 7.5;
  const ForwardModel base(mesh, {1.0, 0.03}), scaled(mesh, {1.0, 0.03 / c});
  const Eigen::VectorXd v = base.frame(sigma), w = scaled.frame(c * sigma);
  EXPECT_LT((w * c - v).norm() / v.norm(), 1e-12);
  // And the drive current enters linearly.
  const ForwardModel doubled(mesh, {2.0, 0.03});
  EXPECT_LT((doubled.frame(sigma) - 2 * v).norm() / v.norm(), 1e-12);
}

TEST(ForwardModel, RotatingTheConductivityRotatesTheFrame) {
  // The symmetric mesh lets sigma be rotated exactly: sigma'(t) = sigma(image of t under rot(-s)).
  // A touch turned by s electrode steps is seen by drive d as the original by drive d - s.
  const int L = 16;
  const Mesh& mesh = testing::disk(L, MeshDensity::coarse);
  const ForwardModel model(mesh);
  const Eigen::VectorXd sigma = testing::random_conductivity(mesh.num_triangles(), 3);
  const Eigen::VectorXd v = model.frame(sigma);
  const Protocol& p = model.protocol();
  for (int s : {1, 5}) {
    const std::vector<int> image = testing::element_image(mesh, s, false);
    Eigen::VectorXd turned(sigma.size());
    for (int t = 0; t < mesh.num_triangles(); ++t) turned[image[t]] = sigma[t];
    const Eigen::VectorXd w = model.frame(turned);
    for (int i = 0; i < p.frame_size(); ++i) {
      const auto [d, m] = p.pairs(MeasurementOrder::rotating)[i];
      const double expected =
          v[p.index((d - s + L) % L, (m - s + L) % L, MeasurementOrder::rotating)];
      EXPECT_NEAR(w[i], expected, 1e-10 * v.cwiseAbs().maxCoeff());
    }
  }
}

TEST(ForwardModel, PointElectrodesWork) {
  // A Gmsh-style mesh with point electrodes: the rim nodes nearest each electrode angle.
  Mesh mesh = testing::disk(16, MeshDensity::medium, 0.02);
  for (auto& e : mesh.electrodes) {
    e.point_node = e.segments[e.segments.size() / 2][0];
    e.segments.clear();
  }
  const ForwardModel model(mesh);
  const Eigen::VectorXd v = model.frame(Eigen::VectorXd::Ones(mesh.num_triangles()));
  EXPECT_LT(model.protocol().reciprocity_error(v, MeasurementOrder::rotating), 1e-10);
  EXPECT_NEAR(v[0], analytic_voltage(16, 0, 1, 2, 1.0, 1.0), 0.01);
}

TEST(ForwardModel, RejectsBadInput) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  EXPECT_THROW(ForwardModel(mesh, {1.0, 0.0}), InputError);
  EXPECT_THROW(ForwardModel(mesh, {1.0, -1.0}), InputError);
  EXPECT_THROW(ForwardModel(mesh, {1.0, NAN}), InputError);
  EXPECT_THROW(ForwardModel(mesh, {0.0, 0.01}), InputError);
  // Options are named by their fields (the command line maps flags to them), and a mesh built in
  // code with too few electrodes is refused as input, before the protocol is made from it.
  try {
    ForwardModel(mesh, {NAN, 0.01});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "current") << e.what();
  }
  Mesh three = mesh;
  three.electrodes.resize(3);
  EXPECT_THROW(ForwardModel(three, {}, "three.msh"), InputError);
  const ForwardModel model(mesh);
  const int T = mesh.num_triangles();
  EXPECT_THROW(model.solve(Eigen::VectorXd::Ones(T - 1)), InputError);
  Eigen::VectorXd sigma = Eigen::VectorXd::Ones(T);
  sigma[5] = 0;
  EXPECT_THROW(model.solve(sigma), InputError);
  sigma[5] = NAN;
  EXPECT_THROW(model.solve(sigma), InputError);
  sigma[5] = INFINITY;
  try {
    model.solve(sigma);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "element 5");
  }
}

}  // namespace
}  // namespace eitbench
