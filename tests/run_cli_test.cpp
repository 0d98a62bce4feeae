// eitbench run, report and compare: the tiny preset end to end, every output and its schema, the
// results file's round trip, resuming, and compare's verdicts.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "cli_fixture.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/io/sensor_file.h"
#include "eitbench/bench/report/efficiency.h"
#include "eitbench/bench/report/report.h"
#include "eitbench/bench/report/results.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

// One tiny run shared by the tests of this file: made once for every process of the suite (CTest
// runs it as shards, each a process of its own, and a tiny run takes 40 s on 2 cores, twice that
// beside another shard), under a lock, in the build tree beside the eitbench it ran, and made
// again when that program changes. The tests read it or copy it, never write into it.
std::string shared_tiny_run() {
  const fs::path cli = EITBENCH_CLI;
  const fs::path dir = cli.parent_path() / "tests_tiny_run";
  const std::string stamp = std::to_string(fs::file_size(cli)) + " " +
                            std::to_string(fs::last_write_time(cli).time_since_epoch().count());
  const std::string lock_path = dir.string() + ".lock", stamp_path = dir.string() + ".stamp";
  const int lock = ::open(lock_path.c_str(), O_CREAT | O_RDWR, 0644);
  EXPECT_GE(lock, 0) << lock_path;
  if (lock >= 0) ::flock(lock, LOCK_EX);  // the others wait while one makes it
  std::ifstream in(stamp_path);
  std::string made;
  std::getline(in, made);
  if (made != stamp || !fs::exists(dir / "results.json")) {
    fs::remove(stamp_path);
    fs::remove_all(dir);
    const fs::path part = dir.string() + ".part";
    fs::remove_all(part);
    const std::string command = cli.string() + " run --preset tiny --quiet --out " + part.string() +
                                " > " + (dir.string() + ".log") + " 2>&1";
    const int status = std::system(command.c_str());
    EXPECT_EQ(WEXITSTATUS(status), 0) << command;
    if (WEXITSTATUS(status) == 0) {
      fs::rename(part, dir);
      std::ofstream(stamp_path) << stamp << "\n";
    }
  }
  if (lock >= 0) ::flock(lock, LOCK_UN), ::close(lock);
  return dir.string();
}

class RunCli : public Cli {
 protected:
  static std::string run_folder() {
    static const std::string folder = shared_tiny_run();
    return folder;
  }
};

std::vector<std::string> csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  bool quoted = false;
  for (char c : line) {
    if (c == '"')
      quoted = !quoted;
    else if (c == ',' && !quoted)
      cells.push_back(cell), cell.clear();
    else
      cell += c;
  }
  cells.push_back(cell);
  return cells;
}

