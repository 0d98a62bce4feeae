// Protocols as data: the generators against hand-counted channels and pyEIT's rule, the CSV form
// and its refusals, and the forward model and Jacobian on any protocol against the analytic
// point-electrode solution and finite differences.
#include <gtest/gtest.h>

#include <cmath>

#include "eitbench/jacobian.h"
#include "test_support.h"

namespace eitbench {
namespace {

// Point electrodes on a homogeneous unit disk: current I into electrode a, out of b, v = U(m) -
// U(n) (the same formula as forward_test.cpp's, for any measured pair).
double analytic_voltage(int L, int a, int b, int m, int n, double current, double sigma) {
  auto s = [L](int j) { return std::sin(M_PI * std::abs(j) / L); };
  return current / (M_PI * sigma) * std::log(s(m - b) * s(n - a) / (s(m - a) * s(n - b)));
}

TEST(MeasurementProtocol, AdjacentIsTheReducedLayoutOfProtocol) {
  for (int L : {8, 16}) {
    const Protocol adjacent(L);
    for (auto order : {MeasurementOrder::rotating, MeasurementOrder::ascending}) {
      const MeasurementProtocol p = adjacent_protocol(L, order);
      ASSERT_EQ(p.size(), adjacent.frame_size());
      EXPECT_TRUE(p.reciprocal());
      ASSERT_EQ(p.input_size(), adjacent.reduced_size());
      const auto inputs = p.input_channels();
      for (int r = 0; r < p.input_size(); ++r) {
        const auto [d, m] = adjacent.reduced_pairs()[r];
        EXPECT_EQ(inputs[r], (Channel{d, (d + 1) % L, m, (m + 1) % L})) << r;
      }
      const Eigen::VectorXd frame = Eigen::VectorXd::LinSpaced(p.size(), 1, p.size());
      EXPECT_EQ(p.to_inputs(frame), adjacent.reduce(frame, order));
    }
  }
}

TEST(MeasurementProtocol, OppositeIsOpenEITs192ChannelsAndSkip7) {
  const MeasurementProtocol p = opposite_protocol(16);
  ASSERT_EQ(p.size(), 192);
  EXPECT_FALSE(p.reciprocal());  // its reciprocals would drive adjacent pairs
  EXPECT_EQ(p.input_size(), 192);
  // Drive 0 -> 8: k = 1..6 and 9..14 (the pairs (0,1), (7,8), (8,9), (15,0) touch a drive).
  const std::vector<int> ks{1, 2, 3, 4, 5, 6, 9, 10, 11, 12, 13, 14};
  for (std::size_t i = 0; i < ks.size(); ++i)
    EXPECT_EQ(p.channels()[i], (Channel{0, 8, ks[i] + 1, ks[i]}));
  EXPECT_EQ(p.channels()[12], (Channel{1, 9, 3, 2}));
  EXPECT_EQ(p.channels()[191], (Channel{15, 7, 14, 13}));  // (14,15), (15,0) touch 15
  EXPECT_TRUE(p.same_channels(skip_protocol(16, 7)));
  EXPECT_EQ(skip_protocol(16, 2).size(), 16 * 12);
  EXPECT_TRUE(skip_protocol(16, 0).reciprocal());  // adjacent drives: reciprocal, 104 inputs
  EXPECT_EQ(skip_protocol(16, 0).input_size(), 104);
}

TEST(MeasurementProtocol, FindsAChannelInEitherOrientationWithItsSign) {
  const MeasurementProtocol p = opposite_protocol(16);
  int sign = 0;
  EXPECT_EQ(p.find({0, 8, 2, 1}, &sign), 0);
  EXPECT_EQ(sign, 1);
  EXPECT_EQ(p.find({0, 8, 1, 2}, &sign), 0);
  EXPECT_EQ(sign, -1);
  // Drive 8 -> 0 is listed too: the exact match wins over the reversed drive.
  EXPECT_EQ(p.find({8, 0, 2, 1}, &sign), 12 * 8);
  EXPECT_EQ(sign, 1);
  EXPECT_EQ(p.find({0, 3, 5, 6}), -1);
}

TEST(MeasurementProtocol, CsvRoundTripAndNames) {
  for (const auto& spec : {"adjacent", "adjacent-ascending", "opposite", "skip-3"}) {
    const MeasurementProtocol p = make_protocol(spec, 16);
    EXPECT_EQ(p.name(), spec);
    const MeasurementProtocol back = parse_protocol_csv(p.csv(), 16, "back", "text");
    EXPECT_TRUE(back.same_channels(p)) << spec;
    EXPECT_EQ(back.input_size(), p.input_size()) << spec;
  }
  EXPECT_EQ(testing::input_error_at([] { make_protocol("skip-15", 16); }), "protocol.skip");
  EXPECT_EQ(testing::input_error_at([] { make_protocol("skip-x", 16); }), "--protocol.");
  EXPECT_EQ(testing::input_error_at([] { make_protocol("diagonal", 16); }), "--protocol.");
  EXPECT_EQ(testing::input_error_at([] { opposite_protocol(15); }), "protocol.electrodes");
  EXPECT_EQ(testing::input_error_at([] { make_protocol("/no/such.csv", 16); }), "/no/such.csv.");
}

TEST(MeasurementProtocol, BadCsvLinesAreRefusedWithTheirNumber) {
  const std::string head = "drive+,drive-,meas+,meas-\n0,1,2,3\n\n";  // line 3 blank
  const std::vector<std::pair<std::string, std::string>> cases{
      {"0,1,2,16\n", "outside"},           {"4,4,2,3\n", "drive+ equals drive-"},
      {"0,2,5,5\n", "meas+ equals meas-"}, {"0,1,2,3\n", "repeats the channel of line 2"},
      {"0,1,2.5,3\n", "not an integer"},   {"0,1,2\n", "3 columns"},
      {"0,1,a,3\n", "not an integer"},     {"0,1,2,-1\n", "outside"}};
  for (const auto& [line, message] : cases) {
    try {
      parse_protocol_csv(head + line, 16, "bad", "bad.csv");
      ADD_FAILURE() << "accepted " << line;
    } catch (const InputError& e) {
      EXPECT_EQ(e.source(), "bad.csv");
      EXPECT_EQ(e.field(), "line 4") << line;
      EXPECT_NE(e.message().find(message), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(testing::input_error_at([] { parse_protocol_csv("header only\n", 16, "x", "x.csv"); }),
            "x.csv.");
  // Without a header (as MATLAB's writematrix writes it) the first channel is kept, not dropped.
  EXPECT_EQ(parse_protocol_csv("0,8,2,1\n0,8,3,2\n", 16, "bare", "bare.csv").size(), 2);
}

TEST(MeasurementProtocol, AdjacentChannelsGiveTheFrameAndJacobianBitForBit) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  const ForwardModel model(mesh);
  const ForwardSolution s = model.solve(testing::random_conductivity(mesh.num_triangles(), 3));
  const MeasurementProtocol& p = model.measurement_protocol();
  EXPECT_EQ(p.name(), "adjacent");
  EXPECT_EQ(model.measured(s), model.frame(s));
  EXPECT_EQ(model.inputs(s), model.protocol().reduce(model.frame(s), MeasurementOrder::rotating));
  EXPECT_EQ(model.input_jacobian(s), model.jacobian(s, model.protocol().reduced_pairs()));
}

TEST(MeasurementProtocol, OppositeAndSkipConvergeToThePointElectrodeSolution) {
  const int L = 16;
  const double current = 2.0, sigma = 0.5;
  for (const auto& p : {opposite_protocol(L), skip_protocol(L, 2)}) {
    Eigen::VectorXd analytic(p.size());
    for (int i = 0; i < p.size(); ++i) {
      const Channel& c = p.channels()[i];
      analytic[i] = analytic_voltage(L, c.drive_plus, c.drive_minus, c.meas_plus, c.meas_minus,
                                     current, sigma);
    }
    std::vector<double> errors;
    for (auto density : {MeshDensity::coarse, MeshDensity::medium, MeshDensity::fine}) {
      const Mesh& mesh = testing::disk(L, density, 0.02);
      ForwardOptions o{current, 0.01};
      o.protocol = std::make_shared<MeasurementProtocol>(p);
      const ForwardModel model(mesh, o);
      const Eigen::VectorXd v =
          model.measured(model.solve(Eigen::VectorXd::Constant(mesh.num_triangles(), sigma)));
      errors.push_back((v - analytic).norm() / analytic.norm());
    }
    EXPECT_LT(errors[2], errors[0]) << p.name();
    EXPECT_LT(errors[2], 0.005) << p.name();
    RecordProperty("relative_error_fine_" + p.name(), std::to_string(errors[2]));
  }
}

// Central differences of the inputs along `dir`.
Eigen::VectorXd central_difference_of_inputs(const ForwardModel& model,
                                             const Eigen::VectorXd& sigma,
                                             const Eigen::VectorXd& dir) {
  const double h = 1e-4 * sigma.cwiseAbs().maxCoeff() / dir.cwiseAbs().maxCoeff();
  return (model.inputs(sigma + h * dir) - model.inputs(sigma - h * dir)) / (2 * h);
}

TEST(MeasurementProtocol, JacobiansMatchFiniteDifferencesSignedAndMagnitude) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  const Eigen::VectorXd sigma = testing::random_conductivity(mesh.num_triangles(), 5);
  const Eigen::VectorXd dir = testing::random_conductivity(mesh.num_triangles(), 6);
  for (bool magnitude : {false, true}) {
    for (const auto& p : {opposite_protocol(16), skip_protocol(16, 3)}) {
      ForwardOptions o;
      o.protocol = std::make_shared<MeasurementProtocol>(p.with_magnitude(magnitude));
      const ForwardModel model(mesh, o);
      const ForwardSolution s = model.solve(sigma);
      const Eigen::VectorXd v = model.inputs(s);
      if (magnitude) {
        EXPECT_GE(v.minCoeff(), 0.0);
      }
      const Eigen::VectorXd jd = model.input_jacobian(s) * dir;
      const Eigen::VectorXd fd = central_difference_of_inputs(model, sigma, dir);
      EXPECT_LT((jd - fd).norm() / fd.norm(), 1e-6) << p.name() << " magnitude " << magnitude;
    }
  }
}

TEST(MeasurementProtocol, AProtocolForOtherElectrodesIsRefused) {
  const Mesh& mesh = testing::disk(8, MeshDensity::coarse);
  ForwardOptions o;
  o.protocol = std::make_shared<MeasurementProtocol>(opposite_protocol(16));
  EXPECT_EQ(testing::input_error_at([&] { ForwardModel(mesh, o); }), "ForwardOptions.protocol");
}

TEST(MeasurementProtocol, WeakChannelsAreThoseNearZero) {
  Eigen::VectorXd v0(4);
  v0 << 1.0, -2e-4, 0.5, 3e-3;
  EXPECT_EQ(weak_channels(v0, 1e-3), std::vector<int>{1});
}

}  // namespace
}  // namespace eitbench
