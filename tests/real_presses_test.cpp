// Real presses: the fingerprint floor, press labels, fine-tuning from a trained model, and `run
// --measured` end to end on stand-in press sets simulated for the tiny preset's sensor (no real
// data needed).
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "cli_fixture.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/training_data.h"
#include "eitbench/bench/io/sensor_file.h"
#include "eitbench/bench/methods/press_fingerprint.h"
#include "eitbench/bench/methods/press_labels.h"
#include "eitbench/bench/report/press_pick.h"
#include "eitbench/bench/report/results.h"
#include "eitbench/jacobian/constants.h"
#include "eitbench/jacobian/error.h"
#include "learned_support.h"
#include "test_support.h"

namespace eitbench {
namespace {

// Frames that vary smoothly with the press position: a fingerprint's neighbours are its
// neighbours on the sensor.
Eigen::VectorXd smooth_frame(double x, double y) {
  Eigen::VectorXd f(6);
  f << x, y, x * y, std::sin(2 * x), std::cos(2 * y), x * x - y * y;
  return f;
}

TEST(PressFingerprint, PutsAPressAmongItsNearestLabelledFrames) {
  std::vector<Eigen::Vector2d> grid;
  for (double x = -0.6; x <= 0.61; x += 0.1)
    for (double y = -0.6; y <= 0.61; y += 0.1) grid.emplace_back(x, y);
  SampleMatrix frames(static_cast<Eigen::Index>(grid.size()), 6);
  Eigen::MatrixX2d positions(static_cast<Eigen::Index>(grid.size()), 2);
  for (std::size_t i = 0; i < grid.size(); ++i) {
    frames.row(static_cast<Eigen::Index>(i)) = smooth_frame(grid[i].x(), grid[i].y()).transpose();
    positions.row(static_cast<Eigen::Index>(i)) = grid[i].transpose();
  }
  // k = 1 recalls a labelled frame exactly.
  const PressFingerprint one(frames, positions, FingerprintOptions{{1}});
  EXPECT_EQ(one.neighbours(), 1);
  EXPECT_NEAR((one.locate(frames.row(17).transpose()) - grid[17]).norm(), 0.0, 1e-15);
  // Leave-one-out on a 0.1 grid: the nearest others lie one step away.
  EXPECT_NEAR(one.leave_one_out_error(), 0.1, 0.02);
  // The k that leave-one-out prefers, and a press between grid points placed near it.
  const PressFingerprint best(frames, positions);
  EXPECT_LE(best.leave_one_out_error(), one.leave_one_out_error());
  const Eigen::Vector2d between(0.05, -0.15);
  EXPECT_LT((best.locate(smooth_frame(between.x(), between.y())) - between).norm(), 0.08);
}

TEST(PressFingerprint, RefusesWhatItCannotUse) {
  SampleMatrix one_frame(1, 6);
  one_frame.setZero();
  EXPECT_EQ(
      testing::input_error_at([&] { PressFingerprint(one_frame, Eigen::MatrixX2d::Zero(1, 2)); }),
      "fingerprint.frames");
  SampleMatrix frames = SampleMatrix::Random(4, 6);
  EXPECT_EQ(
      testing::input_error_at([&] { PressFingerprint(frames, Eigen::MatrixX2d::Zero(3, 2)); }),
      "fingerprint.positions");
  const PressFingerprint f(frames, Eigen::MatrixX2d::Zero(4, 2));
  EXPECT_EQ(testing::input_error_at([&] { f.locate(Eigen::VectorXd::Zero(5)); }),
            "fingerprint.frame");
}

TEST(PressLabels, ADiscAtEachPressWhoseCentreTheScoreFinds) {
  const PixelGrid grid(64, 1.0);
  const std::vector<std::vector<PressTouch>> touches = {{{0.3, -0.4, NAN}}, {{-0.55, 0.1, NAN}}};
  const SampleMatrix labels = press_labels(touches, grid, "cal.h5");
  ASSERT_EQ(labels.rows(), 2);
  for (int i = 0; i < 2; ++i) {
    const Eigen::VectorXd label = labels.row(i).transpose();
    const Eigen::Vector2d at = label_centre(label, grid);
    EXPECT_NEAR(at.x(), touches[i][0].x, 1e-3);
    EXPECT_NEAR(at.y(), touches[i][0].y, 1e-3);
    EXPECT_NEAR(label.maxCoeff(), 1.0, 1e-12);  // intensity 1 at the disc's core
    // An image that is the label scores (almost) no error; the other press's label scores their
    // distance.
    const ScoreFn score = press_score(grid, 0.5);
    EXPECT_GT(score(label, label), -0.01);
    EXPECT_NEAR(score(labels.row(1 - i).transpose(), label), -std::hypot(0.3 + 0.55, -0.4 - 0.1),
                0.01);
  }
  const std::vector<std::vector<PressTouch>> two = {{{0.1, 0.1, NAN}, {0.2, 0.2, NAN}}};
  EXPECT_EQ(testing::input_error_at([&] { press_labels(two, grid, "cal.h5"); }), "cal.h5.touches");
}

double image_mse(const SampleMatrix& a, const SampleMatrix& b) {
  return (a - b).squaredNorm() / static_cast<double>(a.size());
}

// Fine-tuning starts where the trained model is (the same images before the first round) and
// lowers the error on the new sensor's frames, here the tiny set read through 1.6x the gain.
TEST(Finetune, StartsFromTheTrainedModelAndLowersItsErrorOnNewFrames) {
  const Dataset& data = testing::tiny();
  const NetworkOptions network = testing::test_network();
  TrainingOptions o;
  o.epochs = 6;
  o.batch_size = 16;
  o.validate_every = 64;
  Trainer first(network, o, labelled_frames(data, Split::train),
                labelled_frames(data, Split::validation), sensor_of(data));
  while (!first.done()) first.run_round();
  const LearnedModel trained = first.best_model();

  LabelledFrames train = labelled_frames(data, Split::train);
  LabelledFrames validation = labelled_frames(data, Split::validation);
  train.frames *= 1.6, validation.frames *= 1.6;
  const SampleMatrix labels = validation.labels;
  ASSERT_EQ(labels.rows(), validation.frames.rows());
  ASSERT_GT(labels.cols(), 0);
  TrainingOptions f = o;
  f.learning_rate = o.learning_rate / 10;
  f.epochs = 10;
  Trainer tune(network, f, train, validation, sensor_of(data));
  tune.start_from(trained, "trained.pt");
  const SampleMatrix before = trained.reconstruct(validation.frames);
  EXPECT_EQ(tune.best_model().reconstruct(validation.frames), before);
  while (!tune.done()) tune.run_round();
  const SampleMatrix after = tune.best_model().reconstruct(validation.frames);
  EXPECT_LT(image_mse(after, labels), 0.9 * image_mse(before, labels));

  NetworkOptions other = network;
  other.hidden = {32};
  Trainer mismatched(other, o, labelled_frames(data, Split::train),
                     labelled_frames(data, Split::validation), sensor_of(data));
  EXPECT_EQ(testing::input_error_at([&] { mismatched.start_from(trained, "trained.pt"); }),
            "trained.pt.network");
}

// Stand-in press sets: the one-touch frames of tiny sets simulated with other seeds than the run's,
// each press at its circle's centre.
class MeasuredRun : public Cli {
 protected:
  // With `references`, each press keeps a reference recorded before it (import
  // --paired-reference): the set's reference with white noise of 0.1 % of its RMS.
  std::string press_set(const std::string& name, int seed, bool references = false) {
    const std::string all = path(name + "_all.h5");
    EXPECT_EQ(run("simulate --preset tiny --quiet --seed " + std::to_string(seed) + " --out " + all)
                  .exit_code,
              0);
    const Dataset d = read_dataset(all);
    Dataset p = d;
    std::vector<int> rows;
    for (int i = 0; i < d.size(); ++i)
      if (d.circles[static_cast<std::size_t>(i)].size() == 1) rows.push_back(i);
    const auto n = static_cast<Eigen::Index>(rows.size());
    p.frames.resize(n, d.frames.cols()), p.differences.resize(n, d.differences.cols());
    p.labels.resize(n, 0);
    p.circles.clear(), p.touches.clear(), p.split.clear();
    for (Eigen::Index k = 0; k < n; ++k) {
      p.frames.row(k) = d.frames.row(rows[k]), p.differences.row(k) = d.differences.row(rows[k]);
      const Circle& c = d.circles[static_cast<std::size_t>(rows[k])][0];
      p.touches.push_back({{c.x, c.y, NAN}});
      p.split.push_back(Split::test);
    }
    if (references) {
      std::mt19937 rng(static_cast<unsigned>(seed));
      const double sigma = 1e-3 * d.reference.norm() / std::sqrt(double(d.reference.size()));
      std::normal_distribution<double> normal(0.0, sigma);
      p.references.resize(n, d.reference.size());
      for (Eigen::Index k = 0; k < n; ++k)
        for (Eigen::Index c = 0; c < d.reference.size(); ++c)
          p.references(k, c) = d.reference(c) + normal(rng);
    }
    p.preset = "imported";
    const std::string out = path(name + ".h5");
    write_dataset(out, p);
    return out;
  }
};

// A run with real presses moved with its stages/ alone: the presses are reconstructed with the
// models themselves, so the learned models are trained again rather than taken from their
// records, and the run ends.
TEST_F(MeasuredRun, StagesAloneTrainTheModelsAgain) {
  const std::string set = press_set("set", 11), cal = press_set("cal", 12);
  const std::string args = "run --preset tiny --methods noser --augment none --measured " + set +
                           " --calibration " + cal + " --out ";
  ASSERT_EQ(run(args + path("whole") + " --quiet").exit_code, 0);
  std::filesystem::create_directories(path("moved"));
  std::filesystem::copy(path("whole/stages"), path("moved/stages"));
  const Result r = run(args + path("moved") + " --resume");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("noser: resumed"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("resumed from its record"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("dnn none: training the"), std::string::npos) << r.output;
  EXPECT_FALSE(read_results_json(path("moved/results.json")).measured.empty());
}

TEST_F(MeasuredRun, ScoresEveryMethodOnPressesTunedOnAnotherSet) {
  const std::string set = press_set("set", 11), cal = press_set("cal", 12);
  const Result r =
      run("run --preset tiny --quiet --methods noser,greit --augment none --measured " + set +
          " --calibration " + cal + " --finetune 0,8 --finetune-steps 40 --out " + path("out"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const RunResults results = read_results_json(path("out/results.json"));
  const MeasuredRow* centre = nullptr;
  const MeasuredRow* noser_cal = nullptr;
  const MeasuredRow* noser_gcv = nullptr;
  const MeasuredRow* noser_gcv_rule = nullptr;
  int finetuned = 0, greit_gcv = 0;
  for (const MeasuredRow& m : results.measured) {
    EXPECT_EQ(m.scored, "set.h5");
    EXPECT_EQ(m.calibration, "cal.h5");
    EXPECT_GT(m.frames, 10);
    if (m.method == "centre") centre = &m;
    if (m.method == "noser" && m.training == "calibration presses") noser_cal = &m;
    if (m.method == "noser" && m.training == "calibration frames (GCV)") noser_gcv = &m;
    if (m.method == "noser" && m.training == "calibration frames (GCV), rule on CAL's presses")
      noser_gcv_rule = &m;
    greit_gcv += m.method == "greit" && m.training.rfind("calibration frames", 0) == 0;
    finetuned += m.training == "fine-tuned" || m.training == "real presses only";
  }
  ASSERT_NE(centre, nullptr);
  ASSERT_NE(noser_cal, nullptr);
  // Simulated presses are found far better than by guessing the centre.
  EXPECT_LT(noser_cal->centre_error_median, 0.5 * centre->centre_error_median);
  // Without any label too: lambda by GCV on the calibration frames, the threshold fixed. GREIT
  // has no GCV, so no such row.
  ASSERT_NE(noser_gcv, nullptr);
  EXPECT_NE(noser_gcv->settings.find("(gcv)"), std::string::npos) << noser_gcv->settings;
  EXPECT_NE(noser_gcv->settings.find("touch threshold 0.5 (fixed: no labels)"), std::string::npos)
      << noser_gcv->settings;
  EXPECT_LT(noser_gcv->centre_error_median, 0.5 * centre->centre_error_median);
  // GCV's lambda with the press rule chosen on the calibration presses: the same lambda, the
  // rule's threshold tuned on CAL, a row that used labels.
  ASSERT_NE(noser_gcv_rule, nullptr);
  const auto lambda_of = [](const MeasuredRow& m) {
    return m.settings.substr(0, m.settings.find(", touch"));
  };
  EXPECT_EQ(lambda_of(*noser_gcv_rule), lambda_of(*noser_gcv));
  EXPECT_NE(noser_gcv_rule->settings.find("(on CAL)"), std::string::npos)
      << noser_gcv_rule->settings;
  EXPECT_LT(noser_gcv_rule->centre_error_median, 0.5 * centre->centre_error_median);
  EXPECT_EQ(greit_gcv, 0);
  // New positions: the scored presses no calibration press came within 0.01 R of.
  const Dataset s = read_dataset(set), c = read_dataset(cal);
  int novel = 0;
  for (const auto& t : s.touches) {
    bool near = false;
    for (const auto& u : c.touches) near |= std::hypot(t[0].x - u[0].x, t[0].y - u[0].y) < 0.01;
    novel += !near;
  }
  EXPECT_GT(novel, 0);
  EXPECT_EQ(noser_cal->novel_frames, novel);
  // Inner presses: those within half the radius. Predicting the centre misses each by its own
  // distance, so under 0.5 R there.
  int inner = 0;
  for (const auto& t : s.touches) inner += std::hypot(t[0].x, t[0].y) < 0.5 * s.radius;
  EXPECT_EQ(noser_cal->inner_frames, inner);
  EXPECT_EQ(centre->inner_frames, inner);
  if (inner > 0) {
    EXPECT_LT(centre->inner_centre_error_mean, 0.5 * s.radius);
  }
  EXPECT_EQ(finetuned, 4);  // n = 8: none and d16, fine-tuned and from scratch
  std::ifstream report(path("out/report.md"));
  const std::string text((std::istreambuf_iterator<char>(report)), {});
  EXPECT_NE(text.find("## Real presses"), std::string::npos);
  EXPECT_NE(text.find("### Few real labels"), std::string::npos);
  EXPECT_NE(text.find("within 0.5 R: mean"), std::string::npos);
  // A calibration set without paired references gives no simulation like the sensor, no pick.
  for (const MeasuredRow& m : results.measured)
    EXPECT_TRUE(std::isnan(m.like_sensor_fraction_of_radius));
  EXPECT_EQ(text.find("### A pick without labels"), std::string::npos);
}

// With the references recorded before each calibration press, the run simulates presses with
// their measured noise and gains: each one-step method gets a row tuned there (lambda and press
// rule, no label), every row without labels its error there, and the report picks the lowest.
TEST_F(MeasuredRun, PicksAMethodWithoutLabelsFromTheSimulationLikeTheSensor) {
  const std::string set = press_set("set", 11), cal = press_set("cal", 12, true);
  const Result r =
      run("run --preset tiny --quiet --methods laplace,greit,gn --augment none "
          "--measured " +
          set + " --calibration " + cal + " --finetune 0 --out " + path("out"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const RunResults results = read_results_json(path("out/results.json"));
  std::set<std::string> like_rows;
  const MeasuredRow* pick = nullptr;
  const MeasuredRow* best_free = nullptr;
  for (const MeasuredRow& m : results.measured) {
    const bool label_free =
        m.training == "simulation like the sensor" || m.training == "calibration frames (GCV)";
    EXPECT_EQ(std::isfinite(m.like_sensor_fraction_of_radius), label_free)
        << m.method << ", " << m.training;
    if (m.training == "simulation like the sensor") {
      like_rows.insert(m.method);
      EXPECT_NE(m.settings.find("on the simulation like the sensor"), std::string::npos)
          << m.settings;
    }
    if (!label_free) continue;
    EXPECT_EQ(m.tuned_on_real_frames, m.training == "calibration frames (GCV)");
    EXPECT_GT(m.misfit_over_noise, 0) << m.method << ", " << m.training;
    if (!best_free || m.centre_error_median < best_free->centre_error_median) best_free = &m;
  }
  // The pick: the lowest in the simulation like the sensor, among the rows the real frames tuned
  // where their misfit passes twice the noise.
  for (const MeasuredRow& m : results.measured) {
    if (std::isnan(m.like_sensor_fraction_of_radius)) continue;
    if (m.misfit_over_noise > 2 && !m.tuned_on_real_frames) continue;
    if (!pick || m.like_sensor_fraction_of_radius < pick->like_sensor_fraction_of_radius) pick = &m;
  }
  // Gauss-Newton would sweep on a few frames: left out; GREIT has no GCV row but a row here.
  EXPECT_EQ(like_rows, (std::set<std::string>{"laplace", "greit"}));
  int dnn_rule = 0;
  for (const MeasuredRow& m : results.measured)
    dnn_rule += m.method == "dnn" && m.training == "simulation, rule like the sensor";
  EXPECT_EQ(dnn_rule, 1);
  ASSERT_NE(pick, nullptr);
  std::ifstream report(path("out/report.md"));
  const std::string text((std::istreambuf_iterator<char>(report)), {});
  EXPECT_NE(text.find("### A pick without labels"), std::string::npos);
  EXPECT_NE(text.find("The pick is **" + pick->method + "** (" + pick->training + ")"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find(fmt::format("Regret against the best row without labels ({}, {}): **{:.3f}",
                                  best_free->method, best_free->training,
                                  pick->centre_error_median - best_free->centre_error_median)),
            std::string::npos)
      << text;
}

// The pick's rule on hand-made rows: the simulation like the sensor ranks them, unless the real
// frames' misfit to the model passes twice the noise; then only the rows the real frames tuned.
TEST(PressPick, KeepsToTheRowsTheRealFramesTunedWhereTheModelsErrorDominates) {
  MeasuredRow simulated, on_frames, labelled;
  simulated.method = "noser", simulated.like_sensor_fraction_of_radius = 0.08;
  on_frames.method = "laplace", on_frames.like_sensor_fraction_of_radius = 0.09;
  on_frames.tuned_on_real_frames = true;
  labelled.method = "tikhonov";  // tuned on labelled presses: no error in the simulation
  for (double ratio : {1.5, 5.0}) {
    simulated.misfit_over_noise = on_frames.misfit_over_noise = ratio;
    const PressPick p = pick_without_labels({labelled, simulated, on_frames});
    ASSERT_NE(p.pick, nullptr);
    EXPECT_EQ(p.pick->method, ratio > 2 ? "laplace" : "noser") << ratio;
    EXPECT_EQ(p.real_frames_only, ratio > 2);
    EXPECT_EQ(p.misfit_over_noise, ratio);
  }
  // No row the real frames tuned: the simulation ranks them whatever the misfit.
  EXPECT_EQ(pick_without_labels({simulated, labelled}).pick->method, "noser");
  EXPECT_EQ(pick_without_labels({labelled}).pick, nullptr);
}

TEST_F(MeasuredRun, RefusesPressSetsItCannotScoreHonestly) {
  const std::string set = press_set("set", 11);
  const std::string base = "run --preset tiny --quiet --out " + path("out") + " ";
  Result r = run(base + "--measured " + set);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--measured: needs --calibration"), std::string::npos) << r.output;
  r = run(base + "--measured " + set + " --calibration " + set);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--calibration: is the measured set"), std::string::npos) << r.output;
  r = run(base + "--measured " + set + " --calibration " + set + " --finetune 0,1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--finetune: '1' is not a number of presses"), std::string::npos)
      << r.output;
  r = run(base + "--calibration " + set);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--calibration: goes with --measured"), std::string::npos) << r.output;
  // A set without touches is no press set.
  const std::string plain = path("set_all.h5");
  r = run(base + "--measured " + set + " --calibration " + plain);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("set_all.h5: touches: is not a press set"), std::string::npos)
      << r.output;
}

// The sensor fit on the calibration presses (calibrate --presses CAL --out) writes a sensor file
// with its press fit; the run scores the methods that locate presses on the model a second time,
// their positions taken back through it. A fit of the scored presses is refused before any work.
TEST_F(MeasuredRun, ScoresThroughTheSensorsPressFit) {
  const std::string set = press_set("set", 11), cal = press_set("cal", 12);
  const std::string mesh = " --electrodes 16 --density coarse";
  Result r = run("calibrate --presses " + cal + mesh + " --step 2 --out " + path("sensor.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const SensorFile sensor = read_sensor_file(path("sensor.json"));
  ASSERT_TRUE(sensor.press_fit.has_value());
  EXPECT_FALSE(sensor.fitted);  // no --reference: nominal background and impedances
  // The stand-in's positions are the simulated circles' centres: no turn, no scale to find but
  // what the linear model's bias on its strong touches (contrast up to 0.9) puts there.
  const SensorPressFit& fit = *sensor.press_fit;
  const double turn = std::min(fit.rotate_degrees, 360 - fit.rotate_degrees);
  EXPECT_LT(turn, 5.0);
  EXPECT_FALSE(fit.mirror);
  EXPECT_NEAR(fit.scale, 1.0, 0.15);
  EXPECT_LT(fit.relative_residual, fit.start_residual);

  ASSERT_EQ(
      run("calibrate --presses " + set + mesh + " --out " + path("fit_of_set.json")).exit_code, 0);
  const std::string base = "run --preset tiny --quiet --methods noser --augment none --measured " +
                           set + " --calibration " + cal + " --finetune 0 --out " + path("out");
  r = run(base + " --sensor " + path("fit_of_set.json"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("press_fit.presses: was fitted on"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(path("out/data.h5")));

  r = run(base + " --sensor " + path("sensor.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const RunResults results = read_results_json(path("out/results.json"));
  auto find = [&](const std::string& method, const std::string& training) {
    for (const MeasuredRow& m : results.measured)
      if (m.method == method && m.training == training) return &m;
    return static_cast<const MeasuredRow*>(nullptr);
  };
  for (const std::string method : {"noser", "dnn"}) {
    const MeasuredRow* plain = find(method, "simulation");
    const MeasuredRow* through = find(method, "simulation + sensor fit");
    ASSERT_NE(plain, nullptr) << method;
    ASSERT_NE(through, nullptr) << method;
    // The fit moves a position in the disk by at most (|1 - 1/s| + 2 sin(turn / 2)) R, and the
    // median error by no more.
    const double moved = std::abs(1 - 1 / fit.scale) + 2 * std::sin(turn * kPi / 360);
    EXPECT_LE(std::abs(through->centre_error_median - plain->centre_error_median), moved + 1e-9)
        << method;
    // (The tiny run's network finds no press: the centre, which no fit moves.)
    if (method == "noser") {
      EXPECT_NE(through->centre_error_median, plain->centre_error_median);
    }
  }
  EXPECT_NE(find("noser", "calibration presses + sensor fit"), nullptr);
  // Each method's own affine position map, fitted on CAL's presses: near the identity on
  // presses simulated where they are recorded, so far better than the centre.
  const MeasuredRow* mapped = find("noser", "calibration presses + position map");
  ASSERT_NE(mapped, nullptr);
  const MeasuredRow* centre = find("centre", "none");
  ASSERT_NE(centre, nullptr);
  EXPECT_LT(mapped->centre_error_median, 0.5 * centre->centre_error_median);
  EXPECT_EQ(find("fingerprint", "calibration presses + sensor fit"), nullptr);
}

}  // namespace
}  // namespace eitbench
