// Protocols of current patterns: the refusals, the values that survive removed electrodes, and the
// forward model and Jacobian on them against independent answers (the adjacent map the channels
// give, superposed point-electrode solutions, finite differences).
#include <gtest/gtest.h>

#include <cmath>

#include "eitbench/jacobian.h"
#include "test_support.h"

namespace eitbench {
namespace {

// The potential difference U(m) - U(n) of point electrodes on a homogeneous unit disk when unit
// current enters at a and leaves at b (measurement_protocol_test.cpp's formula).
double point_voltage(int L, int a, int b, int m, int n, double sigma) {
  auto s = [L](int j) { return std::sin(M_PI * std::abs(j) / L); };
  return 1.0 / (M_PI * sigma) * std::log(s(m - b) * s(n - a) / (s(m - a) * s(n - b)));
}

// The adjacent drives and every adjacent difference, the driven pairs' included: the L x L map.
CurrentPatterns adjacent_map_patterns(int L, double current) {
  CurrentPatterns p;
  p.injection = Eigen::MatrixXd::Zero(L, L);
  p.measurement = Eigen::MatrixXd::Zero(L, L);
  for (int k = 0; k < L; ++k) {
    p.injection(k, k) = current;
    p.injection((k + 1) % L, k) = -current;
    p.measurement(k, k) = 1;
    p.measurement((k + 1) % L, k) = -1;
  }
  return p;
}

// Three patterns that drive three or four electrodes at once with unequal currents, and four
// differences, one of them a weighted sum of three electrodes.
CurrentPatterns multi_electrode_patterns(int L) {
  CurrentPatterns p;
  p.injection = Eigen::MatrixXd::Zero(L, 3);
  p.injection(0, 0) = 2.0, p.injection(5, 0) = -1.5, p.injection(9, 0) = -0.5;
  p.injection(3, 1) = 1.0, p.injection(4, 1) = 0.25, p.injection(11, 1) = -1.25;
  p.injection(1, 2) = -1.0, p.injection(7, 2) = 0.5, p.injection(8, 2) = 0.75,
                 p.injection(14, 2) = -0.25;
  p.measurement = Eigen::MatrixXd::Zero(L, 4);
  p.measurement(2, 0) = 1, p.measurement(3, 0) = -1;
  p.measurement(6, 1) = 1, p.measurement(12, 1) = -1;
  p.measurement(0, 2) = 1, p.measurement(15, 2) = -1;
  p.measurement(10, 3) = 2, p.measurement(13, 3) = -1, p.measurement(1, 3) = -1;
  return p;
}

std::shared_ptr<const MeasurementProtocol> protocol_of(CurrentPatterns p) {
  return std::make_shared<MeasurementProtocol>("patterns", std::move(p));
}

TEST(CurrentPatterns, BadMatricesAreRefusedNamingTheColumn) {
  const CurrentPatterns good = multi_electrode_patterns(16);
  EXPECT_NO_THROW(good.validate("Inj.mat"));
  auto refused = [](CurrentPatterns p) {
    return testing::input_error_at([&] { p.validate("Inj.mat"); });
  };
  CurrentPatterns p = good;
  p.injection(0, 1) = 0.5;  // pattern 1 no longer sums to zero
  EXPECT_EQ(refused(p), "Inj.mat.injection column 1");
  p = good;
  p.measurement(2, 3) = std::nan("");
  EXPECT_EQ(refused(p), "Inj.mat.measurement column 3");
  p = good;
  p.measurement.col(0).setZero();
  EXPECT_EQ(refused(p), "Inj.mat.measurement column 0");
  p = good;
  p.measurement = Eigen::MatrixXd::Zero(8, 4);
  EXPECT_EQ(refused(p), "Inj.mat.measurement");
  p = good;
  p.injection.resize(16, 0);
  EXPECT_EQ(refused(p), "Inj.mat.injection");
}

TEST(CurrentPatterns, AProtocolOfPatternsHasEveryValueAsAnInputAndNoChannels) {
  const MeasurementProtocol p("patterns", multi_electrode_patterns(16));
  EXPECT_TRUE(p.has_patterns());
  EXPECT_EQ(p.electrodes(), 16);
  EXPECT_EQ(p.size(), 12);
  EXPECT_EQ(p.input_size(), 12);
  EXPECT_TRUE(p.channels().empty());
  EXPECT_FALSE(p.reciprocal());
  EXPECT_TRUE(p.same_channels(MeasurementProtocol("other name", multi_electrode_patterns(16))));
  EXPECT_FALSE(p.same_channels(MeasurementProtocol("map", adjacent_map_patterns(16, 1))));
  EXPECT_FALSE(p.same_channels(adjacent_protocol(16)));
  EXPECT_THROW(p.csv(), std::logic_error);
  EXPECT_EQ(testing::input_error_at([&] { p.with_magnitude(true); }), "protocol.magnitude");
  EXPECT_THROW(adjacent_protocol(16).patterns(), std::logic_error);
}

TEST(CurrentPatterns, RemovedElectrodesTakeEveryValueThatDrivesOrReadsThem) {
  const CurrentPatterns p = multi_electrode_patterns(16);
  const std::vector<bool> keep = p.values_without({0, 1});
  // Pattern 0 drives electrode 0 and pattern 2 electrode 1: both go. Under pattern 1, the
  // differences 2 (reads 0) and 3 (reads 1) go; 0 and 1 stay.
  const std::vector<bool> expected{false, false, false, false, true,  true,
                                   false, false, false, false, false, false};
  EXPECT_EQ(keep, expected);
  EXPECT_EQ(p.values_without({}), std::vector<bool>(12, true));
}

TEST(CurrentPatterns, TheAdjacentDrivesAsPatternsGiveTheAdjacentMap) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  const Eigen::VectorXd sigma = testing::random_conductivity(mesh.num_triangles(), 11);
  ForwardOptions channels_options{1.5, 0.02};
  const ForwardModel channels(mesh, channels_options);
  ForwardOptions o = channels_options;
  o.protocol = protocol_of(adjacent_map_patterns(16, 1.5));
  const ForwardModel patterns(mesh, o);
  const ForwardSolution s = patterns.solve(sigma);
  const Eigen::VectorXd map = channels.adjacent_map(channels.solve(sigma));
  EXPECT_LT((patterns.measured(s) - map).cwiseAbs().maxCoeff(), 1e-12 * map.cwiseAbs().maxCoeff());
  EXPECT_EQ(patterns.inputs(s), patterns.measured(s));
  EXPECT_LT((patterns.measured(sigma) - map).cwiseAbs().maxCoeff(),
            1e-12 * map.cwiseAbs().maxCoeff());
  // The rows of the map the channels also read: the Jacobian of the same values.
  std::vector<Channel> all;
  for (int d = 0; d < 16; ++d)
    for (int m = 0; m < 16; ++m) all.push_back({d, (d + 1) % 16, m, (m + 1) % 16});
  const Eigen::MatrixXd J = channels.jacobian(channels.solve(sigma), all);
  EXPECT_LT((patterns.input_jacobian(s) - J).cwiseAbs().maxCoeff(),
            1e-12 * J.cwiseAbs().maxCoeff());
}

TEST(CurrentPatterns, ManyElectrodePatternsConvergeToSuperposedPointSolutions) {
  const int L = 16;
  const double current = 2.0, sigma = 0.5;
  const CurrentPatterns p = multi_electrode_patterns(L);
  // Superposition: with r and q two electrodes the value neither drives nor reads, a pattern is
  // the pair drives a -> r of current c_a (c = sum_a c_a (e_a - e_r), as c sums to zero) and a
  // difference the pairs U(e) - U(q) weighted by w_e. A point electrode's own potential under its
  // current is singular, so only the values that read no driven electrode are compared.
  std::vector<int> compared;
  std::vector<double> analytic;
  for (int k = 0; k < p.patterns(); ++k)
    for (int m = 0; m < p.differences(); ++m) {
      std::vector<int> unused;
      bool clean = true;
      for (int e = 0; e < L; ++e) {
        const bool driven = p.injection(e, k) != 0, read = p.measurement(e, m) != 0;
        clean = clean && !(driven && read);
        if (!driven && !read) unused.push_back(e);
      }
      if (!clean) continue;
      const int r = unused[0], q = unused[1];
      double v = 0;
      for (int a = 0; a < L; ++a)
        for (int e = 0; e < L; ++e)
          if (p.injection(a, k) != 0 && p.measurement(e, m) != 0)
            v += p.injection(a, k) * p.measurement(e, m) * point_voltage(L, a, r, e, q, sigma);
      compared.push_back(k * p.differences() + m);
      analytic.push_back(v);
    }
  ASSERT_GE(compared.size(), 8u);
  const Eigen::Map<const Eigen::VectorXd> exact(analytic.data(),
                                                static_cast<Eigen::Index>(analytic.size()));
  std::vector<double> errors;
  for (auto density : {MeshDensity::coarse, MeshDensity::medium, MeshDensity::fine}) {
    const Mesh& mesh = testing::disk(L, density, 0.02);
    ForwardOptions o{current, 0.01};
    o.protocol = protocol_of(p);
    const ForwardModel model(mesh, o);
    const Eigen::VectorXd all =
        model.measured(model.solve(Eigen::VectorXd::Constant(mesh.num_triangles(), sigma)));
    Eigen::VectorXd v(exact.size());
    for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = all[compared[static_cast<std::size_t>(i)]];
    errors.push_back((v - exact).norm() / exact.norm());
  }
  EXPECT_LT(errors[2], errors[0]);
  EXPECT_LT(errors[2], 0.005);
  RecordProperty("relative_error_fine", std::to_string(errors[2]));
}

TEST(CurrentPatterns, TheJacobianMatchesFiniteDifferences) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  const Eigen::VectorXd sigma = testing::random_conductivity(mesh.num_triangles(), 5);
  const Eigen::VectorXd dir = testing::random_conductivity(mesh.num_triangles(), 6);
  ForwardOptions o{0.7, 0.03};
  o.protocol = protocol_of(multi_electrode_patterns(16));
  const ForwardModel model(mesh, o);
  const Eigen::VectorXd jd = model.input_jacobian(model.solve(sigma)) * dir;
  const double h = 1e-4 * sigma.cwiseAbs().maxCoeff() / dir.cwiseAbs().maxCoeff();
  const Eigen::VectorXd fd =
      (model.inputs(sigma + h * dir) - model.inputs(sigma - h * dir)) / (2 * h);
  EXPECT_LT((jd - fd).norm() / fd.norm(), 1e-6);
  // Chosen elements give the full Jacobian's columns.
  const std::vector<int> some{0, 7, 3};
  const ForwardSolution s = model.solve(sigma);
  const Eigen::MatrixXd full = model.input_jacobian(s), part = model.input_jacobian(s, some);
  for (std::size_t k = 0; k < some.size(); ++k)
    EXPECT_EQ(part.col(static_cast<Eigen::Index>(k)), full.col(some[k]));
}

}  // namespace
}  // namespace eitbench
