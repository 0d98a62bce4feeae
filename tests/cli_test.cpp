// The command-line tool as users meet it: outputs, formats, and every bad input of the corpus.
#include <H5Cpp.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_fixture.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/csv.h"
#include "eitbench/bench/io/sensor_file.h"
#include "eitbench/jacobian.h"

namespace eitbench {
namespace {
namespace fs = std::filesystem;

const std::string kSquare = kCorpus + "/../square_points.msh";

TEST_F(Cli, MeshWritesGmshAndPng) {
  const Result r = run("mesh --electrodes 8 --density coarse --out " + path("m.msh") + " --png " +
                       path("m.png"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("smallest"), std::string::npos);
  EXPECT_EQ(read_msh_file(path("m.msh")).num_electrodes(), 8);
  std::ifstream png(path("m.png"), std::ios::binary);
  char magic[8] = {};
  png.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  ASSERT_EQ(
      run("mesh --mesh " + path("m.msh") + " --msh-version 2.2 --out " + path("m22.msh")).exit_code,
      0);
  EXPECT_EQ(read_msh_file(path("m22.msh")).nodes, read_msh_file(path("m.msh")).nodes);
}

// A build without Gmsh reads the meshes `mesh --cache` wrote: node for node the generated ones.
TEST_F(Cli, MeshCacheHoldsTheGeneratedMeshExactly) {
  const std::string dir = path("meshes");
  fs::create_directories(dir);
  const Result r =
      run("mesh --electrodes 8 --density coarse --electrode-coverage 0.4 --cache " + dir);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  DiskMeshOptions o;
  o.electrodes = 8, o.density = MeshDensity::coarse, o.electrode_coverage = 0.4;
  const Mesh generated = generate_disk_mesh(o), cached = read_disk_mesh(dir, o);
  EXPECT_EQ(cached.nodes, generated.nodes);
  EXPECT_EQ(cached.triangles, generated.triangles);
  ASSERT_EQ(cached.num_electrodes(), 8);
  for (int e = 0; e < 8; ++e)
    EXPECT_EQ(cached.electrodes[e].segments, generated.electrodes[e].segments);
  // Other options name another file: it is missing, and the message names it.
  DiskMeshOptions other = o;
  other.electrode_coverage = 0.5;
  EXPECT_NE(disk_mesh_file_name(other), disk_mesh_file_name(o));
  try {
    read_disk_mesh(dir, other);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), dir + "/" + disk_mesh_file_name(other));
  }
  // A file under the name whose mesh has other electrodes is refused.
  other.electrodes = 16;
  fs::copy_file(dir + "/" + disk_mesh_file_name(o), dir + "/" + disk_mesh_file_name(other));
  EXPECT_THROW(read_disk_mesh(dir, other), InputError);
  EXPECT_NE(run("mesh --mesh " + dir + "/" + disk_mesh_file_name(o) + " --cache " + dir).exit_code,
            0);
}

TEST_F(Cli, ForwardWritesTheFrameInTheRequestedOrderAndSize) {
  const std::string common =
      "forward --electrodes 16 --density coarse --circles '0.3,0.2,0.2,0.5' --background 1";
  ASSERT_EQ(run(common + " --out " + path("full.csv")).exit_code, 0);
  ASSERT_EQ(run(common + " --values 104 --out " + path("reduced.csv")).exit_code, 0);
  ASSERT_EQ(run(common + " --order ascending --out " + path("asc.csv")).exit_code, 0);
  const auto full = read_numbers(path("full.csv")), reduced = read_numbers(path("reduced.csv")),
             asc = read_numbers(path("asc.csv"));
  ASSERT_EQ(full.size(), 208u);
  ASSERT_EQ(reduced.size(), 104u);
  const Protocol p(16);
  const Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(full.data(), 208);
  EXPECT_EQ(p.reduce(v, MeasurementOrder::rotating),
            Eigen::Map<const Eigen::VectorXd>(reduced.data(), 104));
  EXPECT_EQ(p.reorder(v, MeasurementOrder::rotating, MeasurementOrder::ascending),
            Eigen::Map<const Eigen::VectorXd>(asc.data(), 208));
}

TEST_F(Cli, ForwardOnAnImportedMeshWithElementConductivities) {
  {
    std::ofstream out(path("sigma.csv"));
    out << "2\n2\n2\n2\n";
  }
  ASSERT_EQ(run("forward --mesh " + kSquare + " --element-conductivity " + path("sigma.csv") +
                " --out " + path("a.csv"))
                .exit_code,
            0);
  ASSERT_EQ(run("forward --mesh " + kSquare + " --conductivity 2 --out " + path("b.csv")).exit_code,
            0);
  EXPECT_EQ(read_numbers(path("a.csv")).size(), 4u);  // L = 4: 4 x 1 values
  EXPECT_EQ(read_numbers(path("a.csv")), read_numbers(path("b.csv")));
}

TEST_F(Cli, JacobianAsHdf5AndCsv) {
  const std::string common = "jacobian --electrodes 16 --density coarse --conductivity 1";
  const Result h5 = run(common + " --basis pixels --out " + path("j.h5"));
  ASSERT_EQ(h5.exit_code, 0) << h5.output;
  H5::H5File file(path("j.h5"), H5F_ACC_RDONLY);
  hsize_t dims[2];
  file.openDataSet("jacobian").getSpace().getSimpleExtentDims(dims);
  EXPECT_EQ(dims[0], 208u);
  EXPECT_EQ(dims[1], 4096u);
  file.openDataSet("pairs").getSpace().getSimpleExtentDims(dims);
  EXPECT_EQ(dims[0], 208u);

  ASSERT_EQ(run(common + " --values reduced --out " + path("j.csv")).exit_code, 0);
  std::ifstream csv(path("j.csv"));
  std::string line;
  int rows = 0;
  std::size_t cols = 0;
  while (std::getline(csv, line)) ++rows, cols = std::count(line.begin(), line.end(), ',') + 1;
  const Mesh mesh = generate_disk_mesh({16, MeshDensity::coarse});
  EXPECT_EQ(rows, 104);
  EXPECT_EQ(static_cast<int>(cols), mesh.num_triangles());
}

TEST_F(Cli, EveryBadMeshIsRejectedWithoutOutput) {
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(kCorpus)) {
    if (entry.path().extension() != ".msh") continue;
    const std::string out = path("frame.csv");
    const Result r =
        run("forward --mesh " + entry.path().string() + " --conductivity 1 --out " + out);
    EXPECT_EQ(r.exit_code, 2) << entry.path() << "\n" << r.output;
    EXPECT_NE(r.output.find(entry.path().string()), std::string::npos)
        << "names the file: " << r.output;
    EXPECT_EQ(r.output.find("terminate"), std::string::npos) << "no crash: " << r.output;
    EXPECT_TRUE(files().empty()) << entry.path() << " left output behind";
    ++checked;
  }
  EXPECT_GE(checked, 15);
}

