// The adjoint Jacobian against central finite differences of the forward model.
#include <gtest/gtest.h>

#include <random>

#include "eitbench/jacobian.h"
#include "test_support.h"

namespace eitbench {
namespace {

// Central difference of the frame along direction `dir`, with a step relative to sigma.
Eigen::VectorXd central_difference(const ForwardModel& model, const Eigen::VectorXd& sigma,
                                   const Eigen::VectorXd& dir) {
  const double h = 1e-4 * sigma.cwiseAbs().maxCoeff() / dir.cwiseAbs().maxCoeff();
  return (model.frame(sigma + h * dir) - model.frame(sigma - h * dir)) / (2 * h);
}

TEST(Jacobian, ElementColumnsMatchFiniteDifferences) {
  for (int L : {8, 16}) {
    const Mesh& mesh = testing::disk(L, MeshDensity::coarse);
    const ForwardModel model(mesh, {1.5, 0.02});
    const Eigen::VectorXd sigma = testing::random_conductivity(mesh.num_triangles(), 11);
    const Eigen::MatrixXd J = model.jacobian(sigma);
    ASSERT_EQ(J.rows(), L * (L - 3));
    ASSERT_EQ(J.cols(), mesh.num_triangles());
    for (int t : {0, 1, 7, mesh.num_triangles() / 2, mesh.num_triangles() - 1}) {
      const Eigen::VectorXd fd =
          central_difference(model, sigma, Eigen::VectorXd::Unit(mesh.num_triangles(), t));
      EXPECT_LT((J.col(t) - fd).norm() / fd.norm(), 1e-5) << "L = " << L << ", element " << t;
    }
    // A random direction exercises every column at once.
    const Eigen::VectorXd dir =
        testing::random_conductivity(mesh.num_triangles(), 12).array() - 1.25;
    const Eigen::VectorXd fd = central_difference(model, sigma, dir);
    EXPECT_LT((J * dir - fd).norm() / fd.norm(), 1e-5);
  }
}

TEST(Jacobian, PixelColumnsMatchFiniteDifferences) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  const ForwardModel model(mesh);
  const PixelGrid grid(64, 1.0);
  const auto P = pixel_to_element(mesh, grid);
  const Eigen::VectorXd sigma = testing::random_conductivity(mesh.num_triangles(), 13);
  const Eigen::MatrixXd Jp = model.jacobian(sigma) * P;
  ASSERT_EQ(Jp.cols(), 4096);
  for (int p : {32 * 64 + 32, 10 * 64 + 20, 50 * 64 + 40, 31 * 64 + 1}) {
    ASSERT_TRUE(grid.mask()[p]);
    const Eigen::VectorXd dir =
        P * Eigen::VectorXd::Unit(grid.num_pixels(), p);  // pixel p's footprint
    const Eigen::VectorXd fd = central_difference(model, sigma, dir);
    EXPECT_LT((Jp.col(p) - fd).norm() / fd.norm(), 1e-5) << "pixel " << p;
  }
  for (int p = 0; p < grid.num_pixels(); ++p)
    if (!grid.mask()[p]) {
      ASSERT_EQ(Jp.col(p).norm(), 0.0) << "masked pixel " << p;
    }
}

TEST(Jacobian, SatisfiesEulersRelationForTheScalingLaw) {
  // v(c sigma, z / c) = v(sigma, z) / c; differentiating at c = 1 gives, exactly,
  //   sum_k J_k sigma_k - z dv/dz = -v,
  // with dv/dz from central differences in the contact impedance.
  const Mesh& mesh = testing::disk(16, MeshDensity::medium);
  const double z = 0.05, h = 1e-4 * z;
  const ForwardModel model(mesh, {1.0, z}), up(mesh, {1.0, z + h}), down(mesh, {1.0, z - h});
  const Eigen::VectorXd sigma = testing::random_conductivity(mesh.num_triangles(), 14);
  const Eigen::VectorXd v = model.frame(sigma);
  const Eigen::VectorXd dv_dz = (up.frame(sigma) - down.frame(sigma)) / (2 * h);
  const Eigen::VectorXd lhs = model.jacobian(sigma) * sigma - z * dv_dz;
  EXPECT_LT((lhs + v).norm() / v.norm(), 1e-7);
  EXPECT_GT((z * dv_dz).norm() / v.norm(), 1e-4) << "the contact term matters at this z";
}

// The rows a reconstruction uses, computed alone, are the full Jacobian's rows bit for bit.
TEST(Jacobian, ChosenRowsEqualTheFullJacobiansRows) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  const ForwardModel model(mesh);
  const ForwardSolution s = model.solve(testing::random_conductivity(mesh.num_triangles(), 9));
  const Protocol& p = model.protocol();
  const Eigen::MatrixXd reduced = model.jacobian(s, p.reduced_pairs());
  ASSERT_EQ(reduced.rows(), 104);
  EXPECT_EQ(reduced, p.select_rows(model.jacobian(s), MeasurementOrder::rotating, true));
  const Eigen::MatrixXd ascending = model.jacobian(s, p.pairs(MeasurementOrder::ascending));
  EXPECT_EQ(ascending, p.select_rows(model.jacobian(s), MeasurementOrder::ascending, false));
}

// The columns of chosen elements (the shape fit's circles reach few of them) are the full
// Jacobian's columns bit for bit, in the order asked, for a signed and a magnitude protocol; an
// element the mesh lacks is refused.
TEST(Jacobian, ChosenElementsEqualTheFullJacobiansColumns) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  const std::vector<int> elements = {mesh.num_triangles() - 1, 0, 7, 3, 3};
  for (bool magnitude : {false, true}) {
    ForwardOptions o;
    o.protocol =
        std::make_shared<MeasurementProtocol>(opposite_protocol(16).with_magnitude(magnitude));
    const ForwardModel model(mesh, o);
    const ForwardSolution s = model.solve(testing::random_conductivity(mesh.num_triangles(), 4));
    const Eigen::MatrixXd all = model.input_jacobian(s);
    const Eigen::MatrixXd chosen = model.input_jacobian(s, elements);
    ASSERT_EQ(chosen.cols(), static_cast<Eigen::Index>(elements.size()));
    for (std::size_t k = 0; k < elements.size(); ++k)
      EXPECT_EQ(chosen.col(static_cast<Eigen::Index>(k)), all.col(elements[k]))
          << "element " << elements[k] << ", magnitude " << magnitude;
    EXPECT_THROW(model.input_jacobian(s, {mesh.num_triangles()}), std::invalid_argument);
  }
}

}  // namespace
}  // namespace eitbench
