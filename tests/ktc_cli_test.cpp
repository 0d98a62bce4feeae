// `eitbench ktc` and `eitbench run --ktc` on a synthetic KTC folder (the challenge's layout and
// protocol, frames from the forward model): the challenge's files written and read back, the
// targets found, and every bad input refused with exit 2 and nothing written.
#include <fmt/core.h>
#include <filesystem>

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "cli_fixture.h"
#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/io/matlab.h"
#include "eitbench/bench/ktc/ktc_files.h"
#include "eitbench/bench/ktc/ktc_run.h"
#include "ktc_synthetic.h"

namespace eitbench {
namespace {

// The mean (row, column) of a class's pixels; NaN when it has none.
Eigen::Vector2d centroid(const ClassImage& image, int cls) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int count = 0;
  for (int i = 0; i < image.rows(); ++i)
    for (int j = 0; j < image.cols(); ++j)
      if (image(i, j) == cls) sum += Eigen::Vector2d(i, j), ++count;
  return sum / count;
}

class KtcCli : public Cli {
 protected:
  // Two samples: a resistive and a conductive disc; one resistive disc near electrode 1.
  void make_folder() {
    testing::write_synthetic_ktc(
        path("in"), {{{-0.04, 0.03, 0.025, 1}, {0.045, -0.02, 0.02, 2}}, {{0.0, 0.07, 0.025, 1}}});
  }
  // The flags that keep a test short: the coarse tank, a small grid.
  static std::string fast() { return " --density coarse --pixels 32"; }
  // `args` exits 2 with a message that says `says`, and writes no OUT.
  void refused(const std::string& args, const std::string& says) {
    const Result r = run(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(says), std::string::npos) << args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(path("out"))) << args;
  }
};

TEST_F(KtcCli, WritesTheChallengesFilesAndFindsTheTargets) {
  make_folder();
  const Result r =
      run("ktc " + path("in") + " " + path("out") + " 1 --method noser --lambda 0.1" + fast());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (int n : {1, 2}) {
    const std::string file = path("out/" + std::to_string(n) + ".mat");
    const auto arrays = detail::read_mat_v5(read_file_bytes(file), file);
    ASSERT_EQ(arrays.size(), 1u);
    EXPECT_EQ(arrays[0].name, "reconstruction");
    EXPECT_EQ(arrays[0].kind, "uint8");
    EXPECT_EQ(arrays[0].shape, (std::vector<std::size_t>{256, 256}));
    // Against the truth the folder holds: each class found where its disc is (centroids within
    // 12 pixels, 11 mm), and a score well above an empty image's.
    const ClassImage truth = read_ktc_truth(path("in/true" + std::to_string(n) + ".mat"));
    ClassImage reco(256, 256);
    for (int i = 0; i < 256; ++i)
      for (int j = 0; j < 256; ++j)
        reco(i, j) = static_cast<std::uint8_t>(arrays[0].values[i * 256 + j]);
    for (int cls : {1, 2}) {
      const Eigen::Vector2d t = centroid(truth, cls), c = centroid(reco, cls);
      if (!t.allFinite()) continue;  // no disc of this class in the sample
      EXPECT_LT((t - c).norm(), 12.0)
          << n << " class " << cls << ": " << t.transpose() << " vs " << c.transpose();
    }
    EXPECT_GT(ktc_score(truth, reco).total(),
              ktc_score(truth, ClassImage::Zero(256, 256)).total() + 0.15)
        << n;
    EXPECT_NE(r.output.find("score"), std::string::npos);
  }
  // Level 7 leaves electrodes 1 ... 12 out: still a file a sample, reconstructed from the rest.
  const Result r7 =
      run("ktc " + path("in") + " " + path("out7") + " 7 --method tikhonov --lambda 0.1" + fast());
  ASSERT_EQ(r7.exit_code, 0) << r7.output;
  EXPECT_TRUE(fs::exists(path("out7/1.mat")));
  EXPECT_NE(r7.output.find("values"), std::string::npos) << r7.output;
}