TEST_F(Cli, EveryBadConductivityFileIsRejectedWithoutOutput) {
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(kCorpus)) {
    if (entry.path().extension() != ".csv") continue;
    const Result r = run("forward --mesh " + kSquare + " --element-conductivity " +
                         entry.path().string() + " --out " + path("f.csv"));
    EXPECT_EQ(r.exit_code, 2) << entry.path() << "\n" << r.output;
    EXPECT_NE(r.output.find(entry.path().string()), std::string::npos) << r.output;
    EXPECT_TRUE(files().empty());
    ++checked;
  }
  EXPECT_EQ(checked, 4);
}

TEST_F(Cli, BadOptionsFailCleanlyAndKeepExistingOutput) {
  {
    std::ofstream keep(path("frame.csv"));
    keep << "keep me\n";
  }
  const std::string base = "forward --electrodes 16 --density coarse ";
  const std::vector<std::string> bad = {
      base + "--conductivity 1 --values 105 --out " + path("frame.csv"),
      base + "--conductivity 0 --out " + path("frame.csv"),
      base + "--conductivity 1 --contact-impedance -1 --out " + path("frame.csv"),
      base + "--circles '0,0,abc,1' --out " + path("frame.csv"),
      base + "--out " + path("frame.csv"),  // no conductivity
      base + "--conductivity 1 --order descending --out " + path("frame.csv"),
      base + "--conductivity 1 --element-conductivity x.csv --out " + path("frame.csv"),
      "forward --electrodes 2 --conductivity 1 --out " + path("frame.csv"),
      "forward --mesh " + kSquare + " --density fine --conductivity 1 --out " + path("frame.csv"),
      "jacobian --electrodes 16 --density coarse --conductivity 1 --out " + path("frame.txt"),
      base + "--conductivity 1 --out /nonexistent/folder/frame.csv",
  };
  for (const auto& args : bad) {
    const Result r = run(args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_EQ(r.output.find("terminate"), std::string::npos) << args << ": " << r.output;
    std::ifstream in(path("frame.csv"));
    std::string first;
    std::getline(in, first);
    EXPECT_EQ(first, "keep me") << args;
  }
  EXPECT_EQ(files().size(), 1u);
}

TEST_F(Cli, AugmentElementEqualsSimulatingTheMovedTouch) {
  // rot:S turns the touch by -S electrode steps; mirror:S mirrors it about the x axis first.
  const std::string common = "forward --electrodes 16 --density coarse --background 0.05 ";
  ASSERT_EQ(run(common + "--circles '0.4,0.1,0.2,0.01' --out " + path("f.csv")).exit_code, 0);
  struct Case {
    const char* element;
    double x, y;
  };
  const double a = -2 * M_PI * 3 / 16;
  for (const Case& c :
       {Case{"rot:3", std::cos(a) * 0.4 - std::sin(a) * 0.1, std::sin(a) * 0.4 + std::cos(a) * 0.1},
        Case{"mirror:0", 0.4, -0.1}}) {
    ASSERT_EQ(run("augment --in " + path("f.csv") + " --element " + c.element + " --out " +
                  path("moved.csv"))
                  .exit_code,
              0);
    const std::string circle = "'" + std::to_string(c.x) + "," + std::to_string(c.y) + ",0.2,0.01'";
    ASSERT_EQ(run(common + "--circles " + circle + " --out " + path("sim.csv")).exit_code, 0);
    const auto moved = read_numbers(path("moved.csv")), sim = read_numbers(path("sim.csv"));
    ASSERT_EQ(moved.size(), 208u);
    double worst = 0, scale = 0;
    for (std::size_t i = 0; i < 208; ++i)
      worst = std::max(worst, std::abs(moved[i] - sim[i])),
      scale = std::max(scale, std::abs(sim[i]));
    // std::to_string keeps 6 decimals of the moved centre: agreement to that precision.
    EXPECT_LT(worst, 1e-5 * scale) << c.element;
  }
}

TEST_F(Cli, AugmentGroupExpandsEveryFrameIdentityFirst) {
  ASSERT_EQ(run("forward --electrodes 8 --density coarse --circles '0.3,0.2,0.2,0.5' --order "
                "ascending --out " +
                path("a.csv"))
                .exit_code,
            0);
  ASSERT_EQ(run("forward --electrodes 8 --density coarse --circles '-0.3,0.1,0.1,3' --order "
                "ascending --out " +
                path("b.csv"))
                .exit_code,
            0);
  {
    std::ofstream two(path("two.csv"));
    std::ifstream a(path("a.csv")), b(path("b.csv"));
    two << a.rdbuf() << b.rdbuf();
  }
  const Result r = run("augment --in " + path("two.csv") +
                       " --electrodes 8 --order ascending --group d16 --out " + path("x.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Eigen::MatrixXd out = read_frames_csv(path("x.csv")), in = read_frames_csv(path("two.csv"));
  ASSERT_EQ(out.rows(), 2 * 16);
  EXPECT_EQ(Eigen::RowVectorXd(out.row(0)), Eigen::RowVectorXd(in.row(0)));
  EXPECT_EQ(Eigen::RowVectorXd(out.row(16)), Eigen::RowVectorXd(in.row(1)));
  ASSERT_EQ(run("augment --in " + path("two.csv") +
                " --electrodes 8 --order ascending --group rotations --out " + path("r.csv"))
                .exit_code,
            0);
  EXPECT_EQ(read_frames_csv(path("r.csv")).rows(), 2 * 8);
}

TEST_F(Cli, AugmentRejectsBadInputWithoutOutput) {
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(path(name)) << text;
    return path(name);
  };
  std::string row104, row103;
  for (int i = 0; i < 104; ++i) row104 += (i ? "," : "") + std::to_string(i + 1);
  for (int i = 0; i < 103; ++i) row103 += (i ? "," : "") + std::to_string(i + 1);
  const std::string good = write("good.csv", row104 + "\n");
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"augment --in " + write("short.csv", row103 + "\n") + " --group d16", "short.csv"},
      {"augment --in " + write("ragged.csv", row104 + "\n" + row103 + "\n") + " --group d16",
       "line 2"},
      {"augment --in " + write("nan.csv", "nan," + row104.substr(2) + "\n") + " --group d16",
       "nan.csv"},
      {"augment --in " + write("empty.csv", "") + " --group d16", "no frames"},
      {"augment --in " + good + " --group d8", "unknown group"},
      {"augment --in " + good + " --element spin:2", "spin:2"},
      {"augment --in " + good + " --electrodes 8 --group d16", "8 electrodes"},
      {"augment --in " + good, "--group or --element"},
      {"augment --in " + path("missing.csv") + " --group d16", "missing.csv"},
  };
  for (const auto& [args, words] : bad) {
    const Result r = run(args + " --out " + path("out.csv"));
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(words), std::string::npos) << args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(path("out.csv"))) << args;
  }
}

