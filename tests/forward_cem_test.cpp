// The complete electrode model's own equations, checked on the solution at every electrode count
// and at a conductivity contrast of 1e4: the contact law on each electrode with its own impedance,
// conservation of current, and reciprocity of the transfer impedances. Each is computed here from
// the node and electrode potentials, not by the library's Protocol or electrode_currents.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "eitbench/jacobian.h"
#include "test_support.h"

namespace eitbench {
namespace {

// Conductivities log-uniform over four decades, [0.01, 100].
Eigen::VectorXd contrast_1e4(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> exponent(-2.0, 2.0);
  Eigen::VectorXd sigma(n);
  for (auto& s : sigma) s = std::pow(10.0, exponent(rng));
  return sigma;
}

// Distinct contact impedances in [0.005, 0.2], in shuffled order so that no index pattern (the
// identity, a shift, the reverse) maps them onto the wrong electrodes unnoticed.
Eigen::VectorXd shuffled_impedances(int L, unsigned seed) {
  Eigen::VectorXd z = Eigen::VectorXd::LinSpaced(L, 0.005, 0.2);
  std::mt19937 rng(seed);
  std::shuffle(z.data(), z.data() + L, rng);
  return z;
}

// The current the adjacent pattern drives into electrode e under drive d.
double pattern_current(int L, int e, int d, double current) {
  return e == d ? current : e == (d + 1) % L ? -current : 0.0;
}

class ElectrodeCount : public ::testing::TestWithParam<int> {
 protected:
  void SetUp() override {
    const int L = GetParam();
    options_.current = 0.8;
    options_.contact_impedances = shuffled_impedances(L, 7);
    model_ = std::make_unique<ForwardModel>(mesh(), options_);
    sigma_ = contrast_1e4(mesh().num_triangles(), 11);
    ASSERT_GT(sigma_.maxCoeff() / sigma_.minCoeff(), 5e3);
    solution_ = model_->solve(sigma_);
  }
  const Mesh& mesh() const { return testing::disk(GetParam(), MeshDensity::medium); }

