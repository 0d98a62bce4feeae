// learned/'s LibTorch half is a module the tool loads on first use (learned/src/backend.h): a
// command that never touches a network runs without LibTorch, one that trains loads it, and a
// module that cannot be loaded is an error naming where it was looked for, with nothing written.
#include "cli_fixture.h"

namespace eitbench {
namespace {

using LearnedModule = Cli;

// The dynamic loader's own log of a run (LD_DEBUG=files, on stderr) names every library it loads.
constexpr const char* kLoaderLog = "env LD_DEBUG=files ";
bool loads_libtorch(const Result& r) {
  return r.output.find("libtorch_cpu.so") != std::string::npos;
}

TEST_F(LearnedModule, OnlyACommandThatUsesANetworkLoadsLibTorch) {
  const std::string data = path("d.h5");
  const Result simulate = run_after(
      kLoaderLog, "simulate --preset tiny --seed 5 --density coarse --quiet --out " + data);
  ASSERT_EQ(simulate.exit_code, 0) << simulate.output;
  EXPECT_NE(simulate.output.find("libgmsh"), std::string::npos)  // the log is there ...
      << "LD_DEBUG gave no loader log";
  EXPECT_FALSE(loads_libtorch(simulate));  // ... and LibTorch is not in it

  const Result train =
      run_after(kLoaderLog, "train --data " + data + " --steps 1 --quiet --out " + path("m.pt"));
  ASSERT_EQ(train.exit_code, 0) << train.output.substr(train.output.size() - 2000);
  EXPECT_TRUE(loads_libtorch(train));
  EXPECT_TRUE(fs::exists(path("m.pt")));
}

TEST_F(LearnedModule, AMissingModuleIsAnErrorOnlyWhereANetworkIsNeeded) {
  const std::string missing = path("nowhere/libeitbench_learned_torch.so");
  const std::string env = "env EITBENCH_LEARNED_MODULE=" + missing + " ";
  const std::string data = path("d.h5");
  ASSERT_EQ(run_after(env, "simulate --preset tiny --seed 5 --density coarse --quiet --out " + data)
                .exit_code,
            0);
  const Result train =
      run_after(env, "train --data " + data + " --steps 1 --quiet --out " + path("m.pt"));
  EXPECT_EQ(train.exit_code, 1) << train.output;
  EXPECT_NE(train.output.find("LibTorch module could not be loaded"), std::string::npos)
      << train.output;
  EXPECT_NE(train.output.find(missing + ": no such file"), std::string::npos) << train.output;
  EXPECT_FALSE(fs::exists(path("m.pt")));
  // --version reports the module's absence instead of LibTorch's version, and exits 0.
  const Result version = run_after(env, "--version");
  EXPECT_EQ(version.exit_code, 0) << version.output;
  EXPECT_NE(version.output.find("could not be loaded"), std::string::npos) << version.output;
}

}  // namespace
}  // namespace eitbench
