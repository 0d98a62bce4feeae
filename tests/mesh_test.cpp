// The generated disk mesh: exact D_L symmetry, quality, electrodes, determinism, validation.
#include <gtest/gtest.h>

#include <set>

#include "eitbench/jacobian.h"
#include "test_support.h"

namespace eitbench {
namespace {

struct Case {
  int electrodes;
  MeshDensity density;
};

void PrintTo(const Case& c, std::ostream* os) {
  *os << "L=" << c.electrodes << " " << to_string(c.density);
}

class DiskMesh : public ::testing::TestWithParam<Case> {};

TEST_P(DiskMesh, EveryGroupElementMapsNodesAndTrianglesOntoThemselves) {
  const Mesh& mesh = testing::disk(GetParam().electrodes, GetParam().density);
  const int L = mesh.num_electrodes();
  const testing::NodeLocator nodes(mesh.nodes);
  for (int s = 0; s < L; ++s)
    for (bool mirror : {false, true}) {
      for (int i = 0; i < mesh.num_nodes(); ++i)
        ASSERT_GE(nodes.find(testing::transform_point(mesh.nodes.row(i), L, s, mirror), 1e-12), 0)
            << "node " << i << " under rotation " << s << (mirror ? " after the mirror" : "");
      const std::vector<int> image = testing::element_image(mesh, s, mirror);
      const std::set<int> distinct(image.begin(), image.end());
      EXPECT_EQ(distinct.count(-1), 0u);
      EXPECT_EQ(static_cast<int>(distinct.size()), mesh.num_triangles())
          << "a permutation of the triangles";
    }
}

TEST_P(DiskMesh, QualityAndSize) {
  const auto [L, density] = GetParam();
  const Mesh& mesh = testing::disk(L, density);
  const MeshQuality q = measure_quality(mesh);
  const std::map<MeshDensity, std::pair<int, int>> range{{MeshDensity::coarse, {300, 1500}},
                                                         {MeshDensity::medium, {2000, 4000}},
                                                         {MeshDensity::fine, {10000, 20000}}};
  EXPECT_GE(q.triangles, range.at(density).first);
  EXPECT_LE(q.triangles, range.at(density).second);
  EXPECT_GT(q.min_area, 0);
  // Symmetry forces L triangles around the centre, so for large L the apex 360/L is the floor;
  // everywhere else no triangle is thinner than 15 degrees.
  EXPECT_GE(q.min_angle_deg, std::min(15.0, 360.0 / L) - 1e-9);
  double away_from_centre = 180;
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    if ((mesh.triangles.row(t).array() == 0).any()) continue;
    Mesh one;
    one.nodes = mesh.nodes;
    one.triangles = mesh.triangles.row(t);
    away_from_centre = std::min(away_from_centre, measure_quality(one).min_angle_deg);
  }
  EXPECT_GE(away_from_centre, 15.0);
  EXPECT_LE(q.max_angle_deg, 140.0);
  // A polygon inscribed in the unit circle: area just under pi.
  const double area = triangle_areas(mesh).sum();
  EXPECT_LT(area, M_PI);
  EXPECT_GT(area, M_PI * 0.995);
}

TEST_P(DiskMesh, ElectrodesAreArcsCentredOnTheirAngles) {
  const Mesh& mesh = testing::disk(GetParam().electrodes, GetParam().density);
  const int L = mesh.num_electrodes();
  ASSERT_EQ(L, GetParam().electrodes);
  validate_mesh(mesh, "generated");
  for (int e = 0; e < L; ++e) {
    const Electrode& el = mesh.electrodes[e];
    ASSERT_FALSE(el.is_point());
    // Chords of the arc of angle 2 pi coverage / L: the length is within chord error of the arc.
    EXPECT_NEAR(el.length(mesh.nodes), 2 * M_PI * 0.5 / L, 2e-3 * 2 * M_PI / L);
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& s : el.segments)
      for (int n : s) {
        EXPECT_NEAR(mesh.nodes.row(n).norm(), 1.0, 1e-14) << "electrode nodes lie on the circle";
        mean += mesh.nodes.row(n).transpose();
      }
    const double angle = std::atan2(mean.y(), mean.x());
    EXPECT_NEAR(std::remainder(angle - 2 * M_PI * e / L, 2 * M_PI), 0.0, 1e-12)
        << "electrode " << e;
  }
}

INSTANTIATE_TEST_SUITE_P(
    LAndDensity, DiskMesh,
    ::testing::Values(Case{8, MeshDensity::coarse}, Case{8, MeshDensity::medium},
                      Case{16, MeshDensity::coarse}, Case{16, MeshDensity::medium},
                      Case{16, MeshDensity::fine}, Case{32, MeshDensity::coarse},
                      Case{32, MeshDensity::medium}),
    [](const auto& info) {
      return "L" + std::to_string(info.param.electrodes) + "_" + to_string(info.param.density);
    });

TEST(DiskMeshGenerator, IsDeterministic) {
  DiskMeshOptions o;
  o.density = MeshDensity::coarse;
  const Mesh a = generate_disk_mesh(o), b = generate_disk_mesh(o);
  EXPECT_EQ(a.nodes, b.nodes);
  EXPECT_EQ(a.triangles, b.triangles);
}