TEST_F(KtcCli, BadInputIsRefusedAndNothingIsWritten) {
  make_folder();
  const std::string ktc = "ktc " + path("in") + " " + path("out");
  const std::string run_ktc = "run --ktc " + path("in") + " --out " + path("out");
  refused(ktc + " 0" + fast(), "level");
  refused(ktc + " 8" + fast(), "level");
  refused("ktc " + path("in") + " " + path("in") + " 1" + fast(), "INPUT_FOLDER");
  refused(ktc + " 1 --method shape" + fast(), "--method");
  refused("ktc " + path("nowhere") + " " + path("out") + " 1" + fast(), "nowhere");
  refused(ktc + " 1 --segmentation otsu --resistive 0.3" + fast(), "--resistive");
  refused(run_ktc + " --pixels 8", "--pixels");
  refused(run_ktc + " --levels 1,1", "--levels");
  refused(run_ktc + " --methods noser,shape", "--methods");
  refused(run_ktc + " --tuning-tanks -1", "--tuning-tanks");
  refused(run_ktc + " --tune-on-simulation shape", "--tune-on-simulation");
  refused(run_ktc + " --methods tv --tune-on-simulation noser", "--tune-on-simulation");
  refused(run_ktc + " --tuning-tanks 0 --tune-on-simulation noser", "--tune-on-simulation");
  refused(run_ktc + " --tuning-tanks 501", "--tuning-tanks");
  refused(run_ktc + " --tuning-noise -0.001", "--tuning-noise");
  refused(run_ktc + " --tuning-noise 2", "--tuning-noise");
  refused(run_ktc + " --tuning-tanks 0 --tuning-noise 0.005", "--tuning-noise");
  refused(run_ktc + " --methods tv --tuning-noise 0.005", "--tuning-noise");
  refused("run --preset tiny --out " + path("out") + " --tuning-noise 0.005", "--tuning-noise");
  refused(ktc + " 1 --setting best" + fast(), "--setting");
  refused(ktc + " 1 --setting simulation" + fast(), "--setting");
  refused(ktc + " 1 --setting joint" + fast(), "--setting");
  refused(run_ktc + " --noise-sweep 0.01,0.01", "--noise-sweep");
  refused(run_ktc + " --noise-sweep 0 --noise-floor 0", "--noise-sweep");
  refused("run --preset tiny --out " + path("out") + " --noise-sweep 0.01", "--noise-sweep");
  // A run's results whose setting is not one: the file and the field named.
  fs::create_directories(path("run"));
  std::ofstream(path("run/results.json"))
      << R"({"kind": "ktc", "tank": {"radius": 0.115, "electrode_coverage": 0.5, "size_factor": 1,
         "density": "coarse", "background": 0.8, "contact_impedances": [0.1, 0.2]}})";
  refused(ktc + " 1 --from " + path("run"), "results.json: tank.contact_impedances");
  // A sample whose values do not match its patterns, and one whose currents do not sum to zero.
  const CurrentPatterns p = testing::ktc_patterns();
  write_bytes_atomically(
      path("in/data3.mat"),
      detail::mat_v5_bytes({testing::mat("Inj", p.injection), testing::mat("Mpat", p.measurement),
                            testing::mat("Uel", Eigen::VectorXd::Ones(2300))}));
  refused(ktc + " 1" + fast(), "data3.mat: Uel");
  CurrentPatterns q = p;
  q.injection(0, 5) = 0.3;
  write_bytes_atomically(
      path("in/data3.mat"),
      detail::mat_v5_bytes({testing::mat("Inj", q.injection), testing::mat("Mpat", q.measurement),
                            testing::mat("Uel", Eigen::VectorXd::Ones(2356))}));
  refused(ktc + " 1" + fast(), "data3.mat: Inj column 5");
  fs::remove(path("in/data3.mat"));
  fs::remove(path("in/ref.mat"));
  refused(ktc + " 1" + fast(), "ref.mat");
}

