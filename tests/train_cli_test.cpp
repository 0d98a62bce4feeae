// eitbench train and reconstruct --method dnn as users meet them: outputs, a run killed with
// SIGKILL and resumed, and the bad inputs of issue 6.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <thread>

#include "cli_fixture.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/simulate.h"
#include "eitbench/bench/methods/model_file.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

// Two epochs of the tiny set's 60 samples (4 steps each), a validation after each.
const std::string kTrain = " --epochs 2 --batch 16 --validate-every 64 --quiet";

class TrainCli : public Cli {
 protected:
  // The tiny preset on the coarse mesh (60 training samples), simulated once per test.
  std::string data(int electrodes = 16) {
    const std::string file = path("d" + std::to_string(electrodes) + ".h5");
    if (!fs::exists(file)) {
      const Result r = run("simulate --preset tiny --density coarse --quiet --electrodes " +
                           std::to_string(electrodes) + " --out " + file);
      EXPECT_EQ(r.exit_code, 0) << r.output;
    }
    return file;
  }

  // A training of three stages (two doublings) into whole.pt, and the same into cut.pt killed
  // once its first stage's record is written; returns the arguments before --out's path.
  std::string doubling_run_killed_after_its_first_stage() {
    const std::string args =
        "train --data " + data() + " --augment rotations --epochs 6 --batch 8 " +
        "--validate-every 64 --patience 0 --doublings 2 --doubling-tolerance 0 --quiet --out ";
    EXPECT_EQ(run(args + path("whole.pt")).exit_code, 0);
    EXPECT_TRUE(kill_when(args + path("cut.pt"), [&] {
      return fs::exists(path("cut.pt.stage.json"));
    })) << "no stage record appeared";
    return args;
  }
};

TEST_F(TrainCli, TrainsAndReconstructs) {
  const Result r =
      run("train --data " + data() + " --augment d16" + kTrain + " --out " + path("m.pt"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(path("m.pt")));
  EXPECT_TRUE(fs::exists(path("m_loss.csv")));
  EXPECT_TRUE(fs::exists(path("m_loss.png")));
  EXPECT_FALSE(fs::exists(path("m.pt.checkpoint"))) << "a finished run leaves no checkpoint";
  std::ifstream csv(path("m_loss.csv"));
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header,
            "run,round,epoch,steps,samples,train_loss,validation_loss,learning_rate,seconds,"
            "samples_per_second");
  int rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    EXPECT_EQ(line.rfind("d16,", 0), 0u) << line;
  }
  EXPECT_EQ(rows, 2);
  const LearnedModel model = read_model_file(path("m.pt"));
  EXPECT_EQ(model.info().augment, "d16");

  const Result rec = run("reconstruct --method dnn --model " + path("m.pt") + " --data " + data() +
                         " --png 1 --out " + path("images.h5"));
  ASSERT_EQ(rec.exit_code, 0) << rec.output;
  EXPECT_NE(rec.output.find("CC "), std::string::npos) << rec.output;
  EXPECT_TRUE(fs::exists(path("images.h5")));
  EXPECT_TRUE(fs::exists(path("images_0.png")));
}