TEST_F(Cli, SimulateInfoShow) {
  const Result sim =
      run("simulate --preset tiny --seed 3 --density coarse --threads 2 --out " + path("d.h5"));
  ASSERT_EQ(sim.exit_code, 0) << sim.output;
  EXPECT_NE(sim.output.find("samples/s"), std::string::npos);
  const Result info = run("info " + path("d.h5"));
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("train 60"), std::string::npos) << info.output;
  ASSERT_EQ(run("show " + path("d.h5") + " --index 70 --out " + path("s.png")).exit_code, 0);
  std::ifstream png(path("s.png"), std::ios::binary);
  char magic[4] = {};
  png.read(magic, 4);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  // Bad input: no output, a named field, status 2.
  for (const auto& [args, words] : std::vector<std::pair<std::string, std::string>>{
           {"show " + path("d.h5") + " --index 81 --out " + path("x.png"), "--index"},
           {"show " + kSquare + " --out " + path("x.png"), "not an HDF5 file"},
           {"info " + path("missing.h5"), "missing.h5"},
           {"simulate --preset tiny --out " + path("nofolder/x.h5"), "does not exist"}}) {
    const Result r = run(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(words), std::string::npos) << r.output;
  }
  EXPECT_NE(run("simulate --preset huge --out " + path("x.h5")).exit_code, 0);
  EXPECT_FALSE(fs::exists(path("x.png")));
  EXPECT_FALSE(fs::exists(path("x.h5")));
}