TEST_F(RunCli, TinyPresetWritesEveryOutput) {
  const fs::path dir = run_folder();
  for (const char* name :
       {"results.json", "reconstructions.npy", "results.csv", "report.md", "reconstructions.png",
        "loss_curves.png", "loss_curves.csv", "data_efficiency.png", "data_efficiency_re.png",
        "touch_centre_errors.png", "data.h5"})
    EXPECT_TRUE(fs::exists(dir / name)) << name;
  // Each line plot is gnuplot's, with its data, its script and an SVG beside it.
  for (const char* plot :
       {"loss_curves", "data_efficiency", "data_efficiency_re", "touch_centre_errors"})
    for (const char* ext : {".dat", ".gp", ".svg"})
      EXPECT_TRUE(fs::exists(dir / (std::string(plot) + ext))) << plot << ext;

  // results.csv: tidy, one row per method x augmentation x SNR, the columns issue 7 names.
  std::ifstream csv(dir / "results.csv");
  std::string line;
  std::getline(csv, line);
  const auto header = csv_line(line);
  const std::vector<std::string> required = {
      "method", "augment",           "snr_db",         "cc",     "re", "ssim",
      "mse",    "latency_median_ms", "latency_p95_ms", "setup_s"};
  ASSERT_GE(header.size(), required.size());
  for (std::size_t k = 0; k < required.size(); ++k) EXPECT_EQ(header[k], required[k]);
  std::set<std::string> keys, snrs;
  int rows = 0;
  while (std::getline(csv, line)) {
    const auto cells = csv_line(line);
    ASSERT_EQ(cells.size(), header.size()) << line;
    keys.insert(cells[0] + "/" + cells[1] + "/" + cells[2]);
    snrs.insert(cells[2]);
    const double cc = std::stod(cells[3]), re = std::stod(cells[4]);
    EXPECT_TRUE(cc >= -1 && cc <= 1) << line;
    EXPECT_GT(re, 0) << line;
    EXPECT_GT(std::stod(cells[7]), 0) << line;
    ++rows;
  }
  EXPECT_EQ(rows, (8 + 4) * 4);  // 8 model-based methods, 4 learned
  EXPECT_EQ(keys.size(), static_cast<std::size_t>(rows)) << "no duplicate rows";
  EXPECT_EQ(snrs, (std::set<std::string>{"inf", "50", "40", "30"}));

  // results.json: the same rows, the training runs and the sweep, the configuration and machine.
  const RunResults r = read_results_json((dir / "results.json").string());
  EXPECT_EQ(static_cast<int>(r.rows.size()), rows);
  EXPECT_EQ(r.training.size(), 4u);
  for (const auto& t : r.training) {
    EXPECT_EQ(t.history.size(), 3u) << t.augment;
    // 3 epochs are far below the patience of 10 rounds: the budget ends every run.
    EXPECT_FALSE(t.converged) << t.augment;
    EXPECT_GT(t.fraction_of_gemm_peak, 0) << t.augment;
    EXPECT_LT(t.fraction_of_gemm_peak, 1) << t.augment;
  }
  // Per size: none and d16 to convergence, d16 at none's steps.
  ASSERT_EQ(r.efficiency.size(), 3u * 3);
  for (std::size_t k = 0; k < r.efficiency.size(); k += 3) {
    EXPECT_EQ(r.efficiency[k].augment + " " + r.efficiency[k].budget, "none converged");
    EXPECT_EQ(r.efficiency[k + 1].augment + " " + r.efficiency[k + 1].budget, "d16 converged");
    EXPECT_EQ(r.efficiency[k + 2].budget, "equal_steps");
    EXPECT_EQ(r.efficiency[k + 2].steps, r.efficiency[k].steps) << "equal compute";
    EXPECT_GT(r.efficiency[k].samples_seen, 0);
  }
  EXPECT_EQ(r.configuration.at("preset"), "tiny");
  EXPECT_FALSE(r.machine.at("cpu").empty());
  EXPECT_NE(r.program.find("eitbench"), std::string::npos);
  EXPECT_NE(r.recommendation.find("Pick"), std::string::npos);
  // ... and says that the learned models it ranks did not converge.
  EXPECT_NE(r.recommendation.find("Not converged:** dnn (none), dnn (rotations)"),
            std::string::npos)
      << r.recommendation;
  // Every row has touch metrics on the 7 test frames (4 touches each), at a threshold of the
  // candidates chosen on validation; the shape fit's are its circles as found (no threshold).
  for (const auto& row : r.rows) {
    EXPECT_EQ(row.touch.frames, 7) << row.method;
    EXPECT_EQ(row.touch.true_touches, 28) << row.method;
    if (row.method.rfind("shape", 0) == 0)
      EXPECT_TRUE(std::isnan(row.touch.threshold)) << row.method;
    else
      EXPECT_TRUE(row.touch.threshold == 0.3 || row.touch.threshold == 0.4 ||
                  row.touch.threshold == 0.5 || row.touch.threshold == 0.6 ||
                  row.touch.threshold == 0.7)
          << row.method << " " << row.touch.threshold;
    EXPECT_NEAR(row.touch.missed_per_frame, 4.0 - row.touch.matched / 7.0, 1e-12) << row.method;
  }
  // The model-based methods beat chance on the tiny test split (CC > 0.5 noise-free).
  for (const auto& row : r.rows)
    if (row.augment == "-" && std::isinf(row.snr_db)) {
      EXPECT_GT(row.cc, 0.5) << row.method;
    }

  std::ifstream report(dir / "report.md");
  const std::string text((std::istreambuf_iterator<char>(report)),
                         std::istreambuf_iterator<char>());
  for (const char* section :
       {"Which reconstructor to pick", "Table I", "relative improvement", "## Runtime",
        "## Training", "**no** (budget)", "## Data efficiency", "reconstructions.png", "## Touches",
        "touch_centre_errors.png", "## Configuration"})
    EXPECT_NE(text.find(section), std::string::npos) << section;
}