TEST_F(TrainCli, KilledRunResumesToTheUninterruptedResult) {
  const std::string args =
      "train --data " + data() + " --augment rotations --epochs 30 --batch 8 " +
      "--validate-every 64 --patience 0 --quiet --out ";  // a round an epoch, all 30 of them
  ASSERT_EQ(run(args + path("whole.pt")).exit_code, 0);

  // The same run in the background, killed with SIGKILL after its second checkpoint.
  const std::string checkpoint = path("cut.pt.checkpoint");
  fs::file_time_type first{};
  ASSERT_TRUE(kill_when(args + path("cut.pt"), [&] {
    std::error_code error;
    const auto t = fs::last_write_time(checkpoint, error);
    if (!error && first == fs::file_time_type{}) first = t;
    return !error && t != first;
  })) << "no second checkpoint appeared";
  ASSERT_FALSE(fs::exists(path("cut.pt"))) << "the run finished before it was killed";
  for (const auto& entry : fs::directory_iterator(dir_))  // no temporary left but the checkpoint's
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();

  const Result resumed = run(args + path("cut.pt") + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  const LearnedModel a = read_model_file(path("whole.pt")), b = read_model_file(path("cut.pt"));
  const SampleMatrix frames = read_dataset(data()).differences;
  EXPECT_EQ(a.reconstruct(frames), b.reconstruct(frames));
  // The same losses round by round (the CSV's columns up to validation_loss; times differ).
  auto losses = [&](const std::string& csv_path) {
    std::ifstream in(csv_path);
    std::vector<std::string> rows;
    for (std::string line; std::getline(in, line);) {
      std::size_t comma = 0;
      for (int k = 0; k < 7; ++k) comma = line.find(',', comma + 1);
      rows.push_back(line.substr(0, comma));
    }
    return rows;
  };
  EXPECT_EQ(losses(path("whole_loss.csv")), losses(path("cut_loss.csv")));
  EXPECT_EQ(losses(path("whole_loss.csv")).size(), 31u);
}

// The budget rule's stages (budget_rule.h): a run killed after its first stage resumes from the
// stage record to the model and curves an uninterrupted run gives.
TEST_F(TrainCli, KilledBetweenStagesResumesToTheUninterruptedResult) {
  const std::string args = doubling_run_killed_after_its_first_stage();
  ASSERT_FALSE(fs::exists(path("cut.pt"))) << "the run finished before it was killed";
  const Result resumed = run(args + path("cut.pt") + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  const LearnedModel a = read_model_file(path("whole.pt")), b = read_model_file(path("cut.pt"));
  EXPECT_NE(a.info().training.find("\"doublings\":"), std::string::npos);
  const SampleMatrix frames = read_dataset(data()).differences;
  EXPECT_EQ(a.reconstruct(frames), b.reconstruct(frames));
  EXPECT_FALSE(fs::exists(path("cut.pt.stage")));
  EXPECT_FALSE(fs::exists(path("cut.pt.stage.json")));
}

// A training started afresh onto a model path where another training left its stage record
// does not inherit it: killed in its first stage and resumed, it ends as the uninterrupted run.
TEST_F(TrainCli, AFreshTrainingDropsAnEarlierOnesStages) {
  const std::string args = doubling_run_killed_after_its_first_stage();
  // Afresh (no --resume), killed in its first stage: after its first checkpoint, before its own
  // stage record. An earlier stage record left in place never lets this happen.
  ASSERT_TRUE(kill_when(args + path("cut.pt"), [&] {
    return fs::exists(path("cut.pt.checkpoint")) && !fs::exists(path("cut.pt.stage.json"));
  })) << "the earlier training's stage record was kept";
  ASSERT_FALSE(fs::exists(path("cut.pt")));
  const Result resumed = run(args + path("cut.pt") + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  const SampleMatrix frames = read_dataset(data()).differences;
  EXPECT_EQ(read_model_file(path("whole.pt")).reconstruct(frames),
            read_model_file(path("cut.pt")).reconstruct(frames));
}

TEST_F(TrainCli, BadInputsFailWithAMessageAndNoOutput) {
  ASSERT_EQ(run("train --data " + data() + kTrain + " --out " + path("m.pt")).exit_code, 0);
  ASSERT_EQ(run("train --data " + data(8) + kTrain + " --out " + path("m8.pt")).exit_code, 0);
  {
    std::ofstream bad(path("garbage.pt"));
    bad << "not a model";
  }
  const std::string bytes = read_file_bytes(path("m.pt"));
  {
    std::ofstream cut(path("truncated.pt"), std::ios::binary);
    cut.write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  }
  { std::ofstream empty(path("empty.pt")); }
  // An unlabelled set (measured frames) and a labelled one without a validation split.
  Dataset unlabelled = read_dataset(data());
  unlabelled.labels.resize(unlabelled.size(), 0);
  unlabelled.circles.clear();
  unlabelled.preset = "imported";
  write_dataset(path("unlabelled.h5"), unlabelled);
  Dataset no_validation = read_dataset(data());
  for (auto& s : no_validation.split)
    if (s == Split::validation) s = Split::test;
  write_dataset(path("novalidation.h5"), no_validation);

  const std::string rec =
      "reconstruct --method dnn --data " + data() + " --out " + path("out.h5") + " --model ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {rec + path("missing.pt"), "missing.pt"},
      {rec + path("garbage.pt"), "garbage.pt"},
      {rec + path("truncated.pt"), "truncated.pt"},
      {rec + path("empty.pt"), "empty.pt"},
      {rec + path("m8.pt"), "electrodes"},
      {"reconstruct --method dnn --data " + data() + " --out " + path("out.h5"), "--model"},
      {"train --data " + path("unlabelled.h5") + kTrain + " --out " + path("out.pt"), "labels"},
      {"train --data " + path("novalidation.h5") + kTrain + " --out " + path("out.pt"),
       "validation"},
      {"train --data " + data() + kTrain + " --resume --out " + path("out.pt"), "checkpoint"},
      {"train --data " + data() + kTrain + " --device cuda --out " + path("out.pt"), "CUDA"},
  };
  for (const auto& [args, needle] : cases) {
    if (needle == "CUDA" && cuda_available()) continue;
    const Result r = run(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(needle), std::string::npos) << args << "\n" << r.output;
    EXPECT_EQ(r.output.find("terminate"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(path("out.h5")) || fs::exists(path("out.pt"))) << args;
  }
}

TEST(ModelFile, ImageSizeMustMatch) {
  NetworkOptions n;
  n.image_size = 32;
  n.latent_size = 4;
  const LearnedModel model(n, 16, 1);
  EXPECT_NO_THROW(check_model_fits(model, "m.pt", 16, 32));
  EXPECT_THROW(check_model_fits(model, "m.pt", 16, 64), InputError);
  EXPECT_THROW(check_model_fits(model, "m.pt", 8, 32), InputError);
}

}  // namespace
}  // namespace eitbench
