// Press sets: measured frames with the touches' known positions, imported from a file of touches
// and kept through the data set's file; every bad touch file refused naming the file and row.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "cli_fixture.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/measurements.h"
#include "eitbench/bench/data/press_touches.h"
#include "eitbench/bench/io/numpy.h"
#include "eitbench/bench/io/sensor_file.h"
#include "eitbench/bench/methods/press_scores.h"
#include "test_support.h"

namespace eitbench {
namespace {

const std::string kFrames = std::string(EITBENCH_BAD_INPUTS) + "/../data/frames.csv";  // 3 frames

Dataset read_dataset_from_import() {
  return import_measurements(kFrames, "", ImportOptions{});
}

class PressSet : public Cli {
 protected:
  std::string text_file(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  std::string import(const std::string& touches, const std::string& more = "") const {
    return "import --in " + kFrames + " --touches " + touches + " --out " + path("set.h5") + " " +
           more;
  }
  // A press set made from the tiny preset's one-touch frames: each press at its circle's centre.
  Dataset stand_in_presses() const {
    const Result made = run("simulate --preset tiny --quiet --out " + path("tiny.h5"));
    EXPECT_EQ(made.exit_code, 0) << made.output;  // and read_dataset throws on a missing file
    Dataset d = read_dataset(path("tiny.h5"));
    d.touches.clear();
    for (const auto& circles : d.circles) d.touches.push_back({{circles[0].x, circles[0].y, NAN}});
    return d;
  }
};

TEST_F(PressSet, TouchesComeThroughTheFileScaledToTheMesh) {
  // Millimetres on a sensor of radius 70 mm, to the unit disk.
  const std::string csv = text_file("t.csv", "35,0\n0,-70\n-10.5,14\n");
  const Result r = run(import(csv, "--touch-scale 0.0142857142857143"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("touches: one a frame"), std::string::npos) << r.output;
  const Dataset d = read_dataset(path("set.h5"));
  ASSERT_EQ(d.touches.size(), 3u);
  EXPECT_NEAR(d.touches[0][0].x, 0.5, 1e-12);
  EXPECT_NEAR(d.touches[1][0].y, -1.0, 1e-12);  // on the rim: inside
  EXPECT_NEAR(d.touches[2][0].x, -0.15, 1e-12);
  EXPECT_NEAR(d.touches[2][0].y, 0.2, 1e-12);
  EXPECT_TRUE(std::isnan(d.touches[0][0].size));
  EXPECT_EQ(d.touch_size, "");
  EXPECT_EQ(d.radius, 1.0);
  const Result info = run("info " + path("set.h5"));
  EXPECT_NE(info.output.find("touches (a press set): 0 / 3 / 0 / 0 / 0 frames"), std::string::npos)
      << info.output;

  // A third column: the depth, scaled as a length; a radius of 70 keeps millimetres.
  const std::string npy = path("t.npy");
  std::ofstream(npy, std::ios::binary)
      << detail::npy_bytes({35, 0, 10, 0, -70, 20, -10.5f, 14, 15}, {3, 3});
  const Result deep =
      run("import --in " + kFrames + " --touches " + npy + " --radius 70 --out " + path("d.h5"));
  ASSERT_EQ(deep.exit_code, 0) << deep.output;
  const Dataset e = read_dataset(path("d.h5"));
  EXPECT_EQ(e.touch_size, "depth");
  EXPECT_EQ(e.radius, 70.0);
  EXPECT_EQ(e.touches[1][0].size, 20.0);
  EXPECT_EQ(e.touches[2][0].x, -10.5);
  EXPECT_NE(run("info " + path("d.h5")).output.find("touch depth: 10 .. 20"), std::string::npos);

  // Mirrored (y -> -y), then turned a quarter counter-clockwise: (x, y) -> (y, x).
  ASSERT_EQ(run(import(csv, "--touch-scale 0.0142857142857143 --touch-mirror --touch-rotate 90"))
                .exit_code,
            0);
  const Dataset turned = read_dataset(path("set.h5"));
  EXPECT_NEAR(turned.touches[0][0].x, 0.0, 1e-12);
  EXPECT_NEAR(turned.touches[0][0].y, 0.5, 1e-12);
  EXPECT_NEAR(turned.touches[1][0].x, -1.0, 1e-12);
  EXPECT_NEAR(turned.touches[2][0].x, 0.2, 1e-12);
  EXPECT_NEAR(turned.touches[2][0].y, -0.15, 1e-12);
}

// Where a method puts each press: the strongest touch it finds, or the centre when it finds none.
TEST(PressScores, TheStrongestTouchOrTheCentre) {
  const std::vector<std::vector<PressTouch>> truth = {
      {{0.5, 0.0, NAN}}, {{0.4, 0.0, NAN}}, {{0.0, -0.2, NAN}}};
  const TouchFrames found = {
      {{0.5, 0.3, 0.1, 0.9}, {0.5, 0.05, 0.1, 0.2}},  // the stronger one is 0.3 off
      {},                                             // none: the centre, 0.4 off
      {{0.0, -0.2, 0.1, 0.5}}};                       // exact
  const PressScores s = score_presses(found, truth);
  EXPECT_EQ(s.frames, 3);
  EXPECT_EQ(s.none_found, 1);
  EXPECT_NEAR(s.median, 0.3, 1e-15);
  EXPECT_NEAR(s.mean, 0.7 / 3, 1e-15);
  EXPECT_NEAR(s.p90, 0.38, 1e-15);  // rank 1.8 of 0, 0.3, 0.4
  const PressScores floor = centre_floor(truth);
  EXPECT_NEAR(floor.median, 0.4, 1e-15);
  EXPECT_EQ(floor.none_found, 3);
  EXPECT_EQ(testing::input_error_at([&] {
              score_presses({{}, {}, {}}, {{{0, 0, NAN}, {0.1, 0, NAN}}, {}, {}});
            }),
            "press set.touches");
}

// The same scores by the press's true distance from the centre, on a sensor of radius 2: each
// press counted in its own band, the last band open beyond the rim, an empty band NaN.
TEST(PressScores, ByDistanceFromTheCentre) {
  const std::vector<std::vector<PressTouch>> truth = {
      {{0.4, 0.0, NAN}}, {{0.0, 1.2, NAN}}, {{1.7, 0.0, NAN}}, {{0.0, -2.1, NAN}}};
  const TouchFrames found = {{{0.4, 0.5, 0.1, 1}},    // 0.2 R from the centre: 0.5 off
                             {},                      // 0.6 R, none found: the centre, 1.2 off
                             {{1.6, 0.0, 0.1, 1}},    // 0.85 R: 0.1 off
                             {{0.0, -2.0, 0.1, 1}}};  // 1.05 R, beyond the rim: 0.1 off
  const std::vector<PressBand> bands = score_presses_by_distance(found, truth, 2.0);
  ASSERT_EQ(bands.size(), 3u);
  EXPECT_EQ(bands[0].inner, 0);
  EXPECT_EQ(bands[0].outer, 0.5);
  EXPECT_EQ(bands[2].outer, INFINITY);
  EXPECT_EQ(bands[0].scores.frames, 1);
  EXPECT_NEAR(bands[0].scores.mean, 0.5, 1e-15);
  EXPECT_EQ(bands[1].scores.frames, 1);
  EXPECT_EQ(bands[1].scores.none_found, 1);
  EXPECT_NEAR(bands[1].scores.mean, 1.2, 1e-15);
  EXPECT_EQ(bands[2].scores.frames, 2);
  EXPECT_NEAR(bands[2].scores.mean, 0.1, 1e-12);
  // From the positions each frame's press was put at, the same.
  std::vector<Eigen::Vector2d> at;
  for (const auto& f : found) at.push_back(located_press(f, Eigen::Vector2d::Zero()));
  const std::vector<PressBand> from_positions = score_positions_by_distance(at, truth, 2.0);
  ASSERT_EQ(from_positions.size(), 3u);
  for (std::size_t b = 0; b < 3; ++b)
    EXPECT_EQ(from_positions[b].scores.mean, bands[b].scores.mean) << b;
  // The bands split the frames: their counts sum to all, their means weigh to the overall mean.
  const PressScores all = score_presses(found, truth);
  EXPECT_NEAR((bands[0].scores.mean + bands[1].scores.mean + 2 * bands[2].scores.mean) / 4,
              all.mean, 1e-12);
  const std::vector<PressBand> fine = score_presses_by_distance(found, truth, 2.0, {0, 0.1});
  EXPECT_EQ(fine[0].scores.frames, 0);
  EXPECT_TRUE(std::isnan(fine[0].scores.mean));
  EXPECT_EQ(fine[1].scores.frames, 4);
  EXPECT_EQ(testing::input_error_at([&] { score_presses_by_distance(found, truth, 2.0, {0.1}); }),
            "press bands.edges");
  EXPECT_EQ(testing::input_error_at([&] { score_presses_by_distance(found, truth, 0.0); }),
            "press bands.radius");
}

// Where a band's presses are put: every press found turned by 20 degrees counter-clockwise and at
// 1.5 times its radius gives those back as the band's turn and mean radii; a press at the centre
// or none found (put at the centre) has no angle and counts only in the radii.
TEST(PressScores, PlacementGivesTheBandsTurnAndRadii) {
  const double turn = 20 * M_PI / 180;
  const std::vector<std::vector<PressTouch>> truth = {{{0.3, 0.0, NAN}},
                                                      {{0.0, -0.2, NAN}},
                                                      {{-0.25, 0.1, NAN}},
                                                      {{0.0, 0.0, NAN}},
                                                      {{0.9, 0.0, NAN}}};
  TouchFrames found;
  for (std::size_t i = 0; i < 3; ++i) {
    const Eigen::Vector2d t(truth[i][0].x, truth[i][0].y);
    const Eigen::Vector2d at = 1.5 * (Eigen::Rotation2Dd(turn) * t);
    found.push_back({{at.x(), at.y(), 0.1, 1}});
  }
  found.push_back({{0.1, 0.0, 0.1, 1}});  // the press at the centre: no angle to turn
  found.push_back({});                    // none found: put at the centre
  const std::vector<PressBand> bands = score_presses_by_distance(found, truth, 1.0, {0, 0.5});
  ASSERT_EQ(bands.size(), 2u);
  const PressPlacement& inner = bands[0].placement;
  const double radii = 0.3 + 0.2 + std::hypot(0.25, 0.1);
  EXPECT_NEAR(inner.true_radius, radii / 4, 1e-12);
  EXPECT_NEAR(inner.found_radius, (1.5 * radii + 0.1) / 4, 1e-12);
  EXPECT_NEAR(inner.turn_degrees, 20, 1e-9);
  const PressPlacement& rim = bands[1].placement;
  EXPECT_NEAR(rim.true_radius, 0.9, 1e-15);
  EXPECT_EQ(rim.found_radius, 0);
  EXPECT_TRUE(std::isnan(rim.turn_degrees));
  // A turn across the negative x axis is the short way round: from 170 to -170 degrees is +20,
  // not -340, and back -20.
  const auto polar = [](double degrees) {
    return Eigen::Vector2d(0.5 * std::cos(degrees * M_PI / 180),
                           0.5 * std::sin(degrees * M_PI / 180));
  };
  for (double sign : {1.0, -1.0}) {
    const Eigen::Vector2d where = polar(sign * 170);
    const std::vector<std::vector<PressTouch>> left = {{{where.x(), where.y(), NAN}}};
    const auto across = score_positions_by_distance({polar(-sign * 170)}, left, 1.0, {0});
    EXPECT_NEAR(across[0].placement.turn_degrees, sign * 20, 1e-9) << sign;
  }
}

// A press set made from simulated one-touch frames: the shape fit puts every press near its true
// centre, far better than the centre's floor, and says so in its summary.
TEST_F(PressSet, ReconstructScoresWhereEachPressIsPut) {
  write_dataset(path("press.h5"), stand_in_presses());
  const Result r =
      run("reconstruct --method shape-linear --data " + path("press.h5") +
          " --split train --touches 1 --density coarse --png 0 --out " + path("out.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto at = r.output.find("presses: centre error median ");
  ASSERT_NE(at, std::string::npos) << r.output;
  const double median = std::stod(r.output.substr(at + 29));
  EXPECT_LT(median, 0.05) << r.output;
  const auto floor = r.output.find("predicting the centre: median ");
  ASSERT_NE(floor, std::string::npos);
  EXPECT_GT(std::stod(r.output.substr(floor + 30)), 4 * median) << r.output;
  // The same split by where the presses lie: every press in one band of three.
  const auto bands = r.output.find("by the press's distance from the centre");
  ASSERT_NE(bands, std::string::npos) << r.output;
  const std::string line = r.output.substr(bands, r.output.find('\n', bands) - bands);
  EXPECT_NE(line.find("from 0.8 R"), std::string::npos) << line;

  // Tuned on other presses of the same set: chosen on them, never on the scored ones.
  const std::string tuned = "reconstruct --method noser --data " + path("press.h5") +
                            " --split train --touches 1 --density coarse --png 0 --out " +
                            path("tuned.h5") + " --calibration " + path("press.h5");
  const Result t = run(tuned + " --frames 0:5 --calibration-frames 20:40");
  ASSERT_EQ(t.exit_code, 0) << t.output;
  EXPECT_NE(t.output.find("(validation)"), std::string::npos) << t.output;
  EXPECT_NE(t.output.find("presses: centre error median"), std::string::npos);
  const Result overlap = run(tuned + " --frames 0:5 --calibration-frames 3:40");
  EXPECT_NE(overlap.exit_code, 0);
  EXPECT_NE(overlap.output.find("nothing may be tuned on the scored presses"), std::string::npos)
      << overlap.output;
  const Result not_presses =
      run("reconstruct --method noser --data " + path("press.h5") +
          " --density coarse --png 0 --out " + path("x.h5") + " --calibration " + path("tiny.h5"));
  EXPECT_NE(not_presses.exit_code, 0);
  EXPECT_NE(not_presses.output.find("is not a press set"), std::string::npos) << not_presses.output;

  // The presses' frame: found for the set as it is (its positions are the model's own), bad
  // options and sets refused naming the flag or the file.
  const std::string fit = "calibrate --density coarse --presses ";
  const Result frame = run(fit + path("press.h5"));
  ASSERT_EQ(frame.exit_code, 0) << frame.output;
  EXPECT_NE(frame.output.find("presses fit best turned by"), std::string::npos) << frame.output;
  EXPECT_EQ(frame.output.find("mirrored"), std::string::npos) << frame.output;
  const auto turned = frame.output.find("turned by ");
  ASSERT_NE(turned, std::string::npos);
  const double degrees = std::stod(frame.output.substr(turned + 10));
  EXPECT_LE(std::min(degrees, 360 - degrees), 2.0) << frame.output;  // no turn, to the step
  const Result step = run(fit + path("press.h5") + " --step 0");
  EXPECT_EQ(step.exit_code, 2);
  EXPECT_NE(step.output.find("--step: must lie in (0, 90]"), std::string::npos) << step.output;
  const Result plain = run(fit + path("tiny.h5"));
  EXPECT_EQ(plain.exit_code, 2);
  EXPECT_NE(plain.output.find("tiny.h5: touches: is not a press set"), std::string::npos);
  const Result neither = run("calibrate --density coarse");
  EXPECT_EQ(neither.exit_code, 2);
  EXPECT_NE(neither.output.find("needs --reference"), std::string::npos) << neither.output;
}

// The reconstruction model and prior a user sets on the command line are the ones used: NOSER's
// exponent 0 places every press where the identity prior does, and so does a smooth prior whose
// length is under a pixel; the electrodes' coverage, not the set's stored one, shapes the
// Jacobian.
TEST_F(PressSet, TheCommandLinesPriorAndElectrodesAreUsed) {
  write_dataset(path("press.h5"), stand_in_presses());
  auto scores = [&](const std::string& more) {
    const Result r = run("reconstruct --data " + path("press.h5") +
                         " --split train --touches 1 --density coarse --png 0 --lambda 0.01 "
                         "--locate centroid --out " +
                         path("out.h5") + " " + more);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const auto at = r.output.find("presses: centre error");
    return at == std::string::npos ? std::string()
                                   : r.output.substr(at, r.output.find('\n', at) - at);
  };
  const std::string identity = scores("--method tikhonov");
  ASSERT_FALSE(identity.empty());
  EXPECT_EQ(scores("--method noser --noser-exponent 0"), identity);
  EXPECT_NE(scores("--method noser"), identity);  // p = 0.5 by default
  EXPECT_EQ(scores("--method smooth --smooth-length 1e-4"), identity);
  EXPECT_NE(scores("--method smooth"), identity);  // the sensor's radius by default
  EXPECT_NE(scores("--method tikhonov --electrode-coverage 0.1"), identity);
  const Result bad = run("reconstruct --method noser --noser-exponent 1.5 --data " +
                         path("press.h5") + " --png 0 --out " + path("bad.h5"));
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("--noser-exponent"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(path("bad.h5")));
  const Result no_length = run("reconstruct --method smooth --smooth-length 0 --data " +
                               path("press.h5") + " --png 0 --out " + path("bad.h5"));
  EXPECT_EQ(no_length.exit_code, 2) << no_length.output;
  EXPECT_NE(no_length.output.find("--smooth-length"), std::string::npos) << no_length.output;
  EXPECT_FALSE(fs::exists(path("bad.h5")));
  // Each press where it is and where the method put it, one CSV line a frame of the selection.
  const Result listed = run("reconstruct --method tikhonov --data " + path("press.h5") +
                            " --split train --touches 1 --frames 2:6 --density coarse --png 0 "
                            "--out " +
                            path("out.h5") + " --presses-csv " + path("presses.csv"));
  ASSERT_EQ(listed.exit_code, 0) << listed.output;
  EXPECT_NE(listed.output.find("turned"), std::string::npos) << listed.output;
  std::ifstream csv(path("presses.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "frame,true_x,true_y,found_x,found_y,error");
  int lines = 0;
  while (std::getline(csv, line)) {
    double v[6];
    ASSERT_EQ(
        std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf", v, v + 1, v + 2, v + 3, v + 4, v + 5),
        6)
        << line;
    EXPECT_NEAR(v[5], std::hypot(v[3] - v[1], v[4] - v[2]), 1e-5) << line;
    ++lines;
  }
  EXPECT_EQ(lines, 4);
  // The same command again replaces its own CSV (an output, not an input); onto --out, refused.
  const Result again = run("reconstruct --method tikhonov --data " + path("press.h5") +
                           " --split train --touches 1 --frames 2:6 --density coarse --png 0 "
                           "--out " +
                           path("out.h5") + " --presses-csv " + path("presses.csv"));
  EXPECT_EQ(again.exit_code, 0) << again.output;
  const Result same = run("reconstruct --method tikhonov --data " + path("press.h5") +
                          " --split train --density coarse --png 0 --out " + path("same") +
                          " --presses-csv " + path("same"));
  EXPECT_EQ(same.exit_code, 2) << same.output;
  EXPECT_NE(same.output.find("is --out"), std::string::npos) << same.output;
  const Result nowhere = run("reconstruct --method tikhonov --data " + path("press.h5") +
                             " --split train --density coarse --png 0 --out " + path("out3.h5") +
                             " --presses-csv " + path("no/such/folder.csv"));
  EXPECT_EQ(nowhere.exit_code, 2) << nowhere.output;
  EXPECT_NE(nowhere.output.find("does not exist"), std::string::npos) << nowhere.output;
  EXPECT_FALSE(fs::exists(path("out3.h5")));  // refused before --out was written
  // Never onto an input, and refused before any work.
  const Result onto = run("reconstruct --method tikhonov --data " + path("press.h5") +
                          " --split train --density coarse --png 0 --out " + path("out2.h5") +
                          " --presses-csv " + path("press.h5"));
  EXPECT_EQ(onto.exit_code, 2) << onto.output;
  EXPECT_FALSE(fs::exists(path("out2.h5")));
  EXPECT_NO_THROW(read_dataset(path("press.h5")));
  // The placement map: measured on the calibration presses, refused without them.
  const std::string mapped = "reconstruct --method noser --data " + path("press.h5") +
                             " --split train --touches 1 --density coarse --png 0 --out " +
                             path("mapped.h5") + " --placement-map";
  const Result without = run(mapped);
  EXPECT_EQ(without.exit_code, 2) << without.output;
  EXPECT_NE(without.output.find("--placement-map: needs --calibration"), std::string::npos)
      << without.output;
  const Result shape =
      run("reconstruct --method shape-linear --placement-map --data " + path("press.h5") +
          " --calibration " + path("press.h5") + " --png 0 --out " + path("shape.h5"));
  EXPECT_EQ(shape.exit_code, 2) << shape.output;
  EXPECT_NE(shape.output.find("not shape-linear"), std::string::npos) << shape.output;
  const Result with = run(mapped + " --frames 0:10 --calibration " + path("press.h5") +
                          " --calibration-frames 10:40");
  ASSERT_EQ(with.exit_code, 0) << with.output;
  EXPECT_NE(with.output.find("placement map: measured on 30 calibration presses"),
            std::string::npos)
      << with.output;
}

TEST_F(PressSet, BadTouchFilesAreRefusedNamingFileAndRow) {
  const auto refused = [&](const std::string& file, const std::string& more,
                           const std::string& message) {
    const Result r = run(import(file, more));
    EXPECT_NE(r.exit_code, 0) << file;
    EXPECT_NE(r.output.find(file), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(path("set.h5")));  // nothing half written
  };
  refused(text_file("short.csv", "0.1,0\n0.2,0\n"), "", "has 2 rows; the frames are 3");
  refused(text_file("nan.csv", "0.1,0\nnan,0.2\n0,0\n"), "", "line 2, value 1: NaN or infinite");
  const std::string nan_npy = path("nan.npy");  // NumPy keeps a NaN: the touch reader refuses it
  std::ofstream(nan_npy, std::ios::binary) << detail::npy_bytes({0.1f, 0, NAN, 0.2f, 0, 0}, {3, 2});
  refused(nan_npy, "", "row 2: the position is not a finite number");
  refused(text_file("out.csv", "0.1,0\n0.2,0\n35,0\n"), "",
          "row 3: (35, 0) x 1 lies outside the sensor (radius 1): is --touch-scale right?");
  refused(text_file("deep.csv", "0.1,0,1\n0.2,0,-1\n0,0,1\n"), "",
          "row 2: the depth must be positive");
  refused(text_file("wide.csv", "0.1,0,1,1\n0.2,0,1,1\n0,0,1,1\n"), "", "has 4 columns");
  EXPECT_NE(run(import(text_file("ok.csv", "0,0\n0,0\n0,0\n"), "--touch-scale 0")).exit_code, 0);
}

// Unlabelled frames set the noise: a press set whose references before each press carry white
// noise of a known level gives that level back (calibrate --noise, into the sensor file), and
// reconstruct --choose discrepancy chooses lambda from it; import --paired-reference keeps the
// references the noise is measured on.
TEST_F(PressSet, TheSensorsNoiseComesFromItsReferencesAndChoosesLambda) {
  const Result paired = run("import --in " + kFrames + " --reference " + kFrames +
                            " --paired-reference --out " + path("paired.h5"));
  ASSERT_EQ(paired.exit_code, 0) << paired.output;
  const Dataset p = read_dataset(path("paired.h5"));
  ASSERT_EQ(p.references.rows(), 3);
  EXPECT_EQ(p.references, p.frames);  // the file is its own reference here
  EXPECT_NE(run("info " + path("paired.h5")).output.find("paired references: one before each"),
            std::string::npos);
  // Split by time: frames 1:3 keep their own references, whose mean is the reference.
  const Result later = run("import --in " + kFrames + " --reference " + kFrames +
                           " --paired-reference --frames 1:3 --out " + path("later.h5"));
  ASSERT_EQ(later.exit_code, 0) << later.output;
  const Dataset l = read_dataset(path("later.h5"));
  ASSERT_EQ(l.size(), 2);
  EXPECT_EQ(l.frames, p.frames.bottomRows(2));
  EXPECT_EQ(l.references, p.references.bottomRows(2));
  EXPECT_LT((l.reference - p.references.bottomRows(2).colwise().mean().transpose()).norm(), 1e-12);
  const Result outside = run("import --in " + kFrames + " --frames 2:9 --out " + path("x.h5"));
  EXPECT_EQ(outside.exit_code, 2);
  EXPECT_NE(outside.output.find("--frames: range 2:9 is empty or outside the 3 frames"),
            std::string::npos)
      << outside.output;
  EXPECT_FALSE(fs::exists(path("x.h5")));

  Dataset d = stand_in_presses();
  const double sigma = 1e-3 * std::sqrt(d.reference.squaredNorm() / d.reference.size());
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0, sigma);
  d.references.resize(d.size(), d.reference.size());
  for (Eigen::Index i = 0; i < d.references.size(); ++i)
    d.references.data()[i] = d.reference.data()[i % d.reference.size()];
  for (Eigen::Index f = 0; f < d.size(); ++f)
    for (Eigen::Index k = 0; k < d.references.cols(); ++k) d.references(f, k) += normal(rng);
  write_dataset(path("press.h5"), d);

  const std::string noise = "calibrate --density coarse --noise " + path("press.h5");
  const Result c = run(noise + " --noise-frames 0:40 --out " + path("sensor.json"));
  ASSERT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find("40 references; a difference frame's noise"), std::string::npos)
      << c.output;
  const SensorFile sensor = read_sensor_file(path("sensor.json"));
  ASSERT_TRUE(sensor.noise.has_value());
  EXPECT_EQ(sensor.noise->references, 40);
  const double expected = std::sqrt(2.0) * 1e-3;  // two frames' noise, relative to the reference
  EXPECT_NEAR(sensor.noise->noise / expected, 1, 0.05);
  EXPECT_EQ(sensor.noise->gains.size(), d.reference.size());

  const std::string lambda = "reconstruct --method noser --data " + path("press.h5") +
                             " --split train --touches 1 --density coarse --png 0 --out " +
                             path("out.h5") + " --choose discrepancy";
  const Result r = run(lambda + " --sensor " + path("sensor.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("(discrepancy)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("the strongest blob at 0.5 x the image's maximum"), std::string::npos);
  // The press where pyEIT puts it: the centroid of every pixel above the threshold.
  const Result centroid = run(lambda + " --sensor " + path("sensor.json") + " --locate centroid");
  ASSERT_EQ(centroid.exit_code, 0) << centroid.output;
  EXPECT_NE(centroid.output.find("the centroid of every pixel at 0.5"), std::string::npos)
      << centroid.output;
  EXPECT_EQ(run(lambda + " --locate middle").exit_code, 2);
  const Result without = run(lambda);
  EXPECT_EQ(without.exit_code, 2);
  EXPECT_NE(without.output.find("needs the sensor's measured noise"), std::string::npos)
      << without.output;
  const Result greit = run("reconstruct --method greit --data " + path("press.h5") +
                           " --density coarse --png 0 --out " + path("g.h5") +
                           " --choose discrepancy --sensor " + path("sensor.json"));
  EXPECT_NE(greit.exit_code, 0);
  EXPECT_NE(greit.output.find("discrepancy needs a one-step linear method"), std::string::npos)
      << greit.output;
  const Result plain = run("calibrate --density coarse --noise " + path("tiny.h5"));
  EXPECT_EQ(plain.exit_code, 2);
  EXPECT_NE(plain.output.find("tiny.h5: references: the set has no reference recorded"),
            std::string::npos)
      << plain.output;
}

// --noise-weights counts each value by one over its noise measured on the references: a value
// whose references wander a thousand times as much as the others', and which carries a glitch
// of a tenth of the set's largest value in every pressed frame, moves the presses without the
// weights and hardly with them. Equal levels change nothing; a missing or mismatched level is
// refused. The frames get white noise at 40 dB, so that GCV's lambda is not at its grid's
// noise-free end.
TEST_F(PressSet, NoiseWeightsCountEachValueByItsMeasuredNoise) {
  Dataset d = stand_in_presses();
  const MeasurementProtocol protocol = measurement_protocol(d);
  int channel = -1, input = -1;  // a raw channel that is an input, and that input
  for (int c = 0; c < protocol.size() && input < 0; ++c) {
    const Eigen::VectorXd in = protocol.to_inputs(Eigen::VectorXd::Unit(protocol.size(), c));
    Eigen::Index j = 0;
    if (in.cwiseAbs().maxCoeff(&j) == 1) channel = c, input = static_cast<int>(j);
  }
  ASSERT_GE(input, 0);
  const double sigma = 1e-3 * std::sqrt(d.reference.squaredNorm() / d.reference.size());
  std::mt19937 rng(11);
  std::normal_distribution<double> normal(0, sigma);
  d.references = d.reference.transpose().replicate(d.size(), 1);
  for (Eigen::Index f = 0; f < d.size(); ++f)
    for (Eigen::Index k = 0; k < d.references.cols(); ++k)
      d.references(f, k) += (k == channel ? 1000 : 1) * normal(rng);
  write_dataset(path("clean.h5"), d);
  d.differences.col(input).array() += 0.1 * d.differences.cwiseAbs().maxCoeff();
  write_dataset(path("glitch.h5"), d);
  const Result c = run("calibrate --density coarse --noise " + path("clean.h5") + " --out " +
                       path("sensor.json"));
  ASSERT_EQ(c.exit_code, 0) << c.output;

  const auto median = [&](const std::string& set, const std::string& more) {
    const Result r = run("reconstruct --method noser --data " + path(set) +
                         " --split train --touches 1 --density coarse --png 0 --out " +
                         path("out.h5") + " --snr 40 " + more);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const auto at = r.output.find("presses: centre error median ");
    return at == std::string::npos ? NAN : std::stod(r.output.substr(at + 29));
  };
  const std::string weighted = "--sensor " + path("sensor.json") + " --noise-weights";
  const double clean = median("clean.h5", ""), glitched = median("glitch.h5", "");
  const double saved = median("glitch.h5", weighted), weighed = median("clean.h5", weighted);
  // A sensor file of the noise alone (not fitted) lends its noise, not its nominal model.
  EXPECT_EQ(median("clean.h5", "--sensor " + path("sensor.json")), clean);
  EXPECT_GT(glitched, 10 * clean) << clean << " " << glitched;
  // Weighed, the glitch hardly moves a press: within half again of the same weights' error on
  // the frames without it (the measured levels of the other values vary by some per cent).
  EXPECT_LT(saved, 0.1 * glitched) << glitched << " " << saved;
  EXPECT_LT(saved, 1.5 * weighed) << weighed << " " << saved;

  SensorFile equal = read_sensor_file(path("sensor.json"));
  equal.noise->inputs.setConstant(0.002);
  write_sensor_file(path("equal.json"), equal);
  EXPECT_EQ(median("clean.h5", "--sensor " + path("equal.json") + " --noise-weights"), clean);

  const auto on_clean_by = [&](const std::string& method) {
    return "reconstruct --method " + method + " --data " + path("clean.h5") +
           " --density coarse --png 0 --out " + path("x.h5") + " ";
  };
  const std::string on_clean = on_clean_by("noser");
  const Result none = run(on_clean + "--noise-weights");
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.output.find("--noise-weights: needs each value's measured noise"),
            std::string::npos)
      << none.output;
  const Result discrepancy =
      run(on_clean + "--noise-weights --choose discrepancy --sensor " + path("equal.json"));
  EXPECT_EQ(discrepancy.exit_code, 2);
  EXPECT_NE(discrepancy.output.find("is not combined with --choose discrepancy"), std::string::npos)
      << discrepancy.output;
  const Result greit = run(on_clean_by("greit") + "--noise-weights --sensor " + path("equal.json"));
  EXPECT_EQ(greit.exit_code, 2);
  EXPECT_NE(greit.output.find("--noise-weights: changes nothing for greit"), std::string::npos)
      << greit.output;
  equal.noise->inputs = Eigen::VectorXd::Constant(5, 0.002);
  write_sensor_file(path("short.json"), equal);
  const Result short_noise = run(on_clean + "--noise-weights --sensor " + path("short.json"));
  EXPECT_EQ(short_noise.exit_code, 2);
  EXPECT_NE(short_noise.output.find("short.json: noise.inputs: holds 5 values"), std::string::npos)
      << short_noise.output;
  EXPECT_FALSE(fs::exists(path("x.h5")));
}

// The hydrogel skin's recording (where ../shared holds it; never committed): 550 presses in
// metres on a skin of radius 70 mm, to the unit disk, the third column the press depth.
TEST_F(PressSet, TheHydrogelRecordingIsAPressSet) {
  const std::string mat =
      std::string(EITBENCH_SOURCE_DIR) + "/../shared/data/hydrogel-skin/superpose50.mat";
  if (!fs::exists(mat)) GTEST_SKIP() << "no " << mat << " (not committed)";
  const Result r = run("import --in " + mat + " --variable responsedowns --reference " + mat +
                       " --reference-variable responseups --paired-reference --protocol opposite "
                       "--magnitude --touches " +
                       mat + " --touch-variable positions --touch-scale 14.2857142857143 --out " +
                       path("presses.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Dataset d = read_dataset(path("presses.h5"));
  ASSERT_EQ(d.touches.size(), 550u);
  EXPECT_EQ(d.references.rows(), 550);  // each press's own reference, for calibrate --noise
  EXPECT_EQ(d.touch_size, "depth");
  for (const auto& list : d.touches) {
    ASSERT_EQ(list.size(), 1u);
    EXPECT_LT(std::hypot(list[0].x, list[0].y), 1.0);
    EXPECT_GE(list[0].size, 0.010 * 14.2857142857143 * (1 - 1e-9));  // 10 to 20 mm deep
    EXPECT_LE(list[0].size, 0.020 * 14.2857142857143 * (1 + 1e-9));
  }
}

// A stored set is checked again when read: a touch outside the sensor, a count out of range.
TEST(PressSetFile, TheReaderRefusesTouchesOutsideTheSensor) {
  Dataset d = read_dataset_from_import();
  d.touches = {{{0.2, 0.1, NAN}}, {{0.0, 1.5, NAN}}, {}};
  const std::string file = (fs::temp_directory_path() / "eitbench_press_out.h5").string();
  write_dataset(file, d);
  EXPECT_EQ(testing::input_error_at([&] { read_dataset(file); }), file + ".touches");
  d.touches[1][0].y = 0.5, d.touches[1][0].size = -1;
  write_dataset(file, d);
  EXPECT_EQ(testing::input_error_at([&] { read_dataset(file); }), file + ".touches");
  d.touches[1][0].size = 0.01, d.touch_size = "depth";
  write_dataset(file, d);
  const Dataset back = read_dataset(file);
  fs::remove(file);
  EXPECT_EQ(back.touches[1][0].size, 0.01);
  EXPECT_TRUE(back.touches[2].empty());
}

}  // namespace
}  // namespace eitbench
