// Runs that cannot lie: --resume reuses only what was made for the same data and options, one
// writer per output folder, and a write that fails (disk full, a file-size limit) ends in exit 2
// and its message, with nothing partial left and an existing output untouched.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <fstream>

#include "cli_fixture.h"
#include "eitbench/bench/report/results.h"
#include "results_json.h"

namespace eitbench {
namespace {

// A small run: one model-based method, one learned model, two epochs (about 10 s). Its log says
// what it resumes and what it makes again; kQuiet is the same run without a log.
const std::string kSmall = "run --preset tiny --methods tikhonov --augment none --epochs 2";
const std::string kQuiet = kSmall + " --quiet";

class RunTrust : public Cli {};

// The measured failure: a tiny run's folder resumed by the quick preset re-simulated its data and
// then reused every tiny stage and model. Now the folder's data set is checked first.
TEST_F(RunTrust, ResumeOntoAnotherPresetsDataStops) {
  ASSERT_EQ(run(kQuiet + " --out " + path("x")).exit_code, 0);
  const std::string results = file_text(path("x/results.json"));
  const Result r = run("run --preset quick --quiet --resume --out " + path("x"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("data.h5"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("preset tiny (this run: quick)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("choose a new --out"), std::string::npos) << r.output;
  EXPECT_EQ(file_text(path("x/results.json")), results);
}

// Other options on the same data: every stage they touch is made again, none is reused, and the
// run's fingerprint changes; the same options resume everything.
TEST_F(RunTrust, ResumeWithOtherOptionsMakesStagesAgain) {
  ASSERT_EQ(run(kQuiet + " --out " + path("x")).exit_code, 0);
  const RunResults first = read_results_json(path("x/results.json"));
  const std::string other =
      "run --preset tiny --methods tikhonov --augment none --epochs 3 --threads 1";
  const Result r = run(other + " --resume --out " + path("x"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("method_tikhonov: made again: it was made with other threads"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("dnn none: trained again: it was made with other epochs"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("resumed from"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("tikhonov: resumed"), std::string::npos) << r.output;
  const RunResults second = read_results_json(path("x/results.json"));
  EXPECT_NE(first.configuration.at("fingerprint"), second.configuration.at("fingerprint"));
  const Result again = run(other + " --resume --out " + path("x"));
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("tikhonov: resumed"), std::string::npos) << again.output;
  EXPECT_NE(again.output.find("dnn none: resumed from"), std::string::npos) << again.output;
  EXPECT_EQ(read_results_json(path("x/results.json")).configuration.at("fingerprint"),
            second.configuration.at("fingerprint"));
}

// The budget rule's rate-left edge in a record, as this version writes it and as runs made
// before it moved wrote it.
const std::string kEdgeNow = "rate left at a tenth of the cosine's range";
const std::string kEarlierEdge = "rate left at 2x the floor";

// Replaces the first `from` in a file by `to` (the file must hold it).
void replace_in(const std::string& file, const std::string& from, const std::string& to) {
  std::string text = file_text(file);
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos) << file << ": " << text;
  std::ofstream(file, std::ios::binary) << text.replace(at, from.size(), to);
}

// A model trained when the budget rule's rate-left edge lay at twice the floor, whose training
// the rule as it is now decides alike, is kept on --resume (hours of the standard preset's
// models), its record rewritten; a record of any other rule is trained again.
TEST_F(RunTrust, ResumeKeepsAModelTheChangedRuleDecidesAlike) {
  ASSERT_EQ(run(kQuiet + " --out " + path("x")).exit_code, 0);
  const std::string record = path("x/models/dnn_none.pt.provenance.json");
  replace_in(record, kEdgeNow, kEarlierEdge);
  const Result kept = run(kSmall + " --resume --out " + path("x"));
  ASSERT_EQ(kept.exit_code, 0) << kept.output;
  EXPECT_NE(
      kept.output.find("dnn none: kept: trained with other budget rule, which decide it alike"),
      std::string::npos)
      << kept.output;
  EXPECT_NE(kept.output.find("dnn none: resumed from"), std::string::npos) << kept.output;
  EXPECT_NE(file_text(record).find(kEdgeNow), std::string::npos);
  replace_in(record, kEdgeNow, "rate left at 3x the floor");
  const Result again = run(kSmall + " --resume --out " + path("x"));
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("dnn none: trained again: it was made with other budget rule"),
            std::string::npos)
      << again.output;
}

// A sweep point's figures made under the earlier edge are kept only while its model is the one
// they were measured on. A point whose model was trained again since (its record names the rule
// as it is now: a run killed between the training and the score) is made again.
TEST_F(RunTrust, ResumeKeepsASweepPointOnlyWithItsOwnModel) {
  const std::string sweep =
      "run --preset tiny --methods tikhonov --augment none,d16 --epochs 2 "
      "--sweep 30 --out " +
      path("s");
  ASSERT_EQ(run(sweep + " --quiet").exit_code, 0);
  for (const std::string point : {"efficiency_none_converged_30", "efficiency_d16_converged_30"})
    replace_in(path("s/stages/" + point + ".json"), kEdgeNow, kEarlierEdge);
  replace_in(path("s/models/efficiency_none_converged_30.pt.provenance.json"), kEdgeNow,
             kEarlierEdge);
  const Result r = run(sweep + " --resume");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("efficiency_none_converged_30: kept: made with other budget rule"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("efficiency_d16_converged_30: made again: it was made with other "
                          "budget rule"),
            std::string::npos)
      << r.output;
}

// A run moved to another machine with its stages/ folder alone (a GPU session brings back a few
// MB; a paper-size model is 19 MB): the learned models resume from their records, the data set is
// simulated again, and the run ends with the same figures, none trained. A record of other
// options is not used: that model is trained.
TEST_F(RunTrust, ResumeFromTheStagesAloneGivesTheSameFigures) {
  const std::string flags = "run --preset tiny --methods tikhonov --sweep 30 --epochs ";
  const std::string sweep = flags + "2 --augment none,d16 --out ";
  ASSERT_EQ(run(sweep + path("whole") + " --quiet").exit_code, 0);
  for (const std::string folder : {"moved", "other"}) {
    fs::create_directories(path(folder));
    fs::copy(path("whole/stages"), path(folder + "/stages"));
  }
  const Result r = run(sweep + path("moved") + " --resume");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* augment : {"none", "d16"})
    EXPECT_NE(r.output.find("dnn " + std::string(augment) + ": resumed from its record"),
              std::string::npos)
        << r.output;
  EXPECT_EQ(r.output.find(": training the"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(path("moved/models/dnn_none.pt")));
  const RunResults a = read_results_json(path("whole/results.json")),
                   b = read_results_json(path("moved/results.json"));
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (std::size_t k = 0; k < a.rows.size(); ++k) {
    EXPECT_EQ(a.rows[k].method + a.rows[k].augment, b.rows[k].method + b.rows[k].augment);
    EXPECT_EQ(a.rows[k].cc, b.rows[k].cc) << k;
    EXPECT_EQ(a.rows[k].re, b.rows[k].re) << k;
    EXPECT_EQ(a.rows[k].latency_median_ms, b.rows[k].latency_median_ms) << k;
  }
  ASSERT_EQ(b.training.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(a.training[k].steps, b.training[k].steps);
    EXPECT_EQ(a.training[k].seconds, b.training[k].seconds);  // the training's, not a re-run's
  }
  ASSERT_EQ(a.efficiency.size(), b.efficiency.size());
  for (std::size_t k = 0; k < a.efficiency.size(); ++k)
    EXPECT_EQ(a.efficiency[k].cc, b.efficiency[k].cc) << k;
  EXPECT_EQ(file_text(path("whole/reconstructions.npy")),
            file_text(path("moved/reconstructions.npy")));

  const Result other = run(flags + "3 --augment none,d16 --resume --out " + path("other"));
  ASSERT_EQ(other.exit_code, 0) << other.output;
  EXPECT_EQ(other.output.find("resumed from its record"), std::string::npos) << other.output;
  EXPECT_NE(other.output.find("dnn none: training the"), std::string::npos) << other.output;
}

// scripts/gpu-paper.sh, the paper run spread over GPU sessions, on the tiny preset and the CPU:
// a later call, in a folder of its own, goes on from the first call's stages tarball alone and
// ends with the same results, training nothing; a tarball made with other threads is refused.
TEST_F(RunTrust, GpuPaperScriptGoesOnFromTheStagesTarball) {
  const std::string cli = EITBENCH_CLI;
  const std::string script = std::string(EITBENCH_SOURCE_DIR) + "/scripts/gpu-paper.sh ";
  const std::string env = "BUILD=" + fs::path(cli).parent_path().string() +
                          " PRESET=tiny METHODS=tikhonov RUN_FLAGS='--augment none,d16 "
                          "--epochs 2 --sweep 30' ";
  auto call = [&](const std::string& settings, const std::string& name) {
    return shell(env + settings + script + path(name) + " " + path(name + "-back") + " 300",
                 name + ".log");
  };
  const Result first = call("THREADS=1 ", "first");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  ASSERT_TRUE(fs::exists(path("first-back/stages.tar.gz"))) << first.output;
  const std::string stages = "STAGES=" + path("first-back/stages.tar.gz") + " ";
  const Result later = call(stages + "THREADS=1 ", "later");
  ASSERT_EQ(later.exit_code, 0) << later.output;
  const std::string log = file_text(path("later-back/run.log"));
  EXPECT_NE(log.find("dnn d16: resumed from its record"), std::string::npos) << log;
  EXPECT_EQ(log.find(": training the"), std::string::npos) << log;
  ASSERT_TRUE(fs::exists(path("later-back/results.tar.gz"))) << later.output;
  EXPECT_EQ(testing::results_without_timings(path("later/results.json")),
            testing::results_without_timings(path("first/results.json")));

  const Result other = call(stages + "THREADS=2 ", "other");
  EXPECT_EQ(other.exit_code, 2) << other.output;
  EXPECT_NE(other.output.find("made with other sources, GPU or threads"), std::string::npos)
      << other.output;
  EXPECT_FALSE(fs::exists(path("other/results.json")));
}

// A user's data set replaced by another between two runs: the stages are made again from it.
TEST_F(RunTrust, ResumeOnOtherUserDataMakesStagesAgain) {
  ASSERT_EQ(run("simulate --preset tiny --quiet --seed 1 --out " + path("a.h5")).exit_code, 0);
  ASSERT_EQ(run("simulate --preset tiny --quiet --seed 2 --out " + path("b.h5")).exit_code, 0);
  ASSERT_EQ(run(kQuiet + " --data " + path("a.h5") + " --out " + path("x")).exit_code, 0);
  const Result r = run(kSmall + " --resume --data " + path("b.h5") + " --out " + path("x"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("method_tikhonov: made again: it was made with other data"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("dnn none: trained again: it was made with other training data"),
            std::string::npos)
      << r.output;
}

// True while some process holds the folder's lock (the file keeps the last holder's PID after
// it ends, so only the lock itself tells). The probe takes the lock for a moment when it is free,
// so it must never race a writer that is about to take it: a run refused by the probe never
// locks at all.
bool locked(const std::string& lock_file) {
  const int fd = ::open(lock_file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool held = ::flock(fd, LOCK_EX | LOCK_NB) != 0;
  ::close(fd);
  return held;
}

// A second writer into a folder, and a report of it, are refused with the holder's PID while the
// first runs; the lock dies with its holder, even by SIGKILL.
TEST_F(RunTrust, OneWriterPerFolder) {
  ASSERT_EQ(run(kQuiet + " --out " + path("x")).exit_code, 0);
  Result second{-1, ""}, report{-1, ""};
  // Resumed with another epoch budget, it trains again: long enough to be caught at work.
  const std::string longer =
      "run --preset tiny --quiet --methods tikhonov --augment none --epochs 50 --resume";
  // Caught at work once the lock file names it: a writer writes its PID only after it holds the
  // lock, and reading the file never takes the lock from under it (locked() would: CI once saw
  // the run refused by the probe itself, and the test wait 300 s for a lock never taken).
  ASSERT_TRUE(kill_when(longer + " --out " + path("x"), [&] {
    const std::string pid = file_text(path("pid"));
    const std::string holder = file_text(path("x/.eitbench.lock"));
    if (holder.empty() || pid.find_first_not_of(" \n") == std::string::npos ||
        std::stol(pid) != std::stol(holder))
      return false;
    second = run(kQuiet + " --out " + path("x"));
    report = run("report --quiet " + path("x"));
    return true;
  }));
  EXPECT_EQ(second.exit_code, 2) << second.output;
  EXPECT_NE(second.output.find("another eitbench (PID "), std::string::npos) << second.output;
  EXPECT_EQ(report.exit_code, 2) << report.output;
  EXPECT_NE(report.output.find("is writing to this folder"), std::string::npos) << report.output;
  EXPECT_FALSE(locked(path("x/.eitbench.lock")));
  const Result after = run(kQuiet + " --out " + path("x"));  // the killed run held it
  EXPECT_EQ(after.exit_code, 0) << after.output;
}

// Commands whose writes are limited to `kib` KiB a file (RLIMIT_FSIZE through ulimit -f, in
// 512-byte blocks, with SIGXFSZ ignored): a write past it fails with EFBIG, as on a full disk.
class WriteFailures : public Cli {
 protected:
  Result limited(const std::string& args, int kib) const {
    return shell("sh -c \"trap '' XFSZ; ulimit -f " + std::to_string(kib * 2) + "; exec " +
                 EITBENCH_CLI + " " + args + "\"");
  }
  // Exit 2 naming a file of the test's folder, no crash, nothing partial left, and an existing
  // `file` as it was.
  void expect_clean_failure(const std::string& args, const std::string& file, int kib) {
    const bool existed = fs::exists(file);
    const std::string before = existed ? file_text(file) : "";
    const Result r = limited(args, kib);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find("error: " + dir_.string()), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("Segmentation"), std::string::npos) << r.output;
    EXPECT_EQ(fs::exists(file), existed) << file;
    if (existed) {
      EXPECT_EQ(file_text(file), before) << file;
    }
    for (const auto& entry : fs::recursive_directory_iterator(dir_)) {
      EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos)
          << entry.path() << " left by " << args;
    }
  }
};

TEST_F(WriteFailures, EveryWriterExitsCleanly) {
  ASSERT_EQ(run("simulate --preset tiny --quiet --out " + path("t.h5")).exit_code, 0);
  ASSERT_EQ(run(kQuiet + " --out " + path("x")).exit_code, 0);
  ASSERT_EQ(
      run("train --data " + path("t.h5") + " --steps 1 --quiet --out " + path("m.pt")).exit_code,
      0);
  // HDF5: a data set (streamed through the writing child), images, a Jacobian.
  expect_clean_failure("simulate --preset tiny --quiet --out " + path("d.h5"), path("d.h5"), 64);
  expect_clean_failure("simulate --preset tiny --quiet --out " + path("t.h5"), path("t.h5"), 64);
  expect_clean_failure(
      "reconstruct --method noser --png 0 --data " + path("t.h5") + " --out " + path("images.h5"),
      path("images.h5"), 8);
  expect_clean_failure("jacobian --conductivity 1 --out " + path("j.h5"), path("j.h5"), 64);
  // CSV, a model and its checkpoint, PNG, the run's store and report.
  expect_clean_failure("forward --conductivity 1 --out " + path("f.csv"), path("f.csv"), 1);
  expect_clean_failure("train --data " + path("t.h5") + " --steps 1 --quiet --out " + path("m.pt"),
                       path("m.pt"), 64);
  expect_clean_failure("mesh --density coarse --png " + path("mesh.png"), path("mesh.png"), 4);
  expect_clean_failure("report --quiet " + path("x"), path("x/report.md"), 4);
  expect_clean_failure(kQuiet + " --resume --out " + path("x"), path("x/results.json"), 4);
}

// The measured case, on a real full disk: a 3 MB tmpfs in a mount namespace of its own. Skipped
// where this process may not mount (not root, or no namespaces).
TEST_F(WriteFailures, SimulateOntoAFullDisk) {
  const std::string mount = path("small");
  fs::create_directories(mount);
  const std::string command = "unshare -m sh -c 'mount -t tmpfs -o size=3m tmpfs " + mount +
                              " && " + EITBENCH_CLI + " simulate --preset quick --quiet --out " +
                              mount + "/d.h5; echo \"exit $?\"; ls -A " + mount + "' > " +
                              path("log.txt") + " 2>&1";
  std::system(command.c_str());
  const std::string log = file_text(path("log.txt"));
  if (log.find("exit ") == std::string::npos) GTEST_SKIP() << "cannot mount a tmpfs: " << log;
  EXPECT_NE(log.find("exit 2"), std::string::npos) << log;
  EXPECT_NE(log.find("disk full?"), std::string::npos) << log;
  EXPECT_EQ(log.find("d.h5\n", log.find("exit 2")), std::string::npos) << "a file was left:\n"
                                                                       << log;
}

}  // namespace
}  // namespace eitbench