TEST_F(KtcCli, TheBenchmarkRanksTheMethodsAndKtcAppliesItsSettings) {
  make_folder();
  // Every method at level 7 (the fewest values: the quickest), then each applied by ktc --from.
  // The methods are tuned at a noise model other than --noise-relative's (GREIT, which it does
  // not change, aside), so that ktc --from reproduces their scores only if it takes each one's.
  const Result r =
      run("run --ktc " + path("in") + " --out " + path("run") +
          " --methods tikhonov,noser,laplace,smooth,greit,tv,gn --levels 7 --ktc-tanks 0 "
          "--noise-sweep 0.05 --tuning-tanks 2" +
          fast());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* file : {"results.json", "report.md"})
    EXPECT_TRUE(fs::exists(path("run/") + file)) << file;
  std::ifstream report(path("run/report.md"));
  std::stringstream text;
  text << report.rdbuf();
  for (const char* method : {"tikhonov", "noser", "laplace", "smooth", "greit", "tv", "gn"})
    EXPECT_NE(text.str().find(std::string("| ") + method + " |"), std::string::npos) << method;
  EXPECT_NE(text.str().find("held out"), std::string::npos);
  EXPECT_NE(text.str().find("tuned on simulation"), std::string::npos);
  EXPECT_NE(text.str().find("samples and tanks"), std::string::npos);
  const auto results = nlohmann::json::parse(read_file_bytes(path("run/results.json")));
  // The one-step methods are tuned on the two simulated tanks too, every sample scored with that
  // setting; the iterative ones are not (by default). The tanks were drawn on a finer mesh.
  EXPECT_EQ(results.at("tuning_tanks").at("tanks"), 2);
  EXPECT_EQ(results.at("tuning_tanks").at("density"), "fine");
  // Each sample's model misfit at level 1 (every value): the synthetic frames are the model's of
  // their truths, on another mesh and at contrasts between the fit's, so it explains most of
  // each; with a sample held out, the tanks' noise is the other's misfit.
  ASSERT_EQ(results.at("model_misfit").size(), results.at("samples").size());
  for (const auto& m : results.at("model_misfit")) {
    EXPECT_LT(m.at("relative").get<double>(), 0.5);
    EXPECT_EQ(m.at("values"), 76 * 31);
    EXPECT_GT(m.at("noise_without").get<double>(), 0.0);
  }
  EXPECT_NE(text.str().find("misses"), std::string::npos);
  for (const auto& m : results.at("methods")) {
    const std::string name = m.at("method");
    const bool one_step = name != "tv" && name != "gn";
    ASSERT_EQ(m.at("simulation").is_null(), !one_step) << name;
    if (!one_step) continue;
    EXPECT_EQ(m.at("simulation").at("tanks"), 2) << name;
    ASSERT_EQ(m.at("simulation").at("held_out").size(), 1u) << name;     // one level
    EXPECT_EQ(m.at("simulation").at("held_out")[0].size(), 2u) << name;  // two samples
    // Tuned on the other sample and the tanks together: a setting for each sample.
    ASSERT_EQ(m.at("joint").is_null(), !one_step) << name;
    EXPECT_EQ(m.at("joint").at("held_out_choices").size(), 2u) << name;
    ASSERT_EQ(m.at("joint").at("held_out").size(), 1u) << name;
    EXPECT_EQ(m.at("joint").at("held_out")[0].size(), 2u) << name;
  }
  // The tanks hold nothing of the samples: with one sample fewer the setting they choose is the
  // same, to the bit.
  testing::write_synthetic_ktc(path("in1"), {{{-0.04, 0.03, 0.025, 1}, {0.045, -0.02, 0.02, 2}}});
  const Result one = run("run --ktc " + path("in1") + " --out " + path("run1") +
                         " --methods tikhonov --levels 7 --ktc-tanks 0 --noise-sweep 0.05 "
                         "--tuning-tanks 2" +
                         fast());
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const auto fewer = nlohmann::json::parse(read_file_bytes(path("run1/results.json")));
  EXPECT_EQ(fewer.at("methods")[0].at("simulation").at("choice"),
            results.at("methods")[0].at("simulation").at("choice"));
  // By default the tanks carry the reference's measured noise (none: the synthetic frames are
  // exact); --tuning-noise sets another, and the same tanks then score otherwise.
  EXPECT_EQ(results.at("tuning_tanks").at("noise").get<double>(), 0.0);
  const Result noisy = run("run --ktc " + path("in1") + " --out " + path("run2") +
                           " --methods tikhonov --levels 7 --ktc-tanks 0 --noise-sweep 0.05 "
                           "--tuning-tanks 2 --tuning-noise 0.0125" +
                           fast());
  ASSERT_EQ(noisy.exit_code, 0) << noisy.output;
  const auto louder = nlohmann::json::parse(read_file_bytes(path("run2/results.json")));
  EXPECT_EQ(louder.at("tuning_tanks").at("noise").get<double>(), 0.0125);
  EXPECT_NE(louder.at("methods")[0].at("simulation").at("choice").at("tuning_score"),
            fewer.at("methods")[0].at("simulation").at("choice").at("tuning_score"));
  EXPECT_NE(read_file_bytes(path("run2/report.md")).find("each value's noise 0.0125 V"),
            std::string::npos);
  // ktc --from --setting simulation applies that setting: the scores the run had with it.
  const Result sim = run("ktc " + path("in") + " " + path("out_sim") +
                         " 7 --method tikhonov --setting simulation --from " + path("run"));
  ASSERT_EQ(sim.exit_code, 0) << sim.output;
  for (int s = 0; s < 2; ++s) {
    const std::string score =
        fmt::format("score {:.6f}",
                    results.at("methods")[0].at("simulation").at("held_out")[0][s].get<double>());
    EXPECT_NE(sim.output.find(score), std::string::npos) << score << "\n" << sim.output;
  }
  // --setting joint: the setting tuned on both samples and the tanks, the run's scores with it.
  const Result joint = run("ktc " + path("in") + " " + path("out_joint") +
                           " 7 --method noser --setting joint --from " + path("run"));
  ASSERT_EQ(joint.exit_code, 0) << joint.output;
  for (const auto& m : results.at("methods"))
    if (m.at("method") == "noser")
      for (int s = 0; s < 2; ++s) {
        const std::string score =
            fmt::format("score {:.6f}", m.at("joint").at("in_sample")[0][s].get<double>());
        EXPECT_NE(joint.output.find(score), std::string::npos) << score << "\n" << joint.output;
      }
  const Result no_sim = run("ktc " + path("in") + " " + path("out_sim2") +
                            " 7 --method tv --setting simulation --from " + path("run"));
  EXPECT_EQ(no_sim.exit_code, 2) << no_sim.output;
  EXPECT_NE(no_sim.output.find("--setting"), std::string::npos) << no_sim.output;
  EXPECT_FALSE(fs::exists(path("out_sim2")));
  // ktc --from takes the run's tank (the same ref.mat: no calibration) and each method's setting,
  // its noise model among it: every method writes the challenge's files with the scores the run
  // had with that setting (in sample), and one method every level's files.
  auto applied = [&](const std::string& method, int level) {
    const std::string out = path("out_" + method + std::to_string(level));
    const Result k = run("ktc " + path("in") + " " + out + " " + std::to_string(level) +
                         " --method " + method + " --from " + path("run"));
    EXPECT_EQ(k.exit_code, 0) << method << " " << level << "\n" << k.output;
    EXPECT_NE(k.output.find("as " + path("run/results.json") + " calibrated it"), std::string::npos)
        << k.output;
    for (const char* file : {"/1.mat", "/2.mat"})
      EXPECT_TRUE(fs::exists(out + file)) << method << level;
    if (level != 7) return;
    for (const auto& m : results.at("methods"))
      if (m.at("method") == method) {
        EXPECT_EQ(m.at("best").at("noise_relative").get<double>(),
                  ktc_sweeps_noise(method) ? 0.05 : 5e-4)
            << method;
        for (int s = 0; s < 2; ++s) {
          const std::string score =
              fmt::format("score {:.6f}", m.at("in_sample")[0][s].get<double>());
          EXPECT_NE(k.output.find(score), std::string::npos) << method << " " << score << "\n"
                                                             << k.output;
        }
      }
  };
  for (const char* method : {"tikhonov", "noser", "laplace", "smooth", "greit", "tv", "gn"})
    applied(method, 7);
  for (int level = 1; level <= 6; ++level) applied("greit", level);
  // Flags the run fixes, and a run of another kind, are refused; nothing is written.
  const Result fixed = run("ktc " + path("in") + " " + path("out2") +
                           " 1 --method noser --pixels 48 --from " + path("run"));
  EXPECT_EQ(fixed.exit_code, 2) << fixed.output;
  const Result other = run("ktc " + path("in") + " " + path("out2") + " 1 --from " + path("in"));
  EXPECT_EQ(other.exit_code, 2) << other.output;
  EXPECT_FALSE(fs::exists(path("out2")));
  // run --ktc with flags of the simulated benchmark, or without a truth beside a sample.
  const Result mixed = run("run --ktc " + path("in") + " --preset tiny --out " + path("run2"));
  EXPECT_EQ(mixed.exit_code, 2) << mixed.output;
  fs::remove(path("in/true2.mat"));
  const Result no_truth = run("run --ktc " + path("in") + " --out " + path("run3") +
                              " --methods noser --levels 1 --ktc-tanks 0" + fast());
  EXPECT_EQ(no_truth.exit_code, 2) << no_truth.output;
  EXPECT_NE(no_truth.output.find("true2.mat"), std::string::npos) << no_truth.output;
  EXPECT_FALSE(fs::exists(path("run3")));
}