TEST(DiskMeshGenerator, RefinesTowardsTheElectrodeEdges) {
  const Mesh& mesh = testing::disk(16, MeshDensity::medium);
  // Rim segments at an electrode edge are shorter than those in the middle of a gap.
  double edge = 1, gap = 0;
  const double edge_angle = M_PI * 0.5 / 16, gap_angle = M_PI / 16;
  for (const auto& s : mesh.electrodes[0].segments) {
    const double len = (mesh.nodes.row(s[0]) - mesh.nodes.row(s[1])).norm();
    const double a = std::abs(std::atan2(mesh.nodes(s[0], 1) + mesh.nodes(s[1], 1),
                                         mesh.nodes(s[0], 0) + mesh.nodes(s[1], 0)));
    if (std::abs(a - edge_angle) < 0.02) edge = std::min(edge, len);
  }
  for (int t = 0; t < mesh.num_triangles(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int u = mesh.triangles(t, k), v = mesh.triangles(t, (k + 1) % 3);
      if (std::abs(mesh.nodes.row(u).norm() - 1) > 1e-12 ||
          std::abs(mesh.nodes.row(v).norm() - 1) > 1e-12)
        continue;
      const double a =
          std::atan2(mesh.nodes(u, 1) + mesh.nodes(v, 1), mesh.nodes(u, 0) + mesh.nodes(v, 0));
      if (std::abs(a - gap_angle) < 0.03)
        gap = std::max(gap, (mesh.nodes.row(u) - mesh.nodes.row(v)).norm());
    }
  EXPECT_LT(edge, 0.6 * gap);
}

TEST(DiskMeshGenerator, RejectsBadOptions) {
  DiskMeshOptions o;
  o.electrodes = 3;
  EXPECT_THROW(generate_disk_mesh(o), InputError);
  o = {};
  o.electrode_coverage = 1.0;
  EXPECT_THROW(generate_disk_mesh(o), InputError);
  o = {};
  o.radius = -1;
  EXPECT_THROW(generate_disk_mesh(o), InputError);
  EXPECT_THROW(parse_density("dense"), InputError);
}

// Each bad field is named by the struct and the field, not by a command-line flag.
TEST(DiskMeshGenerator, ValidateNamesTheField) {
  using testing::input_error_at;
  EXPECT_EQ(input_error_at([] { DiskMeshOptions{}.validate(); }), "no InputError");
  const std::pair<void (*)(DiskMeshOptions&), std::string> cases[] = {
      {[](DiskMeshOptions& o) { o.electrodes = 257; }, "electrodes"},
      {[](DiskMeshOptions& o) { o.radius = INFINITY; }, "radius"},
      {[](DiskMeshOptions& o) { o.electrode_coverage = 0; }, "electrode_coverage"},
      {[](DiskMeshOptions& o) { o.size_factor = 0.05; }, "size_factor"},
  };
  for (const auto& [spoil, field] : cases) {
    DiskMeshOptions o;
    spoil(o);
    EXPECT_EQ(input_error_at([&] { o.validate(); }), "DiskMeshOptions." + field);
    EXPECT_EQ(input_error_at([&] { generate_disk_mesh(o); }), "DiskMeshOptions." + field);
  }
  EXPECT_EQ(input_error_at([] { parse_density("dense"); }), "MeshDensity.name");
}

Mesh square() {  // two triangles, four point electrodes at the corners
  Mesh m;
  m.nodes.resize(4, 2);
  m.nodes << 0, 0, 1, 0, 1, 1, 0, 1;
  m.triangles.resize(2, 3);
  m.triangles << 0, 1, 2, 0, 2, 3;
  m.electrodes.resize(4);
  for (int e = 0; e < 4; ++e) m.electrodes[e].point_node = e;
  return m;
}

TEST(ValidateMesh, AcceptsAGoodMeshAndNamesWhatIsWrong) {
  EXPECT_NO_THROW(validate_mesh(square(), "square"));
  auto expect_field = [](const Mesh& m, const std::string& field) {
    try {
      validate_mesh(m, "square.msh");
      ADD_FAILURE() << "expected an error about " << field;
    } catch (const InputError& e) {
      EXPECT_EQ(e.source(), "square.msh");
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  Mesh m = square();
  m.triangles.row(1) << 0, 3, 2;  // clockwise beside a counter-clockwise one
  expect_field(m, "triangle 1");
  m = square();
  m.nodes.row(2) << 2, 0;  // triangle 0 becomes (0,0) (1,0) (2,0): zero area
  expect_field(m, "triangle 0");
  m = square();
  m.triangles(0, 2) = 9;
  expect_field(m, "triangle 0");
  m = square();
  m.electrodes[2].point_node = -1;
  expect_field(m, "electrode_2");
  m = square();
  m.electrodes.pop_back();
  expect_field(m, "electrodes");
  m = square();
  m.electrodes[1].point_node = -1;
  m.electrodes[1].segments = {{0, 2}};  // the diagonal is interior
  expect_field(m, "electrode_1");
  m = square();
  m.nodes(3, 0) = NAN;
  expect_field(m, "nodes");
}

TEST(NormalizeMesh, FlipsAllClockwiseMeshesAndDropsUnusedNodes) {
  Mesh m = square();
  m.triangles.col(1).swap(m.triangles.col(2));
  Points nodes(5, 2);
  nodes << 9, 9, 0, 0, 1, 0, 1, 1, 0, 1;  // an unused node first
  m.nodes = nodes;
  m.triangles.array() += 1;
  for (auto& e : m.electrodes) e.point_node += 1;
  normalize_mesh(m);
  EXPECT_EQ(m.num_nodes(), 4);
  EXPECT_GT(triangle_areas(m).minCoeff(), 0);
  EXPECT_EQ(m.electrodes[0].point_node, 0);
  EXPECT_NO_THROW(validate_mesh(m, "square"));
}

}  // namespace
}  // namespace eitbench
