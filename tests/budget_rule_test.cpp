// The budget rule (docs/learned.md#the-budget): its decision, and training under it on the tiny
// set: a budget too short for a model that keeps improving is doubled, and doubled again while
// the doubling pays; one that early stopping ended with rate left is not doubled; a doubling that
// does not pay ends the training.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "eitbench/bench/data/training_data.h"
#include "eitbench/bench/methods/budget_rule.h"
#include "eitbench/bench/methods/training_run.h"
#include "learned_support.h"
#include "test_support.h"

namespace eitbench {
namespace {

using testing::test_network;
using testing::tiny;

TEST(BudgetRule, DoublesAgainOnlyWhileTheLastDoublingPaid) {
  const BudgetRule rule{3, 0.01};
  EXPECT_TRUE(double_again(rule, 1.0, 0.98, 1));    // 2 % better: again
  EXPECT_FALSE(double_again(rule, 1.0, 0.995, 1));  // 0.5 %: no
  EXPECT_FALSE(double_again(rule, 1.0, 1.2, 1));    // worse: no
  EXPECT_FALSE(double_again(rule, 1.0, 0.5, 3));    // the cap
  EXPECT_FALSE(double_again(rule, INFINITY, 0.5, 1));
  EXPECT_FALSE(double_again(rule, 1.0, NAN, 1));
  EXPECT_FALSE(double_again(BudgetRule{}, 1.0, 0.5, 0));  // no doubling allowed
  EXPECT_TRUE(doubling_paid(rule, 1.0, 0.5));             // past the cap: it still paid (cap)
  EXPECT_FALSE(doubling_paid(rule, 1.0, 0.995));          // it did not (rule)
  EXPECT_FALSE(doubling_paid(rule, 1.0, NAN));
  EXPECT_TRUE(converged(TrainingEnd::rule));
  EXPECT_TRUE(converged(TrainingEnd::early_stopping));
  EXPECT_FALSE(converged(TrainingEnd::cap));
  EXPECT_FALSE(converged(TrainingEnd::budget));
  EXPECT_FALSE(converged(TrainingEnd::floor));
  for (TrainingEnd e : {TrainingEnd::early_stopping, TrainingEnd::floor, TrainingEnd::budget,
                        TrainingEnd::rule, TrainingEnd::cap})
    EXPECT_EQ(parse_training_end(to_string(e)), e);
  EXPECT_EQ(testing::input_error_at([] {
              BudgetRule{-1, 0.01}.validate();
            }),
            "BudgetRule.max_doublings");
  EXPECT_EQ(testing::input_error_at([] { BudgetRule{1, 1.0}.validate(); }), "BudgetRule.tolerance");
}

// Rate left: the rate at the stop above the floor by a tenth of the cosine's range or more. The
// cosine from the peak 1 (after a 20-step warm-up) to the floor 0.01 at step 600 of 1,000 is
// 0.01 + 0.99 (1 + cos(pi t)) / 2, a tenth of the range above the floor where (1 + cos(pi t)) / 2
// = 0.1, t = 0.795: step 20 + 0.795 x 580 = 481. A stop there or later, in the cosine's last
// fifth, may be the schedule's.
TEST(BudgetRule, RateLeftMeansATenthOfTheRangeOrMore) {
  const LearningRateSchedule cosine(1.0, 1000, ScheduleOptions{});
  const double t = std::acos(2 * 0.1 - 1) / M_PI;
  const long long edge = 20 + static_cast<long long>(std::floor(t * 580));
  EXPECT_NEAR(static_cast<double>(edge), 481, 1);
  EXPECT_TRUE(stopped_with_rate_left(cosine, 100));
  EXPECT_TRUE(stopped_with_rate_left(cosine, edge - 1));
  EXPECT_FALSE(stopped_with_rate_left(cosine, edge + 2));
  EXPECT_FALSE(stopped_with_rate_left(cosine, 560));  // 2.1 x the floor: rate left at 1/99
  EXPECT_FALSE(stopped_with_rate_left(cosine, 599));
  EXPECT_FALSE(stopped_with_rate_left(cosine, 600));
  EXPECT_FALSE(stopped_with_rate_left(cosine, 900));
  // The edge is a share of the cosine's range, whatever the floor: at a floor of 0 a stop one
  // step before it has no rate left (twice 0 is no edge), at half the peak a stop near the peak
  // has (twice the floor would be the peak itself).
  ScheduleOptions zero, half;
  zero.final_fraction = 0;
  half.final_fraction = 0.5;
  EXPECT_FALSE(stopped_with_rate_left(LearningRateSchedule(1.0, 1000, zero), 599));
  EXPECT_TRUE(stopped_with_rate_left(LearningRateSchedule(1.0, 1000, zero), edge - 1));
  EXPECT_TRUE(stopped_with_rate_left(LearningRateSchedule(1.0, 1000, half), 100));
  EXPECT_FALSE(stopped_with_rate_left(LearningRateSchedule(1.0, 1000, half), 599));
  // Without decay every step before the end has the whole rate left.
  ScheduleOptions flat;
  flat.kind = ScheduleKind::constant;
  const LearningRateSchedule constant(1.0, 1000, flat);
  EXPECT_TRUE(stopped_with_rate_left(constant, 599));
}

// A model trained when the edge lay at twice the floor is kept unless early stopping ended its
// first stage between that edge and today's: such a stop counts as the schedule's now, and the
// rule doubles it (or, with no doubling allowed, calls it "floor"). At a budget of 1,000 steps
// the edges lie at steps 481 and 562 (RateLeftMeansATenthOfTheRangeOrMore).
TEST(BudgetRule, AnEarlierEdgesModelIsKeptWhereTheRuleDecidesAlike) {
  TrainingOptions o;
  o.learning_rate = 1.0;
  LearnedModel model(test_network(), 16, 1);
  auto decided = [&](const std::string& end, long long stop, int doublings) {
    TrainingRecord last;
    last.round = 1, last.steps = stop;
    model.info().training =
        nlohmann::json{{"end", end},
                       {"doublings", doublings},
                       {"budget_steps", 1000 << doublings},
                       {"history", nlohmann::json::parse(history_to_json({last}))}}
            .dump();
    return decided_as_now(model, o);
  };
  EXPECT_TRUE(decided("early stopping", 300, 0));   // rate left under either edge
  EXPECT_FALSE(decided("early stopping", 520, 0));  // between the edges: doubled now
  EXPECT_FALSE(decided("early stopping", 560, 0));
  EXPECT_TRUE(decided("floor", 590, 0));  // no rate left under either
  EXPECT_TRUE(decided("budget", 1000, 0));
  EXPECT_TRUE(decided("cap", 7500, 3));  // the first stage was doubled: still is
  EXPECT_TRUE(decided("rule", 3800, 2));
  EXPECT_FALSE(decided("early stopping", 300, 1));  // early stopping after a doubling: no rule's
  model.info().training = "{\"end\": \"early stopping\"}";
  EXPECT_FALSE(decided_as_now(model, o));  // a record without the rule's fields: trained again
  o.schedule.decay_fraction = 0.9;  // the run's schedule decides: its cosine ends at step 900
  EXPECT_TRUE(decided("early stopping", 520, 0));
}

class BudgetRuleTraining : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("eitbench_budget_rule_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  TrainingRun run(int doublings) const {
    TrainingRun r;
    r.out = (dir_ / "model.pt").string();
    r.quiet = true;
    r.curves = false;
    r.rule = {doublings, 0.01};
    return r;
  }
  std::filesystem::path dir_;
};

TEST_F(BudgetRuleTraining, ABudgetTooShortIsDoubledWhileItPays) {
  // Validated on its own training frames at a constant rate: every step helps, so 6 steps are
  // far too few, and each doubling lowers the best validation loss by far more than 1 %.
  const LabelledFrames train = labelled_frames(tiny(), Split::train);
  TrainingOptions o;
  o.steps = 6;
  o.batch_size = 16;
  o.validate_every = 32;
  o.learning_rate = 3e-3;
  o.schedule.kind = ScheduleKind::constant;
  const TrainingResult r =
      train_and_save(test_network(), o, train, train, sensor_of(tiny()), run(2));
  EXPECT_EQ(r.doublings, 2);
  EXPECT_EQ(r.end, TrainingEnd::cap);  // the cap ended it: budget-bound, not converged
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.total_steps, 24);  // 6, doubled to 12, then to 24
  EXPECT_EQ(r.history.back().steps, 24);
  ASSERT_EQ(r.stage_best.size(), 3u);
  EXPECT_LT(r.stage_best[1], 0.99 * r.stage_best[0]);
  EXPECT_LT(r.stage_best[2], 0.99 * r.stage_best[1]);
  // The model file records it, and no stage file is left behind.
  EXPECT_NE(r.model.info().training.find("\"end\":\"cap\""), std::string::npos);
  EXPECT_NE(r.model.info().training.find("\"doublings\":2"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "model.pt.stage"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "model.pt.stage.json"));
  EXPECT_TRUE(std::filesystem::exists(dir_ / "model.pt"));
}