// The learned rows: run --ktc trains none and group on simulated tanks, each from the frame (dnn)
// and from a one-step image (dnn-post), and scores them beside the model-based methods; ktc
// --method dnn|dnn-post --from RUN applies the run's model files (dnn-post rebuilding the one-step
// method from the file's record and the run's tank) and scores each sample as the run did.
TEST_F(KtcCli, TheRunTrainsTheLearnedModelsAndKtcAppliesThem) {
  make_folder();
  const Result r =
      run("run --ktc " + path("in") + " --out " + path("run") +
          " --methods noser --levels 1,7 --ktc-tanks 40 --ktc-steps 20 --doublings 0 --seed 3"
          " --tuning-tanks 0" +
          fast());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto results = nlohmann::json::parse(read_file_bytes(path("run/results.json")));
  EXPECT_EQ(results.at("learned").at("training").at("seed"), 3);  // --seed reaches the training
  const auto& arms = results.at("learned").at("arms");
  ASSERT_EQ(arms.size(), 4u);
  std::stringstream report;
  report << std::ifstream(path("run/report.md")).rdbuf();
  EXPECT_NE(report.str().find("## The learned models"), std::string::npos);
  std::set<std::string> trained;
  for (const auto& arm : arms) {
    const std::string name = arm.at("arm"), network = arm.at("network");
    trained.insert(network + " " + name);
    EXPECT_NE(report.str().find("| " + network + " " + name + " |"), std::string::npos) << name;
    EXPECT_TRUE(fs::exists(path("run/ktc_" + network + "_" + name + ".model"))) << name;
    EXPECT_EQ(arm.at("end"), "budget");  // 20 steps, no doubling: the report says so
    EXPECT_EQ(arm.at("training_frames"), name == "group" ? 8 * 32 : 32);
    const auto& scores = arm.at("scores");  // [level][sample]
    ASSERT_EQ(scores.size(), 2u);
    // The challenge's convention on the run's model: each sample's score as the run had it.
    for (int l = 0; l < 2; ++l) {
      const std::string level = l == 0 ? "1" : "7";
      const std::string folder = path(network + "_" + name + level);
      const Result k = run("ktc " + path("in") + " " + folder + " " + level + " --method " +
                           network + " --augment " + name + " --from " + path("run"));
      ASSERT_EQ(k.exit_code, 0) << k.output;
      for (int s = 0; s < 2; ++s) {
        EXPECT_TRUE(fs::exists(folder + "/" + std::to_string(s + 1) + ".mat"));
        const std::string score = fmt::format("score {:.6f}", scores[l][s].get<double>());
        EXPECT_NE(k.output.find(std::to_string(s + 1) + ": "), std::string::npos);
        EXPECT_NE(k.output.find(score), std::string::npos) << score << "\n" << k.output;
      }
    }
  }
  EXPECT_EQ(trained,
            (std::set<std::string>{"dnn none", "dnn group", "dnn-post none", "dnn-post group"}));
  // dnn needs a run; --augment goes with dnn; a KTC run trains none and group only, and the
  // networks dnn and dnn-post only.
  refused("run --ktc " + path("in") + " --out " + path("out") + " --ktc-learned cnn" + fast(),
          "--ktc-learned");
  refused("ktc " + path("in") + " " + path("out") + " 1 --method dnn", "--from");
  refused("ktc " + path("in") + " " + path("out") + " 1 --method noser --augment group" + fast(),
          "--augment");
  refused("ktc " + path("in") + " " + path("out") + " 1 --method dnn --lambda 0.1 --from " +
              path("run"),
          "--lambda");
  refused("run --ktc " + path("in") + " --out " + path("out") + " --augment d16" + fast(),
          "--augment");
  refused("run --ktc " + path("in") + " --out " + path("out") + " --ktc-tanks 5" + fast(),
          "--ktc-tanks");
  // A run whose model file is gone: the file named.
  fs::remove(path("run/ktc_dnn_none.model"));
  refused("ktc " + path("in") + " " + path("out") + " 1 --method dnn --augment none --from " +
              path("run"),
          "ktc_dnn_none.model");
}

}  // namespace
}  // namespace eitbench
