// Gmsh files: our writer and reader round-trip, Gmsh itself reads what we write, we read what
// Gmsh writes, and every defect in the bad-input corpus is named.
#include <gmsh.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "eitbench/jacobian.h"
#include "test_support.h"

namespace eitbench {
// Found by argument-dependent lookup: names the format in test output.
void PrintTo(MshVersion v, std::ostream* os) {
  *os << (v == MshVersion::v22 ? "2.2" : "4.1");
}

namespace {
namespace fs = std::filesystem;

std::string msh_path(const std::string& name) {
  return (fs::temp_directory_path() / ("eitbench_test_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

void expect_same(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.num_nodes(), b.num_nodes());
  EXPECT_EQ(a.nodes, b.nodes);  // 17 significant digits round-trip exactly
  EXPECT_EQ(a.triangles, b.triangles);
  ASSERT_EQ(a.num_electrodes(), b.num_electrodes());
  for (int e = 0; e < a.num_electrodes(); ++e) {
    EXPECT_EQ(a.electrodes[e].segments, b.electrodes[e].segments);
    EXPECT_EQ(a.electrodes[e].point_node, b.electrodes[e].point_node);
  }
}

class MshRoundTrip : public ::testing::TestWithParam<MshVersion> {};

TEST_P(MshRoundTrip, WriteThenReadGivesTheSameMesh) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  std::stringstream file;
  write_msh(file, mesh, GetParam());
  expect_same(mesh, read_msh(file, "memory"));
}

TEST_P(MshRoundTrip, PointElectrodesRoundTrip) {
  std::ifstream in(std::string(EITBENCH_BAD_INPUTS) + "/../square_points.msh");
  const Mesh mesh = read_msh(in, "square_points.msh");
  ASSERT_EQ(mesh.num_electrodes(), 4);
  EXPECT_TRUE(mesh.electrodes[2].is_point());
  std::stringstream file;
  write_msh(file, mesh, GetParam());
  expect_same(mesh, read_msh(file, "memory"));
}

TEST_P(MshRoundTrip, GmshReadsWhatWeWrite) {
  const Mesh& mesh = testing::disk(8, MeshDensity::coarse);
  const std::string path = msh_path("ours.msh");
  {
    std::ofstream out(path);
    write_msh(out, mesh, GetParam());
  }
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::open(path);
  std::vector<std::size_t> triangles, triangle_nodes, tags,
      nodes;  // fresh vectors: Gmsh 4.8 appends
  gmsh::model::mesh::getElementsByType(2, triangles, triangle_nodes);
  EXPECT_EQ(static_cast<int>(triangles.size()), mesh.num_triangles());
  gmsh::model::mesh::getElementsByType(1, tags, nodes);
  std::size_t segments = 0;
  for (const auto& e : mesh.electrodes) segments += e.segments.size();
  EXPECT_EQ(tags.size(), segments);
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, 1);
  ASSERT_EQ(groups.size(), 8u);
  std::string name;
  gmsh::model::getPhysicalName(1, groups[3].second, name);
  EXPECT_EQ(name, "electrode_3");
  gmsh::finalize();
  fs::remove(path);
}

INSTANTIATE_TEST_SUITE_P(Versions, MshRoundTrip,
                         ::testing::Values(MshVersion::v22, MshVersion::v41), [](const auto& info) {
                           return info.param == MshVersion::v22 ? "v22" : "v41";
                         });

// A disk with L electrodes built and meshed by Gmsh itself, written in the given format.
void gmsh_disk(const std::string& path, int L, bool point_electrodes, const std::string& version) {
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  namespace geo = gmsh::model::geo;
  const int centre = geo::addPoint(0, 0, 0);
  std::vector<int> points, arcs;
  for (int e = 0; e < L; ++e)
    for (double offset : {-0.1, 0.1}) {
      const double a = 2 * M_PI * e / L + offset;
      points.push_back(geo::addPoint(std::cos(a), std::sin(a), 0, 0.1));
    }
  for (std::size_t i = 0; i < points.size(); ++i)
    arcs.push_back(geo::addCircleArc(points[i], centre, points[(i + 1) % points.size()]));
  const int surface = geo::addPlaneSurface({geo::addCurveLoop(arcs)});
  geo::synchronize();
  for (int e = 0; e < L; ++e) {
    const int tag = point_electrodes ? gmsh::model::addPhysicalGroup(0, {points[2 * e]})
                                     : gmsh::model::addPhysicalGroup(1, {arcs[2 * e]});
    gmsh::model::setPhysicalName(point_electrodes ? 0 : 1, tag, "electrode_" + std::to_string(e));
  }
  gmsh::model::setPhysicalName(2, gmsh::model::addPhysicalGroup(2, {surface}), "sensor");
  gmsh::model::mesh::generate(2);
  gmsh::option::setNumber("Mesh.MshFileVersion", std::stod(version));
  gmsh::write(path);
  gmsh::finalize();
}

TEST(MshImport, ReadsMeshesThatGmshWrites) {
  for (const std::string version : {"2.2", "4.1"})
    for (bool points : {false, true}) {
      const std::string path = msh_path("gmsh.msh");
      gmsh_disk(path, 8, points, version);
      const Mesh mesh = read_msh_file(path);
      fs::remove(path);
      ASSERT_EQ(mesh.num_electrodes(), 8) << version;
      EXPECT_NEAR(triangle_areas(mesh).sum(), M_PI, 0.02);
      for (int e = 0; e < 8; ++e) {
        EXPECT_EQ(mesh.electrodes[e].is_point(), points);
        const Eigen::Vector2d at =
            points ? Eigen::Vector2d(mesh.nodes.row(mesh.electrodes[e].point_node))
                   : Eigen::Vector2d(mesh.nodes.row(mesh.electrodes[e].segments[0][0]));
        EXPECT_NEAR(std::remainder(std::atan2(at.y(), at.x()) - 2 * M_PI * e / 8, 2 * M_PI), 0.0,
                    0.11);
      }
      // And the solver takes it.
      const ForwardModel model(mesh);
      const Eigen::VectorXd v = model.frame(Eigen::VectorXd::Ones(mesh.num_triangles()));
      EXPECT_LT(model.protocol().reciprocity_error(v, MeasurementOrder::rotating), 1e-10);
    }
}

struct BadFile {
  const char* file;
  const char* field;  // a word the message must contain
};

void PrintTo(const BadFile& f, std::ostream* os) {
  *os << f.file;
}

class MshBadInput : public ::testing::TestWithParam<BadFile> {};

TEST_P(MshBadInput, IsRejectedWithTheFileAndFieldNamed) {
  const std::string path = std::string(EITBENCH_BAD_INPUTS) + "/" + GetParam().file;
  try {
    read_msh_file(path);
    FAIL() << "accepted " << path;
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), path);
    EXPECT_NE(std::string(e.what()).find(GetParam().field), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Corpus, MshBadInput,
    ::testing::Values(
        BadFile{"empty.msh", "empty"}, BadFile{"truncated.msh", "ends early"},
        BadFile{"binary.msh", "binary"}, BadFile{"unknown_version.msh", "version 3.0"},
        BadFile{"electrode_gap.msh", "electrode_2"}, BadFile{"no_electrodes.msh", "electrode_0"},
        BadFile{"missing_node.msh", "node 9"}, BadFile{"duplicate_node.msh", "defined twice"},
        BadFile{"huge_count.msh", "more than the file can hold"},
        BadFile{"not_a_number.msh", "'one' is not a number"}, BadFile{"nan_coordinate.msh", "NaN"},
        BadFile{"folded_mesh.msh", "the mesh folds over itself"},
        BadFile{"zero_area.msh", "zero area"}, BadFile{"quadratic_elements.msh", "element type 9"},
        BadFile{"no_triangles.msh", "no triangles"}, BadFile{"not_msh.msh", "$MeshFormat"}),
    [](const auto& info) {
      std::string name = info.param.file;
      return name.substr(0, name.find('.'));
    });

// EIDORS writes triangles in either orientation (half of its d2C2 disk is clockwise). The reader
// turns each clockwise triangle round, counts them, and the forward model's voltages are the
// consistently oriented mesh's.
TEST(MshImport, MixedOrientationImportsWithTheSameVoltages) {
  const Mesh ccw = generate_disk_mesh({16, MeshDensity::coarse});
  Mesh mixed = ccw;
  for (int t = 0; t < mixed.num_triangles(); t += 2)
    std::swap(mixed.triangles(t, 1), mixed.triangles(t, 2));
  std::stringstream text;
  write_msh(text, mixed, MshVersion::v41);
  const Mesh read = read_msh(text, "mixed.msh");
  EXPECT_EQ(read.reoriented, (ccw.num_triangles() + 1) / 2);
  EXPECT_GT(triangle_areas(read).minCoeff(), 0);
  const Eigen::VectorXd sigma = Eigen::VectorXd::LinSpaced(ccw.num_triangles(), 0.5, 2.0);
  const Eigen::VectorXd a = ForwardModel(ccw).frame(sigma), b = ForwardModel(read).frame(sigma);
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-12 * a.cwiseAbs().maxCoeff());
}

// A triangle turned round because the mesh folds (its node pulled across a neighbour) overlaps
// that neighbour: refused, naming both.
TEST(MshImport, AFoldedMeshIsRefused) {
  Mesh folded = generate_disk_mesh({16, MeshDensity::coarse});
  const int t = 0, node = folded.triangles(t, 0);
  // Pull the node through the opposite edge: the triangle inverts and overlaps its neighbours.
  const Eigen::RowVector2d mid =
      0.5 * (folded.nodes.row(folded.triangles(t, 1)) + folded.nodes.row(folded.triangles(t, 2)));
  folded.nodes.row(node) = folded.nodes.row(node) + 2.5 * (mid - folded.nodes.row(node));
  std::stringstream text;
  write_msh(text, folded, MshVersion::v41);
  try {
    read_msh(text, "folded.msh");
    FAIL() << "a folded mesh was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("folds over itself"), std::string::npos) << e.what();
  }
}

TEST(MshImport, MissingFileIsNamed) {
  try {
    read_msh_file("/nonexistent/sensor.msh");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "/nonexistent/sensor.msh");
  }
}

}  // namespace
}  // namespace eitbench
