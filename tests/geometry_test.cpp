// Overlap areas against independent references: closed forms, and conservation of area.
#include <gtest/gtest.h>

#include <random>

#include "eitbench/jacobian.h"
#include "test_support.h"

namespace eitbench {
namespace {

TEST(Geometry, TriangleInsideCircleGivesTriangleArea) {
  const Eigen::Vector2d a(0.1, 0.0), b(0.3, 0.1), c(0.0, 0.3);
  const double area = 0.5 * std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
  EXPECT_NEAR(triangle_circle_overlap(a, b, c, {0.1, 0.1}, 1.0), area, 1e-15);
}

TEST(Geometry, CircleInsideTriangleGivesCircleArea) {
  EXPECT_NEAR(triangle_circle_overlap({-10, -10}, {10, -10}, {0, 10}, {0.5, -1}, 0.7), M_PI * 0.49,
              1e-13);
}

TEST(Geometry, HalfDiskThroughTheCentre) {
  // A huge triangle whose edge y = 0 cuts the circle through its centre: half the disk.
  EXPECT_NEAR(triangle_circle_overlap({-50, 0}, {50, 0}, {0, 50}, {0.2, 0.0}, 0.3),
              0.5 * M_PI * 0.09, 1e-13);
}

TEST(Geometry, CircularSegmentMatchesClosedForm) {
  // Chord at distance d from the centre: the segment's area is r^2 acos(d/r) - d sqrt(r^2 - d^2).
  const double r = 0.8, d = 0.3;
  const double expected = r * r * std::acos(d / r) - d * std::sqrt(r * r - d * d);
  EXPECT_NEAR(triangle_circle_overlap({-100, d}, {100, d}, {0, 100}, {0, 0}, r), expected, 1e-12);
}

TEST(Geometry, CircleOverlapsOfAMeshSumToTheCircleArea) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.4, 0.4);  // circles stay inside the mesh
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Vector2d centre(u(rng), u(rng));
    const double r = 0.2 + 0.1 * trial / 5;
    double sum = 0;
    for (int t = 0; t < mesh.num_triangles(); ++t)
      sum += triangle_circle_overlap(mesh.nodes.row(mesh.triangles(t, 0)),
                                     mesh.nodes.row(mesh.triangles(t, 1)),
                                     mesh.nodes.row(mesh.triangles(t, 2)), centre, r);
    EXPECT_NEAR(sum, M_PI * r * r, 1e-12);
  }
}

TEST(Geometry, BoxOverlapsTileTheTriangle) {
  const Eigen::Vector2d a(0.013, -0.2), b(0.31, 0.07), c(-0.05, 0.19);
  const double area = 0.5 * std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
  double sum = 0;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j)
      sum += triangle_box_overlap(a, b, c, -0.5 + 0.05 * i, -0.45 + 0.05 * i, -0.5 + 0.05 * j,
                                  -0.45 + 0.05 * j);
  EXPECT_NEAR(sum, area, 1e-15);
  EXPECT_DOUBLE_EQ(triangle_box_overlap(a, b, c, -1, 1, -1, 1), area);
  EXPECT_EQ(triangle_box_overlap(a, b, c, 2, 3, 2, 3), 0.0);
}

TEST(Geometry, ConductivityFromCirclesConservesTheInclusion) {
  // sum_t area_t (sigma_t - sigma_0) = sum_c pi r_c^2 (sigma_c - sigma_0) for circles inside the
  // mesh.
  const Mesh& mesh = testing::disk(16, MeshDensity::medium);
  const std::vector<Circle> circles{{0.3, 0.2, 0.2, 0.01}, {-0.4, -0.3, 0.15, 0.2}};
  const double background = 0.05;
  const Eigen::VectorXd sigma = conductivity_from_circles(mesh, circles, background);
  const Eigen::VectorXd area = triangle_areas(mesh);
  const double expected = M_PI * 0.04 * (0.01 - background) + M_PI * 0.0225 * (0.2 - background);
  EXPECT_NEAR(area.dot((sigma.array() - background).matrix()), expected, 1e-12);
  EXPECT_GE(sigma.minCoeff(), 0.01 - 1e-12);
  EXPECT_LE(sigma.maxCoeff(), 0.2 + 1e-12);
}

TEST(Geometry, ParseCirclesRejectsBadText) {
  EXPECT_EQ(parse_circles("0.1,0.2,0.3,0.4; -0.1,0,0.1,2", "--circles").size(), 2u);
  for (const char* bad :
       {"", "1,2,3", "1,2,3,4,5", "a,b,c,d", "0,0,-1,1", "0,0,1,0", "0,0,nan,1", "0,0,1,inf"})
    EXPECT_THROW(parse_circles(bad, "--circles"), InputError) << bad;
  try {
    parse_circles("0,0,1,1;0,0,0.1,x", "--circles");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "--circles");
    EXPECT_EQ(e.field(), "circle 1");
  }
}

TEST(PixelGrid, CentresAndMaskFollowTheSpec) {
  const PixelGrid grid(64, 1.0);
  EXPECT_NEAR(grid.center(0, 0).x(), -1 + 1.0 / 64, 1e-15);
  EXPECT_NEAR(grid.center(0, 0).y(), 1 - 1.0 / 64, 1e-15);  // row 0 at the top
  EXPECT_NEAR(grid.center(63, 63).y(), -1 + 1.0 / 64, 1e-15);
  EXPECT_FALSE(grid.mask()[0]);
  EXPECT_TRUE(grid.mask()[32 * 64 + 32]);
  // The in-disk pixel count approaches pi/4 of the grid.
  EXPECT_NEAR(grid.num_inside() / 4096.0, M_PI / 4, 0.01);
}

// The size and radius come from a data set or a user: bad input, named by the field.
TEST(PixelGrid, RefusesABadSizeOrRadiusAsInput) {
  using testing::input_error_at;
  EXPECT_EQ(input_error_at([] { PixelGrid(0, 1.0); }), "PixelGrid.size");
  EXPECT_EQ(input_error_at([] { PixelGrid(64, 0.0); }), "PixelGrid.radius");
  EXPECT_EQ(input_error_at([] { PixelGrid(64, INFINITY); }), "PixelGrid.radius");
}

TEST(PixelGrid, OverlapConservesAreaAndMapsAreMeans) {
  const Mesh& mesh = testing::disk(16, MeshDensity::medium);
  const PixelGrid grid(64, 1.0);
  const auto overlap = pixel_overlap(mesh, grid);
  const Eigen::VectorXd area = triangle_areas(mesh);
  const Eigen::VectorXd rows = overlap * Eigen::VectorXd::Ones(grid.num_pixels());
  EXPECT_LT((rows - area).cwiseAbs().maxCoeff(), 1e-15);  // every triangle tiled by its pixels

  const auto P = pixel_to_element(mesh, grid);
  const Eigen::VectorXd ones = P * Eigen::VectorXd::Ones(grid.num_pixels());
  EXPECT_LT((ones.array() - 1).abs().maxCoeff(), 1e-13);  // a uniform image is a uniform mesh
  const auto Q = element_to_pixel(mesh, grid);
  const Eigen::VectorXd back = Q * Eigen::VectorXd::Ones(mesh.num_triangles());
  for (int p = 0; p < grid.num_pixels(); ++p) {
    if (grid.mask()[p])
      EXPECT_NEAR(back[p], 1.0, 1e-13);
    else
      EXPECT_EQ(back[p], 0.0);
  }
  for (int t = 0; t < P.rows(); ++t)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(P, t); it; ++it)
      EXPECT_TRUE(grid.mask()[it.col()]);
}

}  // namespace
}  // namespace eitbench