TEST_F(RunCli, ResumeReusesFinishedStagesWithTheSameFigures) {
  const fs::path first = run_folder();
  fs::copy(first, dir_ / "copy", fs::copy_options::recursive);
  const Result r = run("run --preset tiny --quiet --resume --out " + path("copy"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const RunResults a = read_results_json((first / "results.json").string());
  const RunResults b = read_results_json(path("copy/results.json"));
  ASSERT_EQ(a.rows.size(), b.rows.size());
  // Model-based rows come back from the finished stages exactly. The learned models are reloaded
  // from their files and evaluated again: float32 inference in another process (other buffer
  // alignment, other kernels' summation order) agrees to about 1e-8 relative, not bit for bit.
  for (std::size_t k = 0; k < a.rows.size(); ++k) {
    const ResultRow &x = a.rows[k], &y = b.rows[k];
    ASSERT_EQ(x.method + x.augment, y.method + y.augment);
    if (x.method == "dnn") {
      EXPECT_NEAR(x.cc, y.cc, 1e-6 * std::abs(x.cc)) << x.augment;
      EXPECT_NEAR(x.re, y.re, 1e-6 * x.re) << x.augment;
    } else {
      EXPECT_EQ(x.cc, y.cc) << x.method;
      EXPECT_EQ(x.re, y.re) << x.method;
      EXPECT_TRUE(x.touch.threshold == y.touch.threshold ||
                  (std::isnan(x.touch.threshold) && std::isnan(y.touch.threshold)))
          << x.method;
      EXPECT_EQ(x.touch.centre_error_median, y.touch.centre_error_median) << x.method;
    }
  }
  EXPECT_LT(std::stod(b.configuration.at("total_seconds")),
            0.5 * std::stod(a.configuration.at("total_seconds")))
      << "resumed stages are not recomputed";
}

TEST_F(RunCli, KilledRunResumesToTheSameFigures) {
  // Killed with SIGKILL while it trains its first model, then resumed. One model-based method
  // keeps the wait for training short (under the sanitizers too); its rows and the learned ones
  // must equal the uninterrupted run's.
  const std::string args = "run --preset tiny --quiet --methods noser --out " + path("cut");
  ASSERT_TRUE(
      kill_when(args, [&] { return fs::exists(path("cut/models/dnn_none.pt.checkpoint")); }));
  EXPECT_FALSE(fs::exists(path("cut/results.json")));
  const Result r = run(args + " --resume");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const RunResults a = read_results_json((fs::path(run_folder()) / "results.json").string());
  const RunResults b = read_results_json(path("cut/results.json"));
  ASSERT_EQ(b.rows.size(), (1u + 4u) * 4u);
  for (const ResultRow& y : b.rows) {
    const ResultRow* x = nullptr;
    for (const ResultRow& row : a.rows)
      if (row.method == y.method && row.augment == y.augment &&
          (row.snr_db == y.snr_db || (std::isinf(row.snr_db) && std::isinf(y.snr_db))))
        x = &row;
    ASSERT_NE(x, nullptr) << y.method << " " << y.augment;
    if (y.method == "dnn") {  // see ResumeReusesFinishedStagesWithTheSameFigures
      EXPECT_NEAR(x->cc, y.cc, 1e-6 * std::abs(x->cc)) << y.augment;
    } else {
      EXPECT_EQ(x->cc, y.cc) << y.method;
    }
  }
  // No temporary file is left: the killed run's were removed by the resumed one.
  for (const auto& entry : fs::recursive_directory_iterator(path("cut")))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
}

TEST_F(RunCli, MeasuredFramesAreReconstructedWithTheSimulatedPresetsChoices) {
  // Measured frames without labels (--reference): every method runs on them, tuned and trained on
  // the simulated tiny preset, and nothing claims a quality it cannot know.
  const std::string data = std::string(EITBENCH_BAD_INPUTS) + "/../data/";
  const Result r =
      run("run --preset tiny --quiet --methods tikhonov,noser --augment none --data " + data +
          "frames_rotating.npy --reference " + data + "reference.npy --out " + path("measured"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("quality cannot be ranked"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(path("measured/reconstructions.png")));

  const RunResults m = read_results_json(path("measured/results.json"));
  EXPECT_EQ(m.configuration.at("test_frames"), "3");
  ASSERT_EQ(m.rows.size(), 3u) << "tikhonov, noser and dnn/none, at the frames' own noise only";
  // The choices are the simulated preset's at its noise-free level: each row's settings (λ, the
  // network's size) equal those of a run on the preset itself, which tunes and trains on the same
  // data with the same seed.
  const Result s = run("run --preset tiny --quiet --methods tikhonov,noser --augment none --out " +
                       path("simulated"));
  ASSERT_EQ(s.exit_code, 0) << s.output;
  const RunResults tiny = read_results_json(path("simulated/results.json"));
  for (const ResultRow& y : m.rows) {
    EXPECT_TRUE(std::isinf(y.snr_db)) << y.method;
    EXPECT_TRUE(std::isnan(y.cc) && std::isnan(y.re)) << y.method << ": scored without labels";
    EXPECT_EQ(y.frames, 0) << y.method;
    EXPECT_EQ(y.touch.frames, 0) << y.method << ": touches scored without circles";
    EXPECT_GT(y.latency_median_ms, 0) << y.method;
    const ResultRow* x = nullptr;
    for (const ResultRow& row : tiny.rows)
      if (row.method == y.method && row.augment == y.augment && std::isinf(row.snr_db)) x = &row;
    ASSERT_NE(x, nullptr) << y.method;
    EXPECT_EQ(x->settings, y.settings) << y.method;
  }
  std::ifstream report(path("measured/report.md"));
  const std::string text((std::istreambuf_iterator<char>(report)),
                         std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("quality cannot be ranked"), std::string::npos);
  EXPECT_EQ(text.find("Pick **"), std::string::npos) << "a pick made without labels";
  EXPECT_EQ(text.find("## Touches"), std::string::npos);
  EXPECT_FALSE(fs::exists(path("measured/touch_centre_errors.png")));
}

// The flags that shape the simulated set and the sweep refuse what they cannot use, naming the
// flag, before anything is simulated or written.
TEST_F(RunCli, SweepAndVariationFlagsRefuseBadValues) {
  const std::string base = "run --preset tiny --quiet --out " + path("out") + " ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--sweep 5,3", "--sweep: sizes must ascend"},
      {"--sweep 500,", "--sweep: '' is not a training-set size"},
      {"--sweep 1", "--sweep: '1' is not a training-set size"},
      {"--touch-radius 0.2,0.3", "--touch-contrast: needs"},
      {"--touch-contrast 0,0.3", "--touch-contrast: goes with --touch-radius"},
      {"--randomise-snr 50,40", "--randomise-snr: needs"},
      {"--decay 0.01", "--decay: must be at least the warm-up's 0.02"},
  };
  for (const auto& [flags, message] : cases) {
    const Result r = run(base + flags);
    EXPECT_EQ(r.exit_code, 2) << flags << "\n" << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << flags << "\n" << r.output;
    EXPECT_FALSE(fs::exists(path("out/data.h5"))) << flags;
  }
  const Result s =
      run("simulate --preset tiny --quiet --touch-radius 0.2,0.3 --out " + path("set.h5"));
  EXPECT_EQ(s.exit_code, 2) << s.output;
  EXPECT_FALSE(fs::exists(path("set.h5")));
  // --sensor-noise needs a sensor file with a measured noise, and gains of the protocol's channels.
  SensorFile sensor;
  sensor.electrodes = 16, sensor.background = 0.05;
  sensor.contact_impedances = Eigen::VectorXd::Constant(16, 0.01);
  write_sensor_file(path("plain.json"), sensor);
  SensorNoise noise;
  noise.noise = 0.003, noise.signal = 0.02, noise.gains = Eigen::VectorXd::Ones(192);
  sensor.noise = noise;
  write_sensor_file(path("opposite.json"), sensor);
  for (const auto& [file, message] : std::vector<std::pair<std::string, std::string>>{
           {"plain.json", "plain.json: noise: is absent: measure it with calibrate --noise"},
           {"opposite.json",
            "--sensor-noise: gains: has 192 channels' gains; the adjacent "
            "protocol has 208"}}) {
    const Result n = run("simulate --preset tiny --quiet --sensor-noise " + path(file) + " --out " +
                         path("set.h5"));
    EXPECT_EQ(n.exit_code, 2) << n.output;
    EXPECT_NE(n.output.find(message), std::string::npos) << n.output;
    EXPECT_FALSE(fs::exists(path("set.h5")));
  }
}

// A sweep size above the training split is the whole split: the main runs' converged models
// there, not a size left out (the standard preset's 5,500 on its 5,459 training frames was).
TEST_F(RunCli, SweepSizeAboveTheSplitIsTheWholeSplit) {
  const Result r = run(
      "run --preset tiny --quiet --methods tikhonov --augment none,d16 --sweep 30,100000 --out " +
      path("s"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const RunResults results = read_results_json(path("s/results.json"));
  const int train = std::stoi(results.configuration.at("training_samples"));
  ASSERT_LT(30, train);
  ASSERT_EQ(results.efficiency.size(), 2u * 3);
  EXPECT_EQ(results.efficiency[0].train_size, 30);
  for (std::size_t k = 3; k < 6; ++k) EXPECT_EQ(results.efficiency[k].train_size, train);
  for (std::size_t k : {3, 4}) {  // none and d16 converged: the main runs' noise-free rows
    const EfficiencyPoint& p = results.efficiency[k];
    int found = 0;
    for (const ResultRow& row : results.rows)
      if (row.method == "dnn" && row.augment == p.augment && std::isinf(row.snr_db)) {
        EXPECT_EQ(p.cc, row.cc) << p.augment;
        ++found;
      }
    EXPECT_EQ(found, 1) << p.augment;
  }
  EXPECT_NE(results.configuration.at("efficiency").find("sizes 30 to " + std::to_string(train)),
            std::string::npos)
      << results.configuration.at("efficiency");
}

// --decay moves the learned model's schedule (its figures change, the model-based ones do not),
// and a resumed run with another --decay trains again instead of reusing the model it made.
TEST_F(RunCli, DecayReachesTheLearnedSchedule) {
  const std::string base =
      "run --preset tiny --quiet --methods tikhonov --augment none "
      "--sweep none --out ";
  ASSERT_EQ(run(base + path("a")).exit_code, 0);
  fs::copy(path("a"), path("c"), fs::copy_options::recursive);
  ASSERT_EQ(run(base + path("b") + " --decay 0.3").exit_code, 0);
  const Result resumed = run(base + path("c") + " --decay 0.3 --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  const RunResults a = read_results_json(path("a/results.json"));
  const RunResults b = read_results_json(path("b/results.json"));
  const RunResults c = read_results_json(path("c/results.json"));
  ASSERT_EQ(a.rows.size(), b.rows.size());
  ASSERT_EQ(a.rows.size(), c.rows.size());
  for (std::size_t k = 0; k < a.rows.size(); ++k) {
    const ResultRow &x = a.rows[k], &y = b.rows[k], &z = c.rows[k];
    if (x.method == "dnn") {
      EXPECT_NE(x.cc, y.cc) << x.snr_db;
      EXPECT_NEAR(z.cc, y.cc, 1e-6 * std::abs(y.cc)) << x.snr_db;
    } else {
      EXPECT_EQ(x.cc, y.cc) << x.method;
    }
  }
  EXPECT_NE(a.configuration.at("training").find("after 0.6 of the budget"), std::string::npos);
  EXPECT_NE(b.configuration.at("training").find("after 0.3 of the budget"), std::string::npos);
}

TEST_F(RunCli, KilledSimulationLeavesNoFile) {
  const std::string out = path("d.h5");
  ASSERT_TRUE(kill_when("simulate --preset quick --quiet --out " + out, [&] {
    for (const auto& entry : fs::directory_iterator(dir_))
      if (entry.path().filename().string().find(".tmp") != std::string::npos) return true;
    return false;
  })) << "the simulation never started writing";
  EXPECT_FALSE(fs::exists(out)) << "a killed simulation left a data set";
  // The next run to the same path succeeds and clears the dead run's temporary.
  ASSERT_EQ(run("simulate --preset tiny --density coarse --quiet --out " + out).exit_code, 0);
  EXPECT_EQ(read_dataset(out).size(), 81);
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
}

// `eitbench report` draws from the store alone (results.json, reconstructions.npy): in a copy of
// the run holding nothing else, it re-draws every derived file, byte for byte as the run did.
TEST_F(RunCli, ReportRedrawsTheRunFromItsStoredResults) {
  const fs::path finished = run_folder();
  const fs::path copy = path("copy");
  fs::create_directories(copy);
  for (const char* name : {"results.json", "reconstructions.npy"})
    fs::copy_file(finished / name, copy / name);
  const Result r = run("report " + copy.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ms/frame"), std::string::npos) << r.output;  // the summary table
  for (const char* name : {"report.md", "results.csv", "reconstructions.png", "loss_curves.csv",
                           "loss_curves.png", "data_efficiency.png", "touch_centre_errors.png"}) {
    ASSERT_TRUE(fs::exists(copy / name)) << name;
    EXPECT_EQ(file_text(copy / name), file_text(finished / name)) << name;
  }
  // The pick is re-made from the rows: a stored one from an older rule does not survive.
  RunResults stale = read_results_json((copy / "results.json").string());
  stale.recommendation = "Pick **an older rule's choice**.";
  write_results_json((copy / "results.json").string(), stale);
  ASSERT_EQ(run("report --quiet " + copy.string()).exit_code, 0);
  EXPECT_EQ(file_text(copy / "report.md"), file_text(finished / "report.md"));
  // Without the images, everything else is drawn and the old figure is left alone.
  fs::remove(copy / "reconstructions.npy");
  fs::remove(copy / "reconstructions.png");
  EXPECT_EQ(run("report " + copy.string()).exit_code, 0);
  EXPECT_FALSE(fs::exists(copy / "reconstructions.png"));
  // Without gnuplot the line plots are left as data and scripts, and the report says how to draw
  // them; a gnuplot that fails is an error that leaves none of its files.
  for (const char* name : {"loss_curves.png", "loss_curves.svg", "loss_curves.dat"})
    fs::remove(copy / name);
  const std::string cli = EITBENCH_CLI;
  const std::string log = path("gnuplot.log");
  const int none = std::system(
      ("PATH=/nonexistent " + cli + " report " + copy.string() + " > " + log + " 2>&1").c_str());
  EXPECT_EQ(WEXITSTATUS(none), 0) << file_text(log);
  EXPECT_NE(file_text(log).find("gnuplot is not installed"), std::string::npos) << file_text(log);
  EXPECT_TRUE(fs::exists(copy / "loss_curves.dat"));
  EXPECT_TRUE(fs::exists(copy / "loss_curves.gp"));
  EXPECT_FALSE(fs::exists(copy / "loss_curves.png"));
  const int failing = std::system(
      ("EITBENCH_GNUPLOT=/bin/false " + cli + " report " + copy.string() + " > " + log + " 2>&1")
          .c_str());
  EXPECT_EQ(WEXITSTATUS(failing), 2) << file_text(log);
  EXPECT_NE(file_text(log).find("gnuplot (/bin/false) failed"), std::string::npos)
      << file_text(log);
  EXPECT_FALSE(fs::exists(copy / "loss_curves.png"));
  for (const auto& entry : fs::directory_iterator(copy))
    EXPECT_EQ(entry.path().filename().string().find(".gnuplot"), std::string::npos) << entry.path();
  // Not a run: a message naming the file, exit 2, nothing written.
  const fs::path empty = path("empty");
  fs::create_directories(empty);
  const Result bad = run("report " + empty.string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("results.json"), std::string::npos) << bad.output;
  EXPECT_TRUE(fs::is_empty(empty));
  // Images that do not fit results.json's rows are refused.
  fs::copy_file(finished / "reconstructions.npy", copy / "reconstructions.npy");
  std::string npy = file_text(copy / "reconstructions.npy");
  npy.resize(npy.size() / 2);
  std::ofstream(copy / "reconstructions.npy", std::ios::binary) << npy;
  const Result truncated = run("report " + copy.string());
  EXPECT_EQ(truncated.exit_code, 2) << truncated.output;
  EXPECT_NE(truncated.output.find("reconstructions.npy"), std::string::npos) << truncated.output;
}

TEST(Results, JsonRoundTrip) {
  RunResults r;
  r.program = "eitbench test";
  r.configuration = {{"preset", "x"}, {"seed", "3"}};
  r.machine = {{"cpu", "test cpu"}};
  ResultRow a;
  a.method = "tv", a.snr_db = INFINITY, a.cc = 0.8125, a.re = 0.5, a.ssim = 0.25, a.mse = 1e-3;
  a.latency_median_ms = 37.5, a.latency_p95_ms = 40, a.setup_s = 1.5, a.frames = 7;
  a.settings = "alpha=3e-05 (validation), \"quoted\"";
  ResultRow b = a;
  b.method = "dnn", b.augment = "d16", b.snr_db = 40, b.cc = NAN, b.frames = 0;
  r.rows = {a, b};
  TrainingSummary t;
  t.augment = "d16", t.best_round = 1, t.best_epoch = 1, t.steps = 4, t.converged = true;
  t.end = "rule", t.doublings = 1, t.budget_steps = 8, t.stage_best = {0.25, 0.2495};
  t.fraction_of_gemm_peak = 0.375;
  t.inference_device = "cuda:0", t.device_latency_ms = 0.5, t.device_frames_per_second = 7e4;
  t.history.push_back({1, 1, 4, 64, 0.5, 0.25, 1e-3, 1.0, 64.0});
  r.training = {t};
  r.efficiency = {
      {"none", "converged", 15, 6, 2, 0.01, 0.5, 0.9, true, 90, 2, 1e3, 0.25, 0.125, 0.0625, 7}};
  r.recommendation = "Pick tv";
  const std::string path = (fs::temp_directory_path() / "eitbench_results_roundtrip.json").string();
  write_results_json(path, r);
  const RunResults back = read_results_json(path);
  fs::remove(path);
  EXPECT_EQ(back.program, r.program);
  EXPECT_EQ(back.configuration, r.configuration);
  EXPECT_EQ(back.machine, r.machine);
  ASSERT_EQ(back.rows.size(), 2u);
  EXPECT_TRUE(std::isinf(back.rows[0].snr_db));
  EXPECT_EQ(back.rows[0].cc, 0.8125);
  EXPECT_EQ(back.rows[0].settings, a.settings);
  EXPECT_EQ(back.rows[1].snr_db, 40);
  EXPECT_TRUE(std::isnan(back.rows[1].cc));
  EXPECT_EQ(back.rows[1].augment, "d16");
  ASSERT_EQ(back.training.size(), 1u);
  EXPECT_EQ(back.training[0].history[0].validation_loss, 0.25);
  EXPECT_EQ(back.training[0].history[0].learning_rate, 1e-3);
  EXPECT_TRUE(back.training[0].converged);
  EXPECT_EQ(back.training[0].end, "rule");
  EXPECT_EQ(back.training[0].doublings, 1);
  EXPECT_EQ(back.training[0].budget_steps, 8);
  EXPECT_EQ(back.training[0].stage_best, t.stage_best);
  EXPECT_EQ(back.training[0].fraction_of_gemm_peak, 0.375);
  EXPECT_EQ(back.training[0].inference_device, "cuda:0");
  EXPECT_EQ(back.training[0].device_latency_ms, 0.5);
  EXPECT_EQ(back.training[0].device_frames_per_second, 7e4);
  ASSERT_EQ(back.efficiency.size(), 1u);
  EXPECT_EQ(back.efficiency[0].test_mse, 0.01);
  EXPECT_TRUE(back.efficiency[0].converged);
  EXPECT_EQ(back.efficiency[0].samples_seen, 90);
  EXPECT_EQ(back.efficiency[0].fraction_of_gemm_peak, 0.25);
  EXPECT_EQ(back.efficiency[0].cc_std, 0.125);
  EXPECT_EQ(back.efficiency[0].re_std, 0.0625);
  EXPECT_EQ(back.efficiency[0].frames, 7);
  EXPECT_EQ(back.recommendation, r.recommendation);
}

// The pick: the best CC, unless a method within 0.02 CC of it is at least 1.5x faster; a few
// microseconds between two GPU models are timing noise, not a reason.
TEST(Report, RecommendsTheBestUnlessAnotherIsClearlyFaster) {
  ResultRow best;
  best.method = "dnn", best.augment = "d16", best.snr_db = 40, best.cc = 0.899, best.frames = 9;
  best.latency_median_ms = 0.331;
  ResultRow close = best;
  close.augment = "paper", close.cc = 0.881, close.latency_median_ms = 0.329;
  EXPECT_EQ(recommend({best, close}).rfind("Pick **dnn (d16)**", 0), 0u)
      << recommend({best, close});
  close.latency_median_ms = 0.2;  // 1.66x faster, 0.018 CC behind: it wins
  EXPECT_EQ(recommend({best, close}).rfind("Pick **dnn (paper)**", 0), 0u);
  close.cc = 0.87;  // 0.029 behind: the best CC wins however fast the other
  close.latency_median_ms = 0.01;
  EXPECT_EQ(recommend({best, close}).rfind("Pick **dnn (d16)**", 0), 0u);
}

// A model timed on a GPU gets the report's GPU inference table; a CPU run's report has none.
TEST(Report, GpuInferenceOnlyWhereMeasured) {
  RunResults r;
  ResultRow row;
  row.method = "dnn", row.augment = "d16", row.snr_db = INFINITY, row.cc = 0.5, row.frames = 1;
  r.rows = {row};
  TrainingSummary t;
  t.augment = "d16", t.best_round = 1, t.best_epoch = 1, t.steps = 4, t.converged = true;
  t.end = "rule", t.doublings = 1, t.budget_steps = 8, t.stage_best = {0.25, 0.2495};
  t.history.push_back({1, 1, 4, 64, 0.5, 0.25, 1e-3, 1.0, 64.0});
  r.training = {t};
  const fs::path dir =
      fs::temp_directory_path() / ("eitbench_gpu_report_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto report = [&] {
    write_report((dir / "report.md").string(), r);
    return file_text((dir / "report.md").string());
  };
  EXPECT_EQ(report().find("Inference on the GPU"), std::string::npos);
  EXPECT_EQ(report().find("The learned reconstructor ran on"), std::string::npos);
  r.configuration["learned_device"] = "cuda";  // a run that scored its models on the GPU
  EXPECT_NE(report().find("The learned reconstructor ran on cuda"), std::string::npos);
  r.training[0].inference_device = "cuda:0";
  r.training[0].device_latency_ms = 0.4125, r.training[0].device_frames_per_second = 68389;
  const std::string text = report();
  EXPECT_NE(text.find("Inference on the GPU"), std::string::npos) << text;
  EXPECT_NE(text.find("| d16 | cuda:0 | 0.412 | 68389 |"), std::string::npos) << text;
  fs::remove_all(dir);
}

TEST_F(RunCli, CompareFlagsRegressionsAndPassesAnIdenticalRun) {
  const std::string results = (fs::path(run_folder()) / "results.json").string();
  const Result same = run("compare " + results + " " + results);
  EXPECT_EQ(same.exit_code, 0) << same.output;
  EXPECT_NE(same.output.find("no regression"), std::string::npos) << same.output;

  // Every test frame 0.05 worse: the mean drops beyond tolerance and the paired test is sure.
  RunResults worse = read_results_json(results);
  for (auto& row : worse.rows)
    if (row.method == "noser" && row.snr_db == 40) {
      ASSERT_EQ(row.frame_cc.size(), static_cast<std::size_t>(row.frames));
      row.cc -= 0.05;
      for (double& cc : row.frame_cc) cc -= 0.05 + 1e-4 * (&cc - row.frame_cc.data());
    }
  write_results_json(path("worse.json"), worse);
  const Result flagged = run("compare " + results + " " + path("worse.json"));
  EXPECT_EQ(flagged.exit_code, 1) << flagged.output;
  EXPECT_NE(flagged.output.find("noser/-/40: CC"), std::string::npos) << flagged.output;
  EXPECT_NE(flagged.output.find("(p = "), std::string::npos) << flagged.output;
  // Within a looser tolerance it passes.
  EXPECT_EQ(run("compare " + results + " " + path("worse.json") + " --tolerance 0.06").exit_code,
            0);

  // The same drop of the mean from one frame alone: beyond tolerance, but not significant.
  RunResults one_frame = read_results_json(results);
  for (auto& row : one_frame.rows)
    if (row.method == "noser" && row.snr_db == 40) {
      row.cc -= 0.05;
      row.frame_cc[0] -= 0.05 * row.frames;
    }
  write_results_json(path("one_frame.json"), one_frame);
  const Result lone = run("compare " + results + " " + path("one_frame.json"));
  EXPECT_EQ(lone.exit_code, 0) << lone.output;
  // Without per-frame scores (a run from before they were kept) the means decide alone.
  for (auto& row : one_frame.rows) row.frame_cc.clear(), row.frame_re.clear();
  write_results_json(path("no_frames.json"), one_frame);
  EXPECT_EQ(run("compare " + results + " " + path("no_frames.json")).exit_code, 1);

  RunResults slower = read_results_json(results);
  for (auto& row : slower.rows)
    if (row.method == "tv") row.latency_median_ms *= 3;
  slower.rows.erase(slower.rows.begin());  // and one row lost
  write_results_json(path("slower.json"), slower);
  const Result slow = run("compare " + results + " " + path("slower.json"));
  EXPECT_EQ(slow.exit_code, 1);
  EXPECT_NE(slow.output.find("tv/-/inf: latency"), std::string::npos) << slow.output;
  EXPECT_NE(slow.output.find("missing"), std::string::npos) << slow.output;

  {
    std::ofstream bad(path("bad.json"));
    bad << "{\"format\": \"eitbench-results-1\", \"program\": 3}";
  }
  const Result broken = run("compare " + results + " " + path("bad.json"));
  EXPECT_EQ(broken.exit_code, 2) << broken.output;
  EXPECT_NE(broken.output.find("bad.json"), std::string::npos) << broken.output;
}

}  // namespace
}  // namespace eitbench

namespace eitbench {
namespace {

// The sweep's headline: the fewest frames at which D16 reaches the CC that no augmentation reaches
// with the most; the equal-compute line does not count.
TEST(Efficiency, HeadlineNamesTheFewestFramesThatMatchTheLargestPlainSet) {
  auto point = [](const char* augment, const char* budget, int n, double cc) {
    EfficiencyPoint p;
    p.augment = augment, p.budget = budget, p.train_size = n, p.cc = cc, p.converged = true;
    return p;
  };
  std::vector<EfficiencyPoint> points = {
      point("none", "converged", 100, 0.60),  point("d16", "converged", 100, 0.70),
      point("d16", "equal_steps", 100, 0.95), point("none", "converged", 400, 0.75),
      point("d16", "converged", 400, 0.80),   point("none", "converged", 1600, 0.78),
      point("d16", "converged", 1600, 0.85)};
  const std::string text = efficiency_headline(points);
  EXPECT_NE(text.find("D16 on 400 frames reaches the CC that no augmentation reaches on 1600"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("4x fewer"), std::string::npos) << text;
  points[4].cc = 0.77;  // now only the whole set matches
  EXPECT_NE(efficiency_headline(points).find("D16 on 1600 frames"), std::string::npos);
  points[6].cc = 0.7;
  EXPECT_NE(efficiency_headline(points).find("does not reach"), std::string::npos);
  std::ostringstream section;
  write_efficiency_section(section, points);
  EXPECT_NE(section.str().find("| 400 | 0.750 / 0.000 ("), std::string::npos) << section.str();
}

}  // namespace
}  // namespace eitbench