TEST_F(BudgetRuleTraining, ABudgetThatSufficesIsNotDoubled) {
  // Validation labels that training moves away from (all zero, as in the early-stopping test): the
  // best validation loss comes in the first rounds, and early stopping ends the training long
  // before the cosine reaches its floor, with rate left to move the model: the budget sufficed.
  const LabelledFrames validation = testing::zero_label_validation();
  TrainingOptions o;
  o.steps = 400;
  o.batch_size = 16;
  o.validate_every = 32;
  o.patience = 4;
  const TrainingResult r = train_and_save(test_network(), o, labelled_frames(tiny(), Split::train),
                                          validation, sensor_of(tiny()), run(3));
  EXPECT_EQ(r.doublings, 0);
  EXPECT_EQ(r.end, TrainingEnd::early_stopping);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.total_steps, 400);
  ASSERT_FALSE(r.history.empty());
  EXPECT_LT(r.history.back().steps, 240);  // before the floor, at 60 % of the budget
  EXPECT_EQ(r.stage_best.size(), 1u);
  // The same stop after the cosine reached its floor (1 % of the budget, 4 steps): the schedule may
  // have ended it. Alone it is not counted as converged; under the rule it is doubled to find out.
  o.schedule.warmup_fraction = 0, o.schedule.decay_fraction = 0.01;
  const TrainingResult alone =
      train_and_save(test_network(), o, labelled_frames(tiny(), Split::train), validation,
                     sensor_of(tiny()), run(0));
  EXPECT_EQ(alone.end, TrainingEnd::floor);
  EXPECT_FALSE(alone.converged);
  ASSERT_FALSE(alone.history.empty());
  EXPECT_GE(alone.history.back().steps, 4);
  EXPECT_LT(alone.history.back().steps, 400);
  const TrainingResult doubled =
      train_and_save(test_network(), o, labelled_frames(tiny(), Split::train), validation,
                     sensor_of(tiny()), run(1));
  EXPECT_EQ(doubled.doublings, 1);
}

TEST_F(BudgetRuleTraining, ADoublingThatDoesNotPayEndsTheTraining) {
  // A rate too small to move the weights: the budget ends the first stage (no early stopping),
  // so it is doubled once, and that doubling changes the best validation loss by far less than
  // 1 %: the rule ends the training, which counts as converged.
  const LabelledFrames train = labelled_frames(tiny(), Split::train);
  TrainingOptions o;
  o.steps = 40;
  o.batch_size = 16;
  o.validate_every = 160;
  o.patience = 100;
  o.learning_rate = 1e-9;
  o.schedule.kind = ScheduleKind::constant;
  const TrainingResult r =
      train_and_save(test_network(), o, train, train, sensor_of(tiny()), run(3));
  EXPECT_EQ(r.doublings, 1);
  EXPECT_EQ(r.end, TrainingEnd::rule);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.total_steps, 80);
  ASSERT_EQ(r.stage_best.size(), 2u);
  EXPECT_GE(r.stage_best[1], 0.99 * r.stage_best[0]);
  EXPECT_NE(r.model.info().training.find("\"end\":\"rule\""), std::string::npos);
}

}  // namespace
}  // namespace eitbench