  ForwardOptions options_;
  std::unique_ptr<ForwardModel> model_;
  Eigen::VectorXd sigma_;
  ForwardSolution solution_;
};

// The CEM's boundary condition U_e = u + z_e sigma du/dn, integrated over electrode e, gives
//   U_e - (1/|e|) int_e u ds = z_e I_e / |e|:
// the voltage across a contact is its impedance times the current density through it, and zero on
// an electrode that carries no current. The mean of u over e is exact for linear u on segments.
// Measured: within 1e-15 of max |U| at L = 8, 16 and 32; the smallest non-zero drop is 1.5e-2 of
// it, so an impedance applied to the wrong electrode is ten orders above the bound.
TEST_P(ElectrodeCount, ContactVoltageIsImpedanceTimesCurrentDensity) {
  const int L = GetParam();
  const Mesh& m = mesh();
  const double scale = solution_.electrode_potentials.cwiseAbs().maxCoeff();
  for (int e = 0; e < L; ++e) {
    for (int d = 0; d < L; ++d) {
      double length = 0, integral = 0;  // |e| and int_e u ds
      for (const auto& [a, b] : m.electrodes[e].segments) {
        const double h = (m.nodes.row(a) - m.nodes.row(b)).norm();
        length += h;
        integral += h * 0.5 * (solution_.node_potentials(a, d) + solution_.node_potentials(b, d));
      }
      const double drop = solution_.electrode_potentials(e, d) - integral / length;
      const double expected =
          options_.contact_impedances[e] * pattern_current(L, e, d, options_.current) / length;
      EXPECT_NEAR(drop, expected, 1e-12 * scale) << "electrode " << e << ", drive " << d;
    }
  }
}

// Current leaves through the electrodes only: the net currents into all electrodes sum to zero,
// and the driven pair carries +-I, whatever the contrast.
TEST_P(ElectrodeCount, CurrentIsConservedAtAContrastOf1e4) {
  const int L = GetParam();
  const Eigen::MatrixXd I = model_->electrode_currents(solution_);
  for (int d = 0; d < L; ++d) {
    EXPECT_NEAR(I.col(d).sum(), 0.0, 1e-12 * options_.current) << "drive " << d;
    for (int e = 0; e < L; ++e)
      EXPECT_NEAR(I(e, d), pattern_current(L, e, d, options_.current), 1e-12 * options_.current)
          << "electrode " << e << ", drive " << d;
  }
}

// Reciprocity: the transfer impedance of drive pair (a, a+1) measured on (b, b+1) equals that of
// drive (b, b+1) measured on (a, a+1), for every a and b, overlapping pairs included (the CEM
// system is symmetric, however the impedances and conductivities vary).
TEST_P(ElectrodeCount, TransferImpedancesAreReciprocalAtAContrastOf1e4) {
  const int L = GetParam();
  const Eigen::MatrixXd& U = solution_.electrode_potentials;
  Eigen::MatrixXd Z(L, L);  // Z(b, a): drive a, measure b
  for (int a = 0; a < L; ++a)
    for (int b = 0; b < L; ++b) Z(b, a) = (U(b, a) - U((b + 1) % L, a)) / options_.current;
  EXPECT_LT((Z - Z.transpose()).norm(), 1e-12 * Z.norm());
  ASSERT_TRUE(Z.allFinite());
}

// A conductivity must be positive and finite, yet one near the largest double overflows the
// assembled system: 1.7e308 everywhere gave NaN potentials while CHOLMOD reported success (1e308
// still solves). The numbers defeated the solve, so it is a NumericalError, which Gauss-Newton's
// line search reads as "no decrease there"; and the failed solve leaves the model's pool of
// workspaces serving the same frames as before it.
TEST(ForwardModel, OverflowIsANumericalErrorAndSpoilsNoLaterSolve) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  const ForwardModel model(mesh);
  const int T = mesh.num_triangles();
  const Eigen::VectorXd sigma = testing::random_conductivity(T, 5);
  const Eigen::VectorXd before = model.frame(sigma);
  const Eigen::VectorXd overflowing = Eigen::VectorXd::Constant(T, 1.7e308);
  EXPECT_THROW(model.solve(overflowing), NumericalError);
  EXPECT_THROW(model.frame(overflowing), NumericalError);
  EXPECT_THROW(model.jacobian(overflowing), NumericalError);
  EXPECT_TRUE(model.frame(Eigen::VectorXd::Constant(T, 1e308)).allFinite());
  EXPECT_EQ(model.frame(sigma), before);
  EXPECT_EQ(model.solve(sigma).electrode_potentials,
            ForwardModel(mesh).solve(sigma).electrode_potentials);
}

// A model moved to other contact impedances is the model built with them, bit for bit (frames,
// a protocol of its own, the Jacobian), and leaves the one it came from as it was.
TEST(ForwardModel, OtherContactImpedancesGiveTheModelBuiltWithThem) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  ForwardOptions options;
  options.current = 0.8;
  options.protocol = std::make_shared<const MeasurementProtocol>(opposite_protocol(16));
  const ForwardModel base(mesh, options);
  const Eigen::VectorXd sigma = contrast_1e4(mesh.num_triangles(), 3);
  const Eigen::VectorXd before = base.measured(sigma);
  const Eigen::VectorXd z = shuffled_impedances(16, 5);
  options.contact_impedances = z;
  const ForwardModel built(mesh, options);
  const ForwardModel moved = base.with_contact_impedances(z);
  EXPECT_EQ(moved.measured(sigma), built.measured(sigma));
  EXPECT_EQ(moved.jacobian(sigma), built.jacobian(sigma));
  EXPECT_EQ(moved.options().contact_impedances, z);
  EXPECT_NE(moved.measured(sigma), before);  // the impedances do change the frame
  EXPECT_EQ(base.measured(sigma), before);
  EXPECT_EQ(testing::input_error_at([&] { base.with_contact_impedances(z.head(15)); }),
            "ForwardOptions.contact_impedances");
  Eigen::VectorXd negative = z;
  negative[3] = -0.01;
  EXPECT_EQ(testing::input_error_at([&] { base.with_contact_impedances(negative); }),
            "ForwardOptions.contact_impedances");
}

INSTANTIATE_TEST_SUITE_P(ForwardModel, ElectrodeCount, ::testing::Values(8, 16, 32),
                         [](const auto& info) {
                           return std::to_string(info.param) + "electrodes";
                         });

}  // namespace
}  // namespace eitbench
