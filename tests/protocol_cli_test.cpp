// Protocols from the command line: a set simulated on the opposite protocol with magnitudes keeps
// its protocol through the file, a model trained on it is refused on an adjacent set, CSV
// protocols are read or refused with their line, measured frames import with one reference per
// frame, and OpenEIT's own lookup table (where ../shared holds it) is the opposite protocol.
#include <filesystem>
#include <fstream>

#include "cli_fixture.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/matlab.h"
#include "eitbench/jacobian.h"

namespace eitbench {
namespace {

using ProtocolCli = Cli;

void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

TEST_F(ProtocolCli, ASetKeepsItsProtocolAndAModelRefusesAnother) {
  const std::string opposite = path("opposite.h5"), adjacent = path("adjacent.h5");
  const Result sim =
      run("simulate --preset tiny --density coarse --quiet --protocol opposite "
          "--magnitude --out " +
          opposite);
  ASSERT_EQ(sim.exit_code, 0) << sim.output;
  const Dataset d = read_dataset(opposite);
  EXPECT_TRUE(measurement_protocol(d).same_channels(opposite_protocol(16).with_magnitude(true)));
  EXPECT_EQ(d.frames.cols(), 192);
  EXPECT_EQ(d.differences.cols(), 192);
  EXPECT_GE(d.frames.minCoeff(), 0.0);  // magnitudes
  const Result info = run("info " + opposite);
  EXPECT_NE(info.output.find("protocol: opposite (magnitudes |v|), 192 channels"),
            std::string::npos)
      << info.output;
  ASSERT_EQ(run("simulate --preset tiny --density coarse --quiet --out " + adjacent).exit_code, 0);
  EXPECT_EQ(read_dataset(adjacent).differences.cols(), 104);

  const Result train =
      run("train --data " + opposite + " --epochs 1 --quiet --out " + path("m.pt"));
  ASSERT_EQ(train.exit_code, 0) << train.output;
  const Result ok = run("reconstruct --method dnn --model " + path("m.pt") + " --data " + opposite +
                        " --png 0 --out " + path("r.h5"));
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  const Result refused = run("reconstruct --method dnn --model " + path("m.pt") + " --data " +
                             adjacent + " --png 0 --out " + path("r2.h5"));
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("protocol: the model was trained on the opposite (magnitudes), "
                                "192 channels, 192 inputs"),
            std::string::npos)
      << refused.output;
  // Flags that contradict the set's protocol are refused; those that confirm it pass.
  const Result contradicts = run("train --data " + adjacent +
                                 " --protocol opposite --epochs 1 "
                                 "--quiet --out " +
                                 path("m2.pt"));
  EXPECT_EQ(contradicts.exit_code, 2) << contradicts.output;
  EXPECT_NE(contradicts.output.find("is read on the adjacent protocol"), std::string::npos)
      << contradicts.output;
  EXPECT_EQ(run("reconstruct --data " + opposite +
                " --protocol opposite --magnitude --png 0 "
                "--frames 0:2 --out " +
                path("r3.h5"))
                .exit_code,
            0);
}

TEST_F(ProtocolCli, CsvProtocolsAreReadOrRefusedWithTheirLine) {
  const std::string good = path("p.csv"), bad = path("bad.csv");
  write_text(good, opposite_protocol(16).csv());
  const Result forward = run("forward --density coarse --conductivity 1 --protocol " + good +
                             " --out " + path("v.csv"));
  ASSERT_EQ(forward.exit_code, 0) << forward.output;
  EXPECT_NE(forward.output.find("wrote 192 values (p.csv protocol)"), std::string::npos)
      << forward.output;
  write_text(bad, "drive+,drive-,meas+,meas-\n0,8,2,1\n0,8,3,2\n0,8,2,1\n");
  const Result refused = run("forward --density coarse --conductivity 1 --protocol " + bad +
                             " --out " + path("w.csv"));
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.output.find("bad.csv: line 4: repeats the channel of line 2"),
            std::string::npos)
      << refused.output;
  EXPECT_FALSE(std::filesystem::exists(path("w.csv")));
  const Result jacobian =
      run("jacobian --density coarse --conductivity 1 --protocol skip-2 --magnitude --out " +
          path("j.h5"));
  EXPECT_EQ(jacobian.exit_code, 0) << jacobian.output;
  EXPECT_NE(jacobian.output.find("192 x"), std::string::npos) << jacobian.output;
}

