// What the learned reconstructor's const and getter methods must not change: LibTorch's
// process-wide random generator, and the model's evaluation mode. This file includes LibTorch
// (30 s to compile) to look at both.
#include <gtest/gtest.h>
#include <torch/torch.h>

#include "eitbench/bench/data/training_data.h"
#include "eitbench/learned.h"
#include "learned_support.h"

namespace eitbench {
namespace {

using testing::test_network;  // dropout 0.1: a model left in training mode reconstructs at random
using testing::tiny;

// Trainer::best_model() makes a model, which seeds LibTorch's generator for its initial weights:
// the process's generator must come out as it went in.
TEST(LearnedState, MakingAModelLeavesTheGlobalGeneratorAlone) {
  TrainingOptions o;
  o.steps = 2;
  o.batch_size = 16;
  Trainer trainer(test_network(), o, labelled_frames(tiny(), Split::train),
                  labelled_frames(tiny(), Split::validation), sensor_of(tiny()));
  trainer.run_round();
  torch::manual_seed(123);
  const torch::Tensor expected = torch::rand({8});
  torch::manual_seed(123);
  const LearnedModel model = trainer.best_model();
  const LearnedModel fresh(test_network(), 16, 7);
  EXPECT_TRUE(torch::equal(torch::rand({8}), expected));
  // And a fresh model's weights are still a function of its seed.
  const SampleMatrix frames = labelled_frames(tiny(), Split::validation).frames;
  EXPECT_EQ(LearnedModel(test_network(), 16, 7).reconstruct(frames), fresh.reconstruct(frames));
}

// With dropout in the network, a model in training mode gives a different image on every call:
// every way of making a model leaves it in evaluation mode, so reconstruct (const) need not set it.
TEST(LearnedState, ModelsReconstructInEvaluationMode) {
  const SampleMatrix frames = labelled_frames(tiny(), Split::validation).frames.topRows(4);
  const LearnedModel fresh(test_network(), 16, 3);
  const LearnedModel copy = fresh;
  const LearnedModel loaded = LearnedModel::from_bytes(fresh.to_bytes(), "mem");
  for (const LearnedModel* m : {&fresh, &copy, &loaded})
    EXPECT_EQ(m->reconstruct(frames), m->reconstruct(frames));
  EXPECT_EQ(copy.reconstruct(frames), fresh.reconstruct(frames));
  EXPECT_EQ(loaded.reconstruct(frames), fresh.reconstruct(frames));
}

}  // namespace
}  // namespace eitbench
