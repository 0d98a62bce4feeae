// eitbench compare on microbenchmark JSON: two runs of the same build show no change, a build
// made 20 % slower on purpose is flagged (exit 1), too few repetitions are not decided, and files
// that are not Google Benchmark JSON, or of two kinds, are refused naming the file.
#include <fstream>

#include "cli_fixture.h"

namespace eitbench {
namespace {

class CompareSpeed : public Cli {
 protected:
  // The fixture's JSON with `repetitions`, `slowdown` more work (0.2: 20 %).
  std::string bench(const std::string& name, double slowdown, int repetitions = 9) const {
#ifndef EITBENCH_SLOWDOWN_FIXTURE
    (void)slowdown, (void)repetitions;
    return "";
#else
    const std::string out = path(name);
    const std::string command =
        "EITBENCH_SLOWDOWN=" + std::to_string(slowdown) + " " + EITBENCH_SLOWDOWN_FIXTURE +
        " --benchmark_repetitions=" + std::to_string(repetitions) +
        " --benchmark_min_time=0.02 --benchmark_out_format=json --benchmark_out=" + out +
        " > /dev/null 2>&1";
    return std::system(command.c_str()) == 0 ? out : "";
#endif
  }
};

// CPU time: the test shares two cores with other tests, whose load would move wall-clock time
// more than the work does. The slow build runs between the two plain ones, so that drift of the
// machine's speed over the test falls on both comparisons alike.
TEST_F(CompareSpeed, SameBuildPassesADeliberateSlowdownIsFlagged) {
#ifndef EITBENCH_SLOWDOWN_FIXTURE
  GTEST_SKIP() << "built without the microbenchmarks (EITBENCH_BUILD_BENCHMARKS=OFF)";
#endif
  const std::string a = bench("a.json", 0), slow = bench("slow.json", 0.2), b = bench("b.json", 0);
  ASSERT_FALSE(a.empty() || b.empty() || slow.empty());
  const Result same = run("compare " + a + " " + b + " --cpu-time");
  EXPECT_EQ(same.exit_code, 0) << same.output;
  EXPECT_NE(same.output.find("BM_Work"), std::string::npos) << same.output;
  EXPECT_NE(same.output.find("no regression"), std::string::npos) << same.output;

  const Result flagged = run("compare " + a + " " + slow + " --cpu-time");
  EXPECT_EQ(flagged.exit_code, 1) << flagged.output;
  EXPECT_NE(flagged.output.find("SLOWER"), std::string::npos) << flagged.output;
  // The other way round the slow build's successor is faster, which is no regression.
  const Result faster = run("compare " + slow + " " + b + " --cpu-time");
  EXPECT_EQ(faster.exit_code, 0) << faster.output;
  EXPECT_NE(faster.output.find("faster"), std::string::npos) << faster.output;
}

TEST_F(CompareSpeed, TooFewRepetitionsAreNotDecided) {
#ifndef EITBENCH_SLOWDOWN_FIXTURE
  GTEST_SKIP() << "built without the microbenchmarks (EITBENCH_BUILD_BENCHMARKS=OFF)";
#endif
  const std::string a = bench("a.json", 0, 3), slow = bench("slow.json", 0.5, 3);
  ASSERT_FALSE(a.empty() || slow.empty());
  const Result r = run("compare " + a + " " + slow);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("undecided: 3 repetitions, need 9"), std::string::npos) << r.output;
}

TEST_F(CompareSpeed, RefusesBadAndMixedFiles) {
  {
    std::ofstream(path("gb.json")) << R"({"context": {"host_name": "x"}, "benchmarks": [
      {"name": "BM_A", "run_type": "iteration", "real_time": 5, "cpu_time": 5, "time_unit": "ms"},
      {"name": "BM_A", "run_type": "aggregate", "aggregate_name": "mean", "real_time": 5,
       "cpu_time": 5, "time_unit": "ms"}]})";
    std::ofstream(path("unit.json")) << R"({"context": {}, "benchmarks": [
      {"name": "BM_A", "run_type": "iteration", "real_time": 5, "cpu_time": 5,
       "time_unit": "fortnights"}]})";
    std::ofstream(path("time.json")) << R"({"context": {}, "benchmarks": [
      {"name": "BM_A", "run_type": "iteration", "real_time": "fast", "cpu_time": 5}]})";
    std::ofstream(path("results.json")) << R"({"format": "eitbench-results-1"})";
    std::ofstream(path("broken.json")) << "{\"context\": ";
  }
  const Result same = run("compare " + path("gb.json") + " " + path("gb.json"));
  EXPECT_EQ(same.exit_code, 0) << same.output;  // one repetition each: undecided, not refused
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"unit.json", "benchmarks[0].time_unit"},
      {"time.json", "benchmarks[0].real_time"},
      {"results.json", "compare two of a kind"},
      {"broken.json", "not JSON"}};
  for (const auto& [file, says] : bad) {
    const Result r = run("compare " + path("gb.json") + " " + path(file));
    EXPECT_EQ(r.exit_code, 2) << file << ": " << r.output;
    EXPECT_NE(r.output.find(file), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(says), std::string::npos) << r.output;
  }
}

}  // namespace
}  // namespace eitbench