TEST_F(ProtocolCli, MeasuredFramesImportWithOneReferencePerFrame) {
  // Three opposite-protocol frames and their own references, as a board recording a reference
  // before every press writes them.
  std::string frames, references;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 192; ++k) {
      frames += std::to_string(100 + k + 10 * i) + (k == 191 ? "\n" : ",");
      references += std::to_string(100 + k + i) + (k == 191 ? "\n" : ",");
    }
  write_text(path("f.csv"), frames);
  write_text(path("r.csv"), references);
  const std::string common = "import --in " + path("f.csv") + " --reference " + path("r.csv") +
                             " --protocol opposite --magnitude ";
  ASSERT_EQ(run(common + "--paired-reference --out " + path("paired.h5")).exit_code, 0);
  const Dataset paired = read_dataset(path("paired.h5"));
  EXPECT_EQ(paired.differences(2, 5), 18.0);  // (100 + 5 + 20) - (100 + 5 + 2)
  ASSERT_EQ(run(common + "--paired-reference --relative --out " + path("rel.h5")).exit_code, 0);
  // Relative to its own reference, in the mean reference's units (106 + 5 for channel 5).
  EXPECT_DOUBLE_EQ(read_dataset(path("rel.h5")).differences(2, 5), 18.0 / 107.0 * 106.0);
  ASSERT_EQ(run(common + "--out " + path("mean.h5")).exit_code, 0);
  EXPECT_EQ(read_dataset(path("mean.h5")).differences(2, 5), 19.0);  // minus the mean, 101 + 5
  write_text(path("one.csv"), references.substr(0, references.find('\n') + 1));
  const Result unpaired = run("import --in " + path("f.csv") + " --reference " + path("one.csv") +
                              " --protocol opposite --paired-reference --out " + path("x.h5"));
  EXPECT_EQ(unpaired.exit_code, 2);
  EXPECT_NE(unpaired.output.find("paired references need one per frame (3)"), std::string::npos)
      << unpaired.output;
  const Result wrong = run("import --in " + path("f.csv") + " --protocol skip-2 --out " +
                           path("y.h5"));  // skip-2 has 192 channels too: accepted
  EXPECT_EQ(wrong.exit_code, 0) << wrong.output;
  const Result adjacent = run("import --in " + path("f.csv") + " --out " + path("z.h5"));
  EXPECT_EQ(adjacent.exit_code, 2) << adjacent.output;  // 192 values fit no adjacent layout
  EXPECT_NE(adjacent.output.find("need --protocol"), std::string::npos) << adjacent.output;
}

TEST_F(ProtocolCli, AugmentingAnOppositeSetMovesFramesAndInputsAlike) {
  const std::string set = path("opp.h5"), out = path("aug.h5");
  ASSERT_EQ(run("simulate --preset tiny --density coarse --quiet --protocol opposite --out " + set)
                .exit_code,
            0);
  const Result r = run("augment --in " + set + " --group d16 --split test --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Dataset d = read_dataset(set), a = read_dataset(out);
  const int tests = static_cast<int>(d.indices(Split::test).size());
  EXPECT_EQ(a.size(), d.size() + 31 * tests);
  // The homogeneous frame is invariant under D16 (signs included), so every moved frame minus the
  // reference must equal its moved differences: frames and inputs moved consistently.
  const double scale = a.differences.cwiseAbs().maxCoeff();
  double worst = 0;
  for (int i = 0; i < a.size(); ++i)
    worst = std::max(worst,
                     (a.frames.row(i).transpose() - a.reference - a.differences.row(i).transpose())
                         .cwiseAbs()
                         .maxCoeff());
  EXPECT_LT(worst, 1e-9 * scale);
  // CSV inputs of the opposite protocol: auto keeps all of D16.
  std::string line;
  for (int k = 0; k < 192; ++k) line += std::to_string(k % 7) + (k == 191 ? "\n" : ",");
  write_text(path("in.csv"), line);
  const Result csv = run("augment --in " + path("in.csv") +
                         " --protocol opposite --group auto --out " + path("out.csv"));
  ASSERT_EQ(csv.exit_code, 0) << csv.output;
  EXPECT_NE(csv.output.find("wrote 32 frames"), std::string::npos) << csv.output;
  const Result paper = run("augment --in " + path("in.csv") +
                           " --protocol opposite --group paper --out " + path("p.csv"));
  EXPECT_EQ(paper.exit_code, 2) << paper.output;
}

TEST(OpenEitLookup, IsTheOppositeProtocol) {
  const std::string lookup =
      std::string(EITBENCH_SOURCE_DIR) + "/../shared/data/hydrogel-skin/lookup192.mat";
  if (!std::filesystem::exists(lookup)) GTEST_SKIP() << "no " << lookup << " (not committed)";
  const auto arrays = detail::read_mat_v5(read_file_bytes(lookup), lookup);
  ASSERT_EQ(arrays.size(), 1u);
  const auto& a = arrays[0];
  ASSERT_EQ(a.shape, (std::vector<std::size_t>{192, 4}));
  const MeasurementProtocol p = opposite_protocol(16);
  for (int i = 0; i < 192; ++i) {  // even numbers 0..30, electrode = value / 2, row-major here
    const Channel c{int(a.values[i * 4]) / 2, int(a.values[i * 4 + 1]) / 2,
                    int(a.values[i * 4 + 2]) / 2, int(a.values[i * 4 + 3]) / 2};
    EXPECT_EQ(c, p.channels()[i]) << "row " << i;
  }
}

}  // namespace
}  // namespace eitbench
