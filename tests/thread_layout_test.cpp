// The threads a learned model trains with are --threads, whatever else ran in the process and
// whatever the launcher's environment says (docs/scaling.md "What is equal"): its figures depend on
// the count, so a mesh made before training, OMP_DYNAMIC, OMP_NUM_THREADS or a binding to fewer
// cores must not change it.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cli_fixture.h"
#include "eitbench/jacobian/disk_mesh.h"
#include "eitbench/learned/runtime.h"
#include "results_json.h"

namespace eitbench {
namespace {

// Gmsh sets the meshing thread's OpenMP thread count to its own (1) on initialising; LibTorch reads
// that count on every parallel operation once it has started, so a mesh made after LibTorch's
// first use once trained the learned model on one thread instead of two.
TEST(ThreadLayout, AMeshLeavesLibTorchsThreadsAsTheyWere) {
  const int before = torch_threads();  // LibTorch starts its threads here, as a run does first
  for (int threads : {2, 1}) {
    set_torch_threads(threads);
    ASSERT_EQ(torch_threads(), threads);
    DiskMeshOptions o;
    o.density = MeshDensity::coarse;
    generate_disk_mesh(o);
    EXPECT_EQ(torch_threads(), threads) << "a mesh changed LibTorch's threads";
    EXPECT_FALSE(thread_layout().dynamic);
  }
  set_torch_threads(before);
}

TEST(ThreadLayout, DescribesItselfAndWarnsOfMoreThreadsThanCpus) {
  ThreadLayout layout;
  layout.threads = 2, layout.dynamic = false, layout.cpus = 1, layout.blas = "OpenBLAS";
  EXPECT_EQ(layout.describe(), "2 threads, OpenMP dynamic off, 1 CPU allowed; OpenBLAS");
  EXPECT_NE(layout.warning().find("2 threads on 1 CPU"), std::string::npos) << layout.warning();
  layout.cpus = 2;
  EXPECT_EQ(layout.warning(), "");
  EXPECT_GT(thread_layout().cpus, 0);  // this process's own affinity is read
}

class ThreadLayoutCli : public Cli {
 protected:
  // The tiny run of one model-based method and the learned model under `environment`, bounded in
  // time: OMP_DYNAMIC once hung OpenBLAS for ever.
  Result run_under(const std::string& environment, const std::string& out,
                   const std::string& extra = "") const {
    return run_after("timeout 600 env " + environment + " ",
                     "run --preset tiny --methods tikhonov --augment none --quiet " + extra +
                         " --out " + path(out));
  }
  nlohmann::json machine(const std::string& out) const {
    std::ifstream in(path(out) + "/results.json");
    return nlohmann::json::parse(in)["machine"];
  }
};

// What a launcher may set (Slurm's OMP_NUM_THREADS, OpenBLAS's own count, OMP_DYNAMIC, a binding
// to one core, the wait policy: the tests run passive) changes neither the threads LibTorch trains
// with nor any figure.
TEST_F(ThreadLayoutCli, TheLaunchersThreadSettingsChangeNoFigure) {
  ASSERT_EQ(run_under("EITBENCH_UNUSED=1", "plain").exit_code, 0);
  const auto plain = testing::results_without_timings(path("plain") + "/results.json");
  EXPECT_EQ(machine("plain")["torch_threads"], "2");
  const std::vector<std::string> environments = {"OMP_NUM_THREADS=1", "OPENBLAS_NUM_THREADS=1",
                                                 "OMP_DYNAMIC=true", "OMP_WAIT_POLICY=active"};
  for (std::size_t k = 0; k < environments.size(); ++k) {
    const std::string& environment = environments[k];
    const std::string out = "env" + std::to_string(k);
    const Result r = run_under(environment, out);
    ASSERT_EQ(r.exit_code, 0) << environment << "\n" << r.output;
    EXPECT_EQ(testing::results_without_timings(path(out) + "/results.json"), plain) << environment;
    EXPECT_EQ(machine(out)["torch_threads"], "2") << environment;
  }
  const Result bound = run_after("taskset -c 0 ",
                                 "run --preset tiny --methods tikhonov "
                                 "--augment none --quiet --out " +
                                     path("bound"));
  ASSERT_EQ(bound.exit_code, 0) << bound.output;
  EXPECT_NE(bound.output.find("warning: 2 threads on 1 CPU"), std::string::npos) << bound.output;
  EXPECT_EQ(testing::results_without_timings(path("bound") + "/results.json"), plain);
}

// Fewer threads than asked for would change the figures and hang OpenBLAS: refused, nothing made.
TEST_F(ThreadLayoutCli, AThreadLimitBelowTheThreadsIsRefused) {
  const Result r = run_under("OMP_THREAD_LIMIT=1", "limited");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("OMP_THREAD_LIMIT"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(path("limited")));
  const Result one = run_under("OMP_THREAD_LIMIT=1", "one", "--threads 1");
  ASSERT_EQ(one.exit_code, 0) << one.output;
  EXPECT_EQ(machine("one")["torch_threads"], "1");
}

}  // namespace
}  // namespace eitbench
