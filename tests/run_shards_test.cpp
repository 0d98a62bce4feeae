// A benchmark run in shards (docs/scaling.md): shards run one after another, then merge, give the
// run one process gives; merge refuses a missing, unfinished or foreign shard, naming it; a shard
// cut off resumes.
#include <gtest/gtest.h>

#include "cli_fixture.h"
#include "results_json.h"

namespace eitbench {
namespace {

const std::string kArgs = "--preset tiny --methods tikhonov,noser --augment none,d16 --quiet ";
const std::string kRun = "run " + kArgs;

TEST_F(Cli, RunShardsMergeIntoTheRunOneProcessMakes) {
  ASSERT_EQ(run(kRun + "--out " + path("one")).exit_code, 0);
  const std::string R = path("R");
  for (int k : {0, 2}) {
    const Result r = run(kRun + "--shard " + std::to_string(k) + "/3 --out " + R);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("eitbench merge"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(R + "/results.json"));  // a shard writes no report
  }
  Result m = run("merge " + R);
  EXPECT_EQ(m.exit_code, 2) << m.output;
  EXPECT_NE(m.output.find("shard(s) 1 of 3 missing"), std::string::npos) << m.output;

  // Shard 1 of another run (another seed): refused by its arguments.
  ASSERT_EQ(run(kRun + "--seed 2 --shard 1/3 --out " + R).exit_code, 0);
  m = run("merge " + R);
  EXPECT_EQ(m.exit_code, 2) << m.output;
  EXPECT_NE(m.output.find("1-of-3: arguments"), std::string::npos) << m.output;

  // Shard 1 cut off: not finished, the others untouched; --resume finishes it.
  const std::string one_of_three = R + "/shards/1-of-3";
  fs::remove_all(one_of_three);
  // Its units are noser and the sweep at n=30: killed between the two.
  ASSERT_TRUE(kill_when(kRun + "--shard 1/3 --out " + R,
                        [&] { return fs::exists(one_of_three + "/stages/method_noser.json"); }));
  m = run("merge " + R);
  EXPECT_EQ(m.exit_code, 2) << m.output;
  EXPECT_NE(m.output.find("has not finished"), std::string::npos) << m.output;
  EXPECT_TRUE(fs::exists(R + "/shards/0-of-3/shard.json"));
  EXPECT_TRUE(fs::exists(R + "/shards/2-of-3/shard.json"));
  ASSERT_EQ(run(kRun + "--shard 1/3 --resume --out " + R).exit_code, 0);

  m = run("merge " + R);
  ASSERT_EQ(m.exit_code, 0) << m.output;
  EXPECT_EQ(testing::results_without_timings(R + "/results.json"),
            testing::results_without_timings(path("one") + "/results.json"));
  EXPECT_TRUE(fs::exists(R + "/report.md"));
  EXPECT_EQ(run("merge " + R + " --out " + path("x.h5")).exit_code, 2);
  EXPECT_EQ(run("merge " + path("one")).exit_code, 2);  // no shards there
}

// The same run as a Slurm array of 3 shards and a merge job that depends on them, on a single-node
// cluster that tests/slurm/array_run.sh starts and stops; skipped where Slurm is not installed or
// will not start.
TEST_F(Cli, SlurmArrayOfShardsAndAMergeJobMakeTheRunOneProcessMakes) {
  ASSERT_EQ(run(kRun + "--threads 1 --out " + path("one")).exit_code, 0);
  const Result slurm = shell(std::string(EITBENCH_SOURCE_DIR) + "/tests/slurm/array_run.sh " +
                                 EITBENCH_CLI + " " + path("slurm") + " 3 " + kArgs + "--threads 1",
                             "slurm.log");
  if (slurm.exit_code == 77) GTEST_SKIP() << slurm.output;
  ASSERT_EQ(slurm.exit_code, 0) << slurm.output;
  EXPECT_EQ(testing::results_without_timings(path("slurm") + "/run/results.json"),
            testing::results_without_timings(path("one") + "/results.json"));
}

}  // namespace
}  // namespace eitbench