TEST_F(Cli, AugmentDataSets) {
  ASSERT_EQ(run("simulate --preset tiny --seed 4 --density coarse --quiet --out " + path("d.h5"))
                .exit_code,
            0);
  const Result r =
      run("augment --in " + path("d.h5") + " --group rotations --split all --out " + path("r.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_dataset(path("r.h5")).size(), 81 * 16);
  ASSERT_EQ(run("augment --in " + path("d.h5") + " --group paper --out " + path("p.h5")).exit_code,
            0);
  EXPECT_EQ(read_dataset(path("p.h5")).augmentation, "paper");
  EXPECT_EQ(run("augment --in " + path("d.h5") + " --group d16 --split some --out " + path("x.h5"))
                    .exit_code != 0,
            true);
  EXPECT_FALSE(fs::exists(path("x.h5")));
}

// The shape fit writes its circles in the data set's layout, and its images are theirs.
TEST_F(Cli, ReconstructShapeWritesCirclesInTheDataSetsLayout) {
  ASSERT_EQ(run("simulate --preset tiny --seed 6 --density coarse --quiet --out " + path("d.h5"))
                .exit_code,
            0);
  const Result r = run("reconstruct --method shape --data " + path("d.h5") +
                       " --frames 0:3 --png 0 --out " + path("s.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  H5::H5File file(path("s.h5"), H5F_ACC_RDONLY);
  hsize_t dims[3];
  file.openDataSet("circles").getSpace().getSimpleExtentDims(dims);
  ASSERT_EQ(dims[0], 3u);
  ASSERT_EQ(dims[1], 4u);
  ASSERT_EQ(dims[2], 4u);
  std::vector<double> circles(3 * 4 * 4);
  file.openDataSet("circles").read(circles.data(), H5::PredType::NATIVE_DOUBLE);
  std::vector<int> count(3);
  file.openDataSet("circle_count").read(count.data(), H5::PredType::NATIVE_INT);
  std::vector<float> images(3 * 64 * 64);
  file.openDataSet("images").read(images.data(), H5::PredType::NATIVE_FLOAT);
  const Dataset data = read_dataset(path("d.h5"));
  const PixelGrid grid(64, data.radius);
  for (int i = 0; i < 3; ++i) {
    ASSERT_GE(count[i], 0);
    ASSERT_LE(count[i], 4);
    std::vector<Circle> found;
    for (int k = 0; k < 4; ++k) {
      const double* c = &circles[(i * 4 + k) * 4];
      EXPECT_EQ(std::isnan(c[0]), k >= count[i]) << "frame " << i << " row " << k;
      if (k < count[i]) found.push_back({c[0], c[1], c[2], c[3]});
    }
    const Eigen::VectorXd drawn = circles_image(grid, found, data.background);
    for (int p = 0; p < 64 * 64; ++p)
      ASSERT_NEAR(images[i * 4096 + p], drawn[p], 1e-6) << "frame " << i << " pixel " << p;
  }
}

// --touches N keeps the split's frames with N true touches: as many images as the data set has
// such frames; data without circles, or no such frame, is refused.
TEST_F(Cli, ReconstructTouchesSelectsFramesByTheirTouchCount) {
  ASSERT_EQ(run("simulate --preset tiny --seed 6 --density coarse --quiet --out " + path("d.h5"))
                .exit_code,
            0);
  const Dataset data = read_dataset(path("d.h5"));
  hsize_t expected = 0;
  for (int row : data.indices(Split::train)) expected += data.circles[row].size() == 2;
  ASSERT_GT(expected, 0u);
  const Result r = run("reconstruct --method noser --data " + path("d.h5") +
                       " --split train --touches 2 --png 0 --out " + path("two.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  hsize_t dims[3];
  H5::H5File(path("two.h5"), H5F_ACC_RDONLY)
      .openDataSet("images")
      .getSpace()
      .getSimpleExtentDims(dims);
  EXPECT_EQ(dims[0], expected);
  const Result none = run("reconstruct --method noser --data " + path("d.h5") +
                          " --split test --touches 1 --png 0 --out " + path("none.h5"));
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.output.find("circle_count"), std::string::npos) << none.output;
  EXPECT_FALSE(fs::exists(path("none.h5")));
}

// calibrate recovers a sensor from the frame that sensor gives (forward --sensor), and its file
// sets up forward and reconstruct; a file for another electrode count is refused.
TEST_F(Cli, CalibrateRecoversTheSensorThatMadeTheFrame) {
  std::vector<double> z;
  for (int e = 0; e < 16; ++e) z.push_back(0.01 * (0.5 + 0.1 * e));
  nlohmann::json truth = {{"format", "eitbench-sensor-1"},
                          {"electrodes", 16},
                          {"background", 0.05},
                          {"contact_impedances", z},
                          {"current", 1.0}};
  std::ofstream(path("truth.json")) << truth.dump();
  const std::string mesh = " --electrodes 16 --density coarse";
  ASSERT_EQ(run("forward" + mesh + " --sensor " + path("truth.json") +
                " --conductivity 0.05 --out " + path("ref.csv"))
                .exit_code,
            0);
  const Result r = run("calibrate" + mesh + " --reference " + path("ref.csv") +
                       " --background 0.1 --out " + path("fit.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const SensorFile fit = read_sensor_file(path("fit.json"));
  EXPECT_NEAR(fit.background, 0.05, 1e-7);
  for (int e = 0; e < 16; ++e) EXPECT_NEAR(fit.contact_impedances[e] / z[e], 1, 1e-4) << e;
  EXPECT_TRUE(fit.converged);
  // The fitted sensor reproduces the frame.
  ASSERT_EQ(run("forward" + mesh + " --sensor " + path("fit.json") + " --conductivity 0.05 --out " +
                path("again.csv"))
                .exit_code,
            0);
  const Eigen::MatrixXd a = read_frames_csv(path("ref.csv")),
                        b = read_frames_csv(path("again.csv"));
  EXPECT_LT((a - b).norm(), 1e-6 * a.norm());
  // Eight electrodes' mesh, sixteen electrodes' sensor: refused, nothing written.
  const Result bad = run("forward --electrodes 8 --density coarse --sensor " + path("fit.json") +
                         " --conductivity 1 --out " + path("x.csv"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("electrodes"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(path("x.csv")));
  std::ofstream(path("broken.json")) << "{\"format\": \"eitbench-sensor-1\", \"electrodes\": 16}";
  const Result broken = run("forward" + mesh + " --sensor " + path("broken.json") +
                            " --conductivity 1 --out " + path("x.csv"));
  EXPECT_EQ(broken.exit_code, 2);
  EXPECT_NE(broken.output.find("background"), std::string::npos) << broken.output;
}

// From an L x L map (forward --values map) the same sensor comes back, and calibrate says nothing
// of the impedances being undetermined; from a frame it says so.
TEST_F(Cli, CalibrateReadsAdjacentMaps) {
  std::vector<double> z;
  for (int e = 0; e < 16; ++e) z.push_back(0.01 * (1.5 - 0.05 * e));
  nlohmann::json truth = {{"format", "eitbench-sensor-1"},
                          {"electrodes", 16},
                          {"background", 0.2},
                          {"contact_impedances", z},
                          {"current", 1.0}};
  std::ofstream(path("truth.json")) << truth.dump();
  const std::string mesh = " --electrodes 16 --density coarse";
  ASSERT_EQ(run("forward" + mesh + " --sensor " + path("truth.json") +
                " --conductivity 0.2 --values map --out " + path("map.csv"))
                .exit_code,
            0);
  EXPECT_EQ(read_frames_csv(path("map.csv")).size(), 256);
  const Result r =
      run("calibrate" + mesh + " --reference " + path("map.csv") + " --out " + path("fit.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("note:"), std::string::npos) << r.output;
  const SensorFile fit = read_sensor_file(path("fit.json"));
  EXPECT_NEAR(fit.background, 0.2, 1e-7);
  for (int e = 0; e < 16; ++e) EXPECT_NEAR(fit.contact_impedances[e] / z[e], 1, 1e-4) << e;
  ASSERT_EQ(run("forward" + mesh + " --sensor " + path("truth.json") +
                " --conductivity 0.2 --out " + path("frame.csv"))
                .exit_code,
            0);
  const Result f =
      run("calibrate" + mesh + " --reference " + path("frame.csv") + " --out " + path("fit2.json"));
  ASSERT_EQ(f.exit_code, 0) << f.output;
  EXPECT_NE(f.output.find("note:"), std::string::npos) << f.output;
}

TEST_F(Cli, ReconstructWritesImagesScoresAndPictures) {
  ASSERT_EQ(run("simulate --preset tiny --seed 6 --density coarse --quiet --out " + path("d.h5"))
                .exit_code,
            0);
  const Result r = run("reconstruct --method noser --choose validation --data " + path("d.h5") +
                       " --frames 0:5 --snr 40 --png 2 --out " + path("img.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("CC "), std::string::npos) << r.output;
  H5::H5File file(path("img.h5"), H5F_ACC_RDONLY);
  hsize_t dims[3];
  file.openDataSet("images").getSpace().getSimpleExtentDims(dims);
  EXPECT_EQ(dims[0], 5u);
  EXPECT_EQ(dims[1], 64u);
  file.openDataSet("scores").getSpace().getSimpleExtentDims(dims);
  EXPECT_EQ(dims[1], 4u);
  EXPECT_TRUE(fs::exists(path("img_0.png")));
  EXPECT_TRUE(fs::exists(path("img_1.png")));
  EXPECT_FALSE(fs::exists(path("img_2.png")));
  ASSERT_EQ(run("reconstruct --method tv --data " + path("d.h5") + " --frames 0:2 --png 0 --out " +
                path("tv.h5"))
                .exit_code,
            0);
  // Measured frames without labels: images, no scores.
  const std::string data = kCorpus + "/../data/";
  const Result m = run("reconstruct --method laplace --data " + data + "frames.csv --reference " +
                       data + "reference.csv --png 0 --out " + path("m.h5"));
  ASSERT_EQ(m.exit_code, 0) << m.output;
  H5::H5File measured(path("m.h5"), H5F_ACC_RDONLY);
  EXPECT_FALSE(measured.nameExists("scores"));
  for (const auto& [args, words] : std::vector<std::pair<std::string, std::string>>{
           {"reconstruct --data " + path("d.h5") + " --frames 5:2 --out " + path("x.h5"),
            "--frames"},
           {"reconstruct --data " + data + "frames.csv --choose validation --out " + path("x.h5"),
            "validation"},
           {"reconstruct --data " + path("d.h5") + " --electrodes 8 --out " + path("x.h5"),
            "electrodes"},
           {"reconstruct --data " + data + "bad_nan.npy --out " + path("x.h5"), "bad_nan.npy"},
           // TV has no GCV: refused, naming the flag, instead of keeping its default weight.
           {"reconstruct --method tv --choose gcv --data " + path("d.h5") + " --out " +
                path("x.h5"),
            "--choose: gcv needs a one-step linear method"},
           // Validation frames by hand: --split validation reconstructs them.
           {"reconstruct --data " + data + "frames.csv --split validation --out " + path("x.h5"),
            "no validation frames"}}) {
    const Result bad = run(args);
    EXPECT_EQ(bad.exit_code, 2) << args << "\n" << bad.output;
    EXPECT_NE(bad.output.find(words), std::string::npos) << bad.output;
  }
  EXPECT_NE(
      run("reconstruct --data " + path("d.h5") + " --lambda -1 --out " + path("x.h5")).exit_code,
      0);
  EXPECT_FALSE(fs::exists(path("x.h5")));
}

TEST_F(Cli, ImportMeasuredFrames) {
  const std::string data = kCorpus + "/../data/";
  const Result r = run("import --in " + data + "frames_v73.mat --reference " + data +
                       "reference.npy --out " + path("m.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("reciprocity error"), std::string::npos) << r.output;
  EXPECT_EQ(read_dataset(path("m.h5")).size(), 3);
  const Result bad = run("import --in " + data + "bad_nan.npy --out " + path("bad.h5"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("bad_nan.npy"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(path("bad.h5")));
  EXPECT_EQ(
      run("import --in " + data + "frames.csv --electrodes 8 --out " + path("bad.h5")).exit_code,
      2);
  EXPECT_FALSE(fs::exists(path("bad.h5")));
}

// Flags refused while parsing are bad input too: exit 2, a message naming the flag, no output.
TEST_F(Cli, RefusedFlagsExitTwoAndWriteNothing) {
  const std::pair<std::string, std::string> cases[] = {{"train --floor 2", "--floor"},
                                                       {"train --warmup -1", "--warmup"},
                                                       {"reconstruct --lambda -1", "--lambda"},
                                                       {"mesh --no-such-flag", "--no-such-flag"}};
  for (const auto& [args, flag] : cases) {
    const Result r = run(args + " --out " + path("refused.out"));
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(flag), std::string::npos) << args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(path("refused.out"))) << args;
  }
}

// The libraries name a bad option by its struct and field; the user still reads the flag. The
// warm-up and the decay are each in range, so only the schedule's own check can refuse them.
TEST_F(Cli, OptionsRefusedByALibraryNameTheFlag) {
  const Result r = run("train --data " + path("missing.h5") + " --warmup 0.5 --decay 0.4 --out " +
                       path("model.pt"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--warmup: the warm-up must end before the decay does"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("ScheduleOptions"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(path("model.pt")));
}

// simulate --shard K/N and merge from the command line: the merged set equals one process's,
// info names a shard, a command that needs a set refuses one, and every refusal exits 2 leaving
// no output.
TEST_F(Cli, ShardsSimulateSeparatelyAndMergeIntoOneSet) {
  const std::string common = "simulate --preset tiny --seed 8 --density coarse --quiet ";
  ASSERT_EQ(run(common + "--out " + path("whole.h5")).exit_code, 0);
  for (int k = 0; k < 3; ++k) {
    const Result r = run(common + "--threads " + std::to_string(1 + k % 2) + " --shard " +
                         std::to_string(k) + "/3 --out " + path("s" + std::to_string(k) + ".h5"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  const Result info = run("info " + path("s1.h5"));
  EXPECT_NE(info.output.find("shard 1 of 3"), std::string::npos) << info.output;
  const Result use = run("augment --in " + path("s1.h5") + " --group d16 --out " + path("a.h5"));
  EXPECT_EQ(use.exit_code, 2) << use.output;
  EXPECT_NE(use.output.find("eitbench merge"), std::string::npos) << use.output;
  EXPECT_FALSE(fs::exists(path("a.h5")));

  const Result missing =
      run("merge " + path("s2.h5") + " " + path("s0.h5") + " --out " + path("m.h5"));
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("shard(s) 1 of 3 missing"), std::string::npos) << missing.output;
  EXPECT_FALSE(fs::exists(path("m.h5")));
  const Result merged = run("merge " + path("s2.h5") + " " + path("s0.h5") + " " + path("s1.h5") +
                            " --out " + path("m.h5"));
  ASSERT_EQ(merged.exit_code, 0) << merged.output;
  const Dataset whole = read_dataset(path("whole.h5")), m = read_dataset(path("m.h5"));
  EXPECT_EQ(m.frames, whole.frames);
  EXPECT_EQ(m.differences, whole.differences);
  EXPECT_EQ(m.labels, whole.labels);
  EXPECT_EQ(m.split, whole.split);

  for (const std::string bad : {"--shard 3/3", "--shard 1", "--shard a/b", "--shard 1/0"}) {
    const Result r = run(common + bad + " --out " + path("bad.h5"));
    EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.output;
    EXPECT_NE(r.output.find("--shard"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(path("bad.h5")));
  }
  const Result folder = run("merge " + path("") + " --out " + path("m2.h5"));
  EXPECT_EQ(folder.exit_code, 2) << folder.output;
  const Result onto = run("merge " + path("s0.h5") + " " + path("s1.h5") + " " + path("s2.h5") +
                          " --out " + path("s1.h5"));
  EXPECT_EQ(onto.exit_code, 2) << onto.output;  // no output replaces an input
}

TEST_F(Cli, HelpIsAvailableEverywhere) {
  for (const std::string sub :
       {"", "mesh", "forward", "jacobian", "augment", "simulate", "info", "show", "import",
        "reconstruct", "train", "run", "compare", "history", "history add", "history show",
        "calibrate", "report", "merge"}) {
    const Result r = run(sub + " --help");
    EXPECT_EQ(r.exit_code, 0) << sub;
    EXPECT_NE(r.output.find("--"), std::string::npos);
  }
}

}  // namespace
}  // namespace eitbench
