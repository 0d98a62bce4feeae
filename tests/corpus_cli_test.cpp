// Issue 8: every file of the bad-input corpus, through the command-line tool. Each must end in a
// message that names the file, exit status 2, no crash, and no output file.
#include <gtest/gtest.h>

#include "cli_fixture.h"

namespace eitbench {
namespace {

class BadInputCorpus : public Cli {
 protected:
  // Every file of one corpus folder through each command (FILE stands for the file).
  int check(const std::string& folder, const std::vector<std::string>& commands) {
    int checked = 0;
    for (const auto& entry : fs::directory_iterator(kCorpus + "/" + folder)) {
      const std::string file = entry.path().string();
      for (std::string command : commands) {
        command.replace(command.find("FILE"), 4, file);
        const Result r = run(command);
        EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.output;
        EXPECT_NE(r.output.find(file), std::string::npos) << "names the file: " << r.output;
        EXPECT_EQ(r.output.find("terminate"), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(path("out.h5")) || fs::exists(path("out.pt"))) << command;
        ++checked;
      }
    }
    return checked;
  }
  std::string good_data() {
    const Result r =
        run("simulate --preset tiny --density coarse --quiet --out " + path("good.h5"));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return path("good.h5");
  }
};

TEST_F(BadInputCorpus, EveryBadDataSetIsRejected) {
  const std::string out = " --out " + path("out.h5");
  EXPECT_GE(check("datasets", {"info FILE", "reconstruct --method noser --data FILE" + out,
                               "train --data FILE --epochs 1 --quiet --out " + path("out.pt")}),
            17 * 3);
}

TEST_F(BadInputCorpus, EveryBadModelIsRejected) {
  const std::string data = good_data();
  EXPECT_GE(check("models", {"reconstruct --method dnn --model FILE --data " + data + " --out " +
                             path("out.h5")}),
            3);
}

TEST_F(BadInputCorpus, EveryBadCheckpointIsRejected) {
  // The model corpus, and a model file, in the place of a training checkpoint.
  const std::string data = good_data();
  ASSERT_EQ(run("train --data " + data + " --steps 1 --quiet --out " + path("m.pt")).exit_code, 0);
  std::vector<std::string> bad{path("m.pt")};
  for (const auto& entry : fs::directory_iterator(kCorpus + "/models")) bad.push_back(entry.path());
  for (const std::string& file : bad) {
    const std::string checkpoint = path("out.pt.checkpoint");
    fs::copy_file(file, checkpoint, fs::copy_options::overwrite_existing);
    const Result r =
        run("train --data " + data + " --steps 2 --quiet --resume --out " + path("out.pt"));
    EXPECT_EQ(r.exit_code, 2) << file << "\n" << r.output;
    EXPECT_NE(r.output.find(checkpoint), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(path("out.pt")));
  }
}

TEST_F(BadInputCorpus, EveryBadResultsFileIsRejected) {
  const std::string good = kCorpus + "/../data/results_tiny.json";
  const std::string history = " --commit c1 --history " + path("h.jsonl");
  EXPECT_GE(check("results", {"compare FILE " + good, "compare " + good + " FILE",
                              "history add FILE" + history}),
            6 * 3);
  EXPECT_FALSE(fs::exists(path("h.jsonl")));
}

TEST_F(BadInputCorpus, EveryBadMicrobenchmarkFileIsRejected) {
  const std::string good = kCorpus + "/../data/microbench_good.json";
  ASSERT_EQ(run("compare " + good + " " + good).exit_code, 0);
  const std::string history = " --commit c1 --history " + path("h.jsonl");
  EXPECT_GE(check("microbench", {"compare FILE " + good, "compare " + good + " FILE",
                                 "history add FILE" + history}),
            6 * 3);
  EXPECT_FALSE(fs::exists(path("h.jsonl")));
}

}  // namespace
}  // namespace eitbench
