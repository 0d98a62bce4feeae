// Convergence by design: the learning-rate schedule's shape, early stopping that keeps the best
// weights, and a run the budget cut short reported as not converged.
#include <gtest/gtest.h>

#include <cmath>

#include "eitbench/bench/data/training_data.h"
#include "eitbench/jacobian/error.h"
#include "eitbench/learned.h"
#include "learned_support.h"
#include "test_support.h"

namespace eitbench {
namespace {

using testing::test_network;
using testing::tiny;

TEST(Schedule, WarmUpThenHalfCosineToTheFloor) {
  ScheduleOptions o;
  o.warmup_fraction = 0.1;
  o.decay_fraction = 1;  // the cosine over the whole budget
  o.final_fraction = 0.01;
  const double peak = 2e-3;
  const long long total = 1001;
  const LearningRateSchedule s(peak, total, o);
  ASSERT_EQ(s.warmup_steps(), 100);
  // Linear warm-up: equal increments from peak / 101 up to the peak.
  EXPECT_NEAR(s.rate(0), peak / 101, 1e-15);
  for (long long k = 1; k < 100; ++k) EXPECT_NEAR(s.rate(k) - s.rate(k - 1), peak / 101, 1e-15);
  EXPECT_DOUBLE_EQ(s.rate(100), peak);
  // The cosine: non-increasing, halfway between peak and floor at its middle, the floor at the end.
  const double floor = 0.01 * peak;
  for (long long k = 101; k < total; ++k) EXPECT_LE(s.rate(k), s.rate(k - 1));
  EXPECT_NEAR(s.rate(100 + 450), (peak + floor) / 2, 1e-15);
  EXPECT_NEAR(s.rate(total - 1), floor, 1e-15);
  EXPECT_NEAR(s.rate(100 + 225), floor + (peak - floor) * (1 + std::cos(M_PI / 4)) / 2, 1e-15);
  EXPECT_EQ(s.rate(5 * total), s.rate(total - 1));  // past the budget: the last rate

  // The cosine over 60 % of the budget, then the floor.
  o.decay_fraction = 0.6;
  const LearningRateSchedule d(peak, total, o);
  ASSERT_EQ(d.decay_steps(), 601);
  EXPECT_NEAR(d.rate(100 + 250), floor + (peak - floor) * (1 + std::cos(M_PI * 250 / 501)) / 2,
              1e-15);  // the cosine spans the 501 steps from the peak to the floor
  for (long long k = 101; k < 601; ++k) EXPECT_LT(d.rate(k), d.rate(k - 1));
  EXPECT_NEAR(d.rate(600), floor, 2e-3 * floor);  // continuous into the floor
  for (long long k = 601; k < total; ++k) EXPECT_EQ(d.rate(k), floor);

  o.kind = ScheduleKind::constant;
  const LearningRateSchedule c(peak, total, o);
  for (long long k : {0LL, 50LL, 500LL, total - 1}) EXPECT_EQ(c.rate(k), peak);

  EXPECT_THROW(LearningRateSchedule(0, total, {}), InputError);
  EXPECT_THROW(LearningRateSchedule(peak, 0, {}), InputError);
  ScheduleOptions bad;
  bad.warmup_fraction = 1.5;
  EXPECT_THROW(LearningRateSchedule(peak, total, bad), InputError);
  bad.warmup_fraction = 0.5;
  bad.decay_fraction = 0.4;  // the warm-up would outlast the decay
  EXPECT_THROW(LearningRateSchedule(peak, total, bad), InputError);
  EXPECT_THROW(parse_schedule("linear"), InputError);
}

// Every options struct of training validates every field in one place and names the field at
// fault, not a command-line flag (the command line maps the fields back to its flags).
TEST(TrainingOptions, ValidateNamesTheField) {
  using testing::input_error_at;
  auto at = [](const auto& options) { return input_error_at([&] { options.validate(); }); };
  EXPECT_EQ(at(TrainingOptions{}), "no InputError");
  EXPECT_EQ(at(ScheduleOptions{}), "no InputError");
  EXPECT_EQ(at(NetworkOptions{}), "no InputError");
  const std::pair<void (*)(TrainingOptions&), std::string> cases[] = {
      {[](TrainingOptions& o) { o.epochs = -1; }, "TrainingOptions.epochs"},
      {[](TrainingOptions& o) { o.steps = -1; }, "TrainingOptions.steps"},
      {[](TrainingOptions& o) { o.epochs = 2, o.steps = 10; }, "TrainingOptions.steps"},
      {[](TrainingOptions& o) { o.batch_size = 1; }, "TrainingOptions.batch_size"},
      {[](TrainingOptions& o) { o.learning_rate = 0; }, "TrainingOptions.learning_rate"},
      {[](TrainingOptions& o) { o.validate_every = 0; }, "TrainingOptions.validate_every"},
      {[](TrainingOptions& o) { o.patience = -1; }, "TrainingOptions.patience"},
      {[](TrainingOptions& o) { o.min_improvement = 1; }, "TrainingOptions.min_improvement"},
      {[](TrainingOptions& o) { o.device = "tpu"; }, "TrainingOptions.device"},
      // The schedule is validated with them, under its own name.
      {[](TrainingOptions& o) { o.schedule.final_fraction = 2; }, "ScheduleOptions.final_fraction"},
      {[](TrainingOptions& o) { o.schedule.warmup_fraction = 0.7; },
       "ScheduleOptions.warmup_fraction"},  // past the decay at 0.6
  };
  for (const auto& [spoil, where] : cases) {
    TrainingOptions o;
    spoil(o);
    EXPECT_EQ(at(o), where);
  }
  ScheduleOptions s;
  s.decay_fraction = -0.1;
  EXPECT_EQ(at(s), "ScheduleOptions.decay_fraction");
  NetworkOptions n;
  n.dropout = 1;
  EXPECT_EQ(at(n), "NetworkOptions.dropout");
  n = {};
  n.latent_size = 4;  // 4 * 2^3 != 64
  EXPECT_EQ(at(n), "NetworkOptions.image_size");
}

// The trainer validates its options before it looks at the data.
TEST(TrainingOptions, TheTrainerValidatesThem) {
  TrainingOptions o;
  o.batch_size = 0;
  EXPECT_EQ(testing::input_error_at([&] {
              Trainer(test_network(), o, LabelledFrames{}, LabelledFrames{}, AugmentSetup{});
            }),
            "TrainingOptions.batch_size");
}

TEST(Schedule, TheTrainerFollowsIt) {
  TrainingOptions o;
  o.steps = 12;
  o.batch_size = 16;
  o.validate_every = 16;  // a validation after every step: its rate is recorded
  o.schedule.warmup_fraction = 0.25;
  Trainer t(test_network(), o, labelled_frames(tiny(), Split::train),
            labelled_frames(tiny(), Split::validation), sensor_of(tiny()));
  while (!t.done()) t.run_round();
  ASSERT_EQ(t.history().size(), 12u);
  for (std::size_t k = 0; k < 12; ++k)
    EXPECT_DOUBLE_EQ(t.history()[k].learning_rate, t.schedule().rate(static_cast<long long>(k)));
}

// Validation labels that training moves away from: every image the network learns to draw for the
// training frames is wrong for the validation set (all zero), so validation loss grows from the
// first rounds on. Early stopping must end the run and keep the round with the least loss.
TEST(EarlyStopping, StopsOnAPlateauAndRestoresTheBestWeights) {
  const LabelledFrames train = labelled_frames(tiny(), Split::train);
  const LabelledFrames validation = testing::zero_label_validation();
  TrainingOptions o;
  o.steps = 400;
  o.batch_size = 16;
  o.validate_every = 32;  // 2 steps a round
  o.patience = 4;
  o.learning_rate = 1e-2;
  Trainer t(test_network(), o, train, validation, sensor_of(tiny()));
  while (!t.done()) t.run_round();
  ASSERT_TRUE(t.converged());
  const auto& h = t.history();
  EXPECT_LT(h.back().steps, 400);  // stopped before the budget
  const int best = t.best_round();
  ASSERT_GE(best, 1);
  EXPECT_LT(best, static_cast<int>(h.size()));
  for (const auto& r : h) EXPECT_GE(r.validation_loss, h[best - 1].validation_loss);
  EXPECT_GT(h.back().validation_loss, h[best - 1].validation_loss);
  // The model kept is the best round's: its validation MSE is that round's, not the last one's.
  const SampleMatrix out = t.best_model().reconstruct(validation.frames);
  const double kept = out.squaredNorm() / double(out.size());
  EXPECT_NEAR(kept, h[best - 1].validation_loss, 1e-5 * h[best - 1].validation_loss);
  // Patience counts rounds since the last improvement.
  EXPECT_EQ(static_cast<int>(h.size()), best + o.patience);
  EXPECT_NE(t.best_model().info().training.find("\"converged\":true"), std::string::npos);
}

// The same run told to wait for the floor (a doubling's stage): it does not stop in the cosine,
// then stops at the first validation past the floor, its patience long spent.
TEST(EarlyStopping, PatienceAfterDecayWaitsForTheFloor) {
  TrainingOptions o;
  o.steps = 400;
  o.batch_size = 16;
  o.validate_every = 32;  // 2 steps a round
  o.patience = 4;
  o.patience_after_decay = true;
  Trainer t(test_network(), o, labelled_frames(tiny(), Split::train),
            testing::zero_label_validation(), sensor_of(tiny()));
  while (!t.done()) t.run_round();
  ASSERT_TRUE(t.converged());
  const long long floor = t.schedule().decay_steps();
  EXPECT_EQ(floor, 240);
  const auto& h = t.history();
  EXPECT_GE(h.back().steps, floor);
  EXPECT_LT(h.back().steps, floor + 2);  // the first round at or past it
  EXPECT_LT(t.best_round() + o.patience, static_cast<int>(h.size()));  // patience long spent
}

TEST(EarlyStopping, ARunTheBudgetEndsIsNotConverged) {
  TrainingOptions o;
  o.steps = 6;
  o.batch_size = 16;
  o.validate_every = 32;
  o.patience = 50;
  Trainer t(test_network(), o, labelled_frames(tiny(), Split::train),
            labelled_frames(tiny(), Split::validation), sensor_of(tiny()));
  while (!t.done()) t.run_round();
  EXPECT_FALSE(t.converged());
  EXPECT_EQ(t.history().back().steps, 6);
  EXPECT_NE(t.best_model().info().training.find("\"converged\":false"), std::string::npos);
  // Without patience a run always goes to its budget.
  o.patience = 0;
  Trainer none(test_network(), o, labelled_frames(tiny(), Split::train),
               labelled_frames(tiny(), Split::validation), sensor_of(tiny()));
  while (!none.done()) none.run_round();
  EXPECT_FALSE(none.converged());
}

}  // namespace
}  // namespace eitbench
