// The tool under mpirun (docs/scaling.md): ranks shard the work, rank 0 joins it, and the result is
// one process's, byte for byte. Skipped in a build without MPI (the tool is then one process).
#include <gtest/gtest.h>

#include <map>
#include <thread>

#include "cli_fixture.h"
#include "eitbench/bench/data/dataset_file.h"
#include "results_json.h"

namespace eitbench {
namespace {

#ifdef EITBENCH_MPIEXEC
// As root, as CI runs, Open MPI needs both permissions; more ranks than cores need
// oversubscription; --bind-to none lets a rank's threads leave its core.
std::string mpirun(int ranks) {
  return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
         "OMPI_MCA_rmaps_base_oversubscribe=1 " EITBENCH_MPIEXEC " -np " +
         std::to_string(ranks) + " --bind-to none " EITBENCH_CLI " ";
}
#endif

class Mpi : public Cli {
 protected:
  void SetUp() override {
#ifndef EITBENCH_MPIEXEC
    GTEST_SKIP() << "built without MPI";
#endif
    Cli::SetUp();
  }
};

const char* const kSimulate = "simulate --preset tiny --seed 5 --density coarse --threads 1 ";

TEST_F(Mpi, RanksSimulateTheSetOneProcessSimulates) {
#ifdef EITBENCH_MPIEXEC
  ASSERT_EQ(run(std::string(kSimulate) + "--quiet --out " + path("one.h5")).exit_code, 0);
  const Dataset one = read_dataset(path("one.h5"));
  for (int ranks : {2, 3}) {
    const std::string out = path("ranks" + std::to_string(ranks) + ".h5");
    const Result r = shell(mpirun(ranks) + kSimulate + "--out " + out);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find(std::to_string(ranks) + " MPI ranks"), std::string::npos) << r.output;
    const Dataset d = read_dataset(out);
    EXPECT_EQ(d.frames, one.frames) << ranks << " ranks";
    EXPECT_EQ(d.differences, one.differences);
    EXPECT_EQ(d.labels, one.labels);
    EXPECT_EQ(d.split, one.split);
    EXPECT_EQ(d.reference, one.reference);
  }
  for (const auto& entry : fs::directory_iterator(path("")))  // the shard files are gone
    EXPECT_EQ(entry.path().filename().string().find(".shard-"), std::string::npos) << entry.path();
#endif
}

// mpirun -np 2 eitbench run: the ranks make the shards and rank 0 joins them into the run one
// process makes (timings and the machine apart).
TEST_F(Mpi, RanksRunTheBenchmarkOneProcessRuns) {
#ifdef EITBENCH_MPIEXEC
  const std::string args = "run --preset tiny --methods tikhonov,noser --augment none,d16 --quiet ";
  ASSERT_EQ(run(args + "--out " + path("one")).exit_code, 0);
  const Result r = shell(mpirun(2) + args + "--out " + path("two"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(testing::results_without_timings(path("two") + "/results.json"),
            testing::results_without_timings(path("one") + "/results.json"));
  EXPECT_TRUE(fs::exists(path("two") + "/shards/1-of-2/shard.json"));
#endif
}

#ifdef EITBENCH_MPIEXEC
// Every file under `folder` with its last write, but the lock and the finished record (which a
// resumed shard writes again).
std::map<std::string, fs::file_time_type> stage_files(const std::string& folder) {
  std::map<std::string, fs::file_time_type> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && name != ".eitbench.lock" && name != "shard.json")
      files[entry.path().string()] = entry.last_write_time();
  }
  return files;
}
#endif

// Rank 1 killed mid-run (SIGKILL, after its first unit, while rank 0 has finished and waits):
// mpirun fails, rank 0's shard and rank 1's finished stage stay as they were, and `--resume`
// finishes the run from them, without making any of them again, into one process's run.
TEST_F(Mpi, KillingOneRankKeepsTheOtherShardsAndResumeFinishesTheRun) {
#ifdef EITBENCH_MPIEXEC
  const std::string args = "run --preset tiny --methods tikhonov,noser --augment none,d16 --quiet ";
  ASSERT_EQ(run(args + "--out " + path("one")).exit_code, 0);
  const std::string R = path("R"), zero = R + "/shards/0-of-2", one = R + "/shards/1-of-2";
  Result killed{};
  std::thread mpi([&] { killed = shell(mpirun(2) + args + "--out " + R, "killed.log"); });
  // Rank 1's units are noser and the sweep at n=15: stopped between the two, until rank 0 is done.
  const bool noser_made = wait_for([&] { return fs::exists(one + "/stages/method_noser.json"); });
  pid_t rank1 = 0;
  std::ifstream(one + "/.eitbench.lock") >> rank1;
  if (noser_made && rank1 > 0) ::kill(rank1, SIGSTOP);
  const bool zero_done = wait_for([&] { return fs::exists(zero + "/shard.json"); });
  if (rank1 > 0) ::kill(rank1, SIGKILL);
  mpi.join();
  ASSERT_TRUE(noser_made && rank1 > 0 && zero_done) << killed.output;
  EXPECT_NE(killed.exit_code, 0) << killed.output;
  EXPECT_FALSE(fs::exists(one + "/shard.json"));
  EXPECT_FALSE(fs::exists(R + "/results.json"));
  const auto zero_files = stage_files(zero);
  EXPECT_EQ(zero_files.count(zero + "/stages/method_tikhonov.json"), 1u);
  const auto noser = fs::last_write_time(one + "/stages/method_noser.json");

  const Result resumed = shell(mpirun(2) + args + "--resume --out " + R);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(testing::results_without_timings(R + "/results.json"),
            testing::results_without_timings(path("one") + "/results.json"));
  EXPECT_EQ(stage_files(zero), zero_files);  // rank 0's shard was found made, file for file
  EXPECT_EQ(fs::last_write_time(one + "/stages/method_noser.json"), noser);
  EXPECT_TRUE(fs::exists(one + "/shard.json"));
#endif
}

// One rank that cannot write its shard fails the run, with its message; the other rank's
// finished shard stays, and no set is written. An explicit --shard is refused under mpirun.
TEST_F(Mpi, AFailedRankFailsTheRunAndKeepsTheFinishedShards) {
#ifdef EITBENCH_MPIEXEC
  fs::create_directories(path("x.shard-1-of-2.h5"));  // rank 1's output is a folder
  const Result r = shell(mpirun(2) + kSimulate + "--quiet --out " + path("x.h5"));
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("x.shard-1-of-2.h5"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("another rank failed"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(path("x.h5")));
  EXPECT_TRUE(fs::is_regular_file(path("x.shard-0-of-2.h5")));

  const Result shard = shell(mpirun(2) + kSimulate + "--shard 0/2 --out " + path("y.h5"));
  EXPECT_EQ(shard.exit_code, 2) << shard.output;
  EXPECT_NE(shard.output.find("the ranks are the shards"), std::string::npos) << shard.output;
  EXPECT_FALSE(fs::exists(path("y.h5")));
#endif
}

}  // namespace
}  // namespace eitbench
