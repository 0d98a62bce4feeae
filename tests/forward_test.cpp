// The CEM forward model against independent references: the analytic point-electrode solution,
// reciprocity, conservation of current, the scaling law and the sensor's symmetry.
#include <gtest/gtest.h>

#include <random>
#include <thread>

#include "eitbench/jacobian.h"
#include "test_support.h"

namespace eitbench {
namespace {

// Point electrodes on a homogeneous unit disk (issue 2): current I into electrode a, out of b.
double analytic_voltage(int L, int a, int b, int m, double current, double sigma) {
  auto s = [L](int j) { return std::sin(M_PI * std::abs(j) / L); };
  return current / (M_PI * sigma) * std::log(s(m - b) * s(m + 1 - a) / (s(m - a) * s(m + 1 - b)));
}

TEST(ForwardModel, SmallElectrodesConvergeToThePointElectrodeSolution) {
  // The reference itself, at a value worked out by hand: drive (0, 1), measurement (2, 3).
  ASSERT_NEAR(analytic_voltage(16, 0, 1, 2, 1.0, 1.0), -0.0958, 5e-5);
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

// Reciprocity and conservation of current do not depend on the contrast: at 1e4 (conductivities
// log-uniform in [0.01, 100]) they hold to the same relative precision as at 4.
TEST(ForwardModel, ReciprocityAndCurrentsHoldAtAContrastOf1e4) {
  const Mesh& mesh = testing::disk(16, MeshDensity::medium);
  const ForwardModel model(mesh, {1.0, 0.01});
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> exponent(-2.0, 2.0);
  Eigen::VectorXd sigma(mesh.num_triangles());
  for (auto& s : sigma) s = std::pow(10.0, exponent(rng));
  ASSERT_GT(sigma.maxCoeff() / sigma.minCoeff(), 5e3);
  const ForwardSolution solution = model.solve(sigma);
  const Eigen::VectorXd v = model.frame(sigma);
  EXPECT_LT(model.protocol().reciprocity_error(v, MeasurementOrder::rotating), 1e-9);
  const Eigen::MatrixXd I = model.electrode_currents(solution);
  for (int d = 0; d < 16; ++d) {
    EXPECT_NEAR(I.col(d).sum(), 0.0, 1e-10) << "drive " << d;
    EXPECT_NEAR(I(d, d), 1.0, 1e-8) << "drive " << d;
  }
}

// One contact impedance per electrode: equal values give the scalar option's frame; distinct
// values keep reciprocity; and turning the impedances with the conductivity turns the frame.
TEST(ForwardModel, PerElectrodeContactImpedances) {
  const int L = 16;
  const Mesh& mesh = testing::disk(L, MeshDensity::coarse);
  const Eigen::VectorXd sigma = testing::random_conductivity(mesh.num_triangles(), 4);
  ForwardOptions equal;
  equal.contact_impedances = Eigen::VectorXd::Constant(L, 0.03);
  const Eigen::VectorXd scalar = ForwardModel(mesh, {1.0, 0.03}).frame(sigma);
  EXPECT_LT((ForwardModel(mesh, equal).frame(sigma) - scalar).norm(), 1e-12 * scalar.norm());
  ForwardOptions distinct;
  distinct.contact_impedances = Eigen::VectorXd::LinSpaced(L, 0.005, 0.2);
  const ForwardModel model(mesh, distinct);
  const Eigen::VectorXd v = model.frame(sigma);
  EXPECT_GT((v - scalar).norm(), 1e-3 * scalar.norm());  // the impedances matter
  EXPECT_LT(model.protocol().reciprocity_error(v, MeasurementOrder::rotating), 1e-10);
  const int s = 3;  // electrode e's impedance moves to e + s, the conductivity turns with it
  ForwardOptions turned_options;
  turned_options.contact_impedances.resize(L);
  for (int e = 0; e < L; ++e)
    turned_options.contact_impedances[(e + s) % L] = distinct.contact_impedances[e];
  const std::vector<int> image = testing::element_image(mesh, s, false);
  Eigen::VectorXd turned(sigma.size());
  for (int t = 0; t < mesh.num_triangles(); ++t) turned[image[t]] = sigma[t];
  const Eigen::VectorXd w = ForwardModel(mesh, turned_options).frame(turned);
  const Protocol& p = model.protocol();
  for (int i = 0; i < p.frame_size(); ++i) {
    const auto [d, m] = p.pairs(MeasurementOrder::rotating)[i];
    EXPECT_NEAR(w[p.index((d + s) % L, (m + s) % L, MeasurementOrder::rotating)], v[i],
                1e-10 * v.cwiseAbs().maxCoeff());
  }
}

// Solves run concurrently on the model's pool of workspaces and give what serial solves give.
TEST(ForwardModel, ConcurrentSolvesMatchSerialOnes) {
  const Mesh& mesh = testing::disk(16, MeshDensity::medium);
  const ForwardModel model(mesh);
  std::vector<Eigen::VectorXd> sigmas, serial;
  for (int k = 0; k < 8; ++k) {
    sigmas.push_back(testing::random_conductivity(mesh.num_triangles(), 20 + k));
    serial.push_back(model.frame(sigmas.back()));
  }
  std::vector<Eigen::VectorXd> parallel(sigmas.size());
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (std::size_t k = t; k < sigmas.size(); k += 4)
        for (int repeat = 0; repeat < 3; ++repeat) parallel[k] = model.frame(sigmas[k]);
    });
  for (auto& thread : threads) thread.join();
  for (std::size_t k = 0; k < sigmas.size(); ++k) EXPECT_EQ(parallel[k], serial[k]) << k;
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

TEST(ForwardModel, ValidateNamesTheField) {
  using testing::input_error_at;
  ForwardOptions o;
  EXPECT_EQ(input_error_at([&] { o.validate(); }), "no InputError");
  o.current = INFINITY;
  EXPECT_EQ(input_error_at([&] { o.validate(); }), "ForwardOptions.current");
  o = {};
  o.contact_impedance = -1;
  EXPECT_EQ(input_error_at([&] { o.validate(); }), "ForwardOptions.contact_impedance");
  o.contact_impedances = Eigen::VectorXd::Constant(16, 0.01);  // overrides contact_impedance
  EXPECT_EQ(input_error_at([&] { o.validate(); }), "no InputError");
  o.contact_impedances[3] = NAN;
  EXPECT_EQ(input_error_at([&] { o.validate(); }), "ForwardOptions.contact_impedances");
  // One value per electrode is checked against the mesh.
  o.contact_impedances = Eigen::VectorXd::Constant(15, 0.01);
  EXPECT_EQ(input_error_at([&] { ForwardModel(testing::disk(16, MeshDensity::coarse), o); }),
            "ForwardOptions.contact_impedances");
}

}  // namespace
}  // namespace eitbench
