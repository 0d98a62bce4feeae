// The KTC benchmark's tuning: the segmentation rule's kind is chosen on samples it was not tuned
// on, so that the levels rule's two fractions more than Otsu do not win by fitting the tuning
// samples alone. Scores are made by hand, so each choice has a value worked out below.
#include <gtest/gtest.h>

#include <stdexcept>

#include "eitbench/bench/ktc/ktc_run.h"

namespace eitbench {
namespace {

// One candidate, one level, three samples. Under Otsu every sample scores 0.4. Under the levels
// rule sample s scores 1 at fraction index peak[s] (both classes) and `elsewhere` at every other.
KtcMethodResult made(const std::vector<int>& peak, double elsewhere) {
  const std::size_t F = ktc_level_fractions().size();
  KtcMethodResult r;
  r.method = "made";
  r.candidates = {0.1};
  r.levels = {1};
  r.samples = {1, 2, 3};
  r.scores.assign(1, std::vector<std::vector<KtcFrameScores>>(1));
  for (int p : peak) {
    KtcFrameScores f;
    f.otsu = 0.4;
    f.resistive.assign(F, elsewhere), f.conductive.assign(F, elsewhere);
    f.resistive[static_cast<std::size_t>(p)] = f.conductive[static_cast<std::size_t>(p)] = 1.0;
    r.scores[0][0].push_back(f);
  }
  return r;
}

// A frame scored `otsu` under Otsu and 0 under every levels rule.
KtcFrameScores otsu_frame(double otsu) {
  KtcFrameScores f;
  f.otsu = otsu;
  f.resistive.assign(ktc_level_fractions().size(), 0.0);
  f.conductive.assign(ktc_level_fractions().size(), 0.0);
  return f;
}

// Two weights at one noise model, one level; the samples and their scores are the test's.
KtcMethodResult two_weights() {
  KtcMethodResult r;
  r.method = "made";
  r.candidates = {0.1, 1.0};
  r.candidate_noise = {5e-3, 5e-3};
  r.levels = {1};
  return r;
}

TEST(KtcTuning, ALevelsRuleThatOnlyFitsItsTuningSamplesLosesToOtsu) {
  // Each sample's best fraction is its own: on all three the levels rule sums 1 + 0.3 + 0.3 = 1.6
  // against Otsu's 1.2, but tuned on two it picks one of theirs and scores 0.3 on the third.
  KtcMethodResult r = made({2, 9, 15}, 0.3);
  const std::vector<int> all = {0, 1, 2};
  EXPECT_EQ(tune_ktc(r, all, KtcRules::either).rule.kind, SegmentationKind::levels);
  const KtcChoice c = choose_ktc_rules(r, all);
  EXPECT_EQ(c.rule.kind, SegmentationKind::otsu);
  EXPECT_NEAR(c.nested_otsu, 1.2, 1e-12);
  EXPECT_NEAR(c.nested_levels, 0.9, 1e-12);
  // Held out: each sample with the setting tuned on the other two, whose own choice of kind
  // (one held-out sample each) is Otsu's 0.4 against the levels rule's 0.3.
  tune_and_hold_out(r);
  for (std::size_t s = 0; s < 3; ++s) {
    EXPECT_EQ(r.held_out_choice[s].rule.kind, SegmentationKind::otsu) << s;
    EXPECT_NEAR(r.held_out[0][s], 0.4, 1e-12) << s;
  }
  EXPECT_EQ(r.best.rule.kind, SegmentationKind::otsu);
}

TEST(KtcTuning, ALevelsRuleThatHoldsOutIsChosen) {
  // The same best fraction on every sample: held out the levels rule scores 1 a sample.
  KtcMethodResult r = made({7, 7, 7}, 0.3);
  const std::vector<int> all = {0, 1, 2};
  const KtcChoice c = choose_ktc_rules(r, all);
  EXPECT_EQ(c.rule.kind, SegmentationKind::levels);
  EXPECT_DOUBLE_EQ(c.rule.resistive, ktc_level_fractions()[7]);
  EXPECT_DOUBLE_EQ(c.rule.conductive, ktc_level_fractions()[7]);
  EXPECT_NEAR(c.nested_levels, 3.0, 1e-12);
  tune_and_hold_out(r);
  for (std::size_t s = 0; s < 3; ++s) EXPECT_NEAR(r.held_out[0][s], 1.0, 1e-12) << s;
  // With one sample nothing is held out within it: Otsu, which tunes nothing.
  EXPECT_EQ(choose_ktc_rules(r, {1}).rule.kind, SegmentationKind::otsu);
}

TEST(KtcTuning, TheNoiseModelIsTunedAsTheWeightIs) {
  // One weight at two noise models, Otsu only (the levels rule scores 0): the second model wins
  // on all three samples (1.7 against 1.5), but held out each sample takes the model the other
  // two prefer: sample 0 the first (1.0 against 0.8), samples 1 and 2 the second.
  const std::size_t F = ktc_level_fractions().size();
  KtcMethodResult r;
  r.method = "made";
  r.candidates = {0.1, 0.1};
  r.candidate_noise = {5e-4, 5e-2};
  r.levels = {1};
  r.samples = {1, 2, 3};
  const double otsu[2][3] = {{0.5, 0.5, 0.5}, {0.9, 0.2, 0.6}};
  r.scores.assign(2, std::vector<std::vector<KtcFrameScores>>(1));
  for (int c = 0; c < 2; ++c)
    for (int s = 0; s < 3; ++s) {
      KtcFrameScores f;
      f.otsu = otsu[c][s];
      f.resistive.assign(F, 0.0), f.conductive.assign(F, 0.0);
      r.scores[static_cast<std::size_t>(c)][0].push_back(f);
    }
  tune_and_hold_out(r);
  EXPECT_EQ(r.best.candidate, 1);
  EXPECT_DOUBLE_EQ(r.best.noise_relative, 5e-2);
  const double chosen[3] = {5e-4, 5e-2, 5e-2}, held_out[3] = {0.5, 0.2, 0.6};
  for (std::size_t s = 0; s < 3; ++s) {
    EXPECT_DOUBLE_EQ(r.held_out_choice[s].noise_relative, chosen[s]) << s;
    EXPECT_NEAR(r.held_out[0][s], held_out[s], 1e-12) << s;
  }
}

TEST(KtcTuning, TheSettingTunedOnSimulatedTanksScoresEverySample) {
  // Two weights, Otsu only (the levels rule scores 0). On the two samples the first weight wins
  // (0.9 and 0.8 against 0.5 and 0.4); on the three simulated tanks the second (0.7 each against
  // 0.2). Tuned on the tanks, every sample is scored with the second weight: 0.5 and 0.4, not
  // the samples' own best; the samples' tuning (best) is left as it was.
  KtcMethodResult r = two_weights();
  r.samples = {1, 2};
  r.scores = {{{otsu_frame(0.9), otsu_frame(0.8)}}, {{otsu_frame(0.5), otsu_frame(0.4)}}};
  tune_and_hold_out(r);
  tune_on_simulation(r);  // no tanks: nothing
  EXPECT_TRUE(r.tuned_on_simulation.empty());
  r.simulated = {{{otsu_frame(0.2), otsu_frame(0.2), otsu_frame(0.2)}},
                 {{otsu_frame(0.7), otsu_frame(0.7), otsu_frame(0.7)}}};
  tune_on_simulation(r);
  EXPECT_EQ(r.simulation_choice.candidate, 1);
  EXPECT_DOUBLE_EQ(r.simulation_choice.lambda, 1.0);
  EXPECT_EQ(r.simulation_choice.rule.kind, SegmentationKind::otsu);
  EXPECT_NEAR(r.simulation_choice.tuning_score, 2.1, 1e-12);
  ASSERT_EQ(r.tuned_on_simulation.size(), 1u);
  ASSERT_EQ(r.tuned_on_simulation[0].size(), 2u);
  EXPECT_NEAR(r.tuned_on_simulation[0][0], 0.5, 1e-12);
  EXPECT_NEAR(r.tuned_on_simulation[0][1], 0.4, 1e-12);
  EXPECT_EQ(r.best.candidate, 0);
}

TEST(KtcTuning, SamplesAndTanksTogetherWeighHalfEachAndHoldOutTheSample) {
  // Two weights, Otsu only (the levels rule scores 0). The three samples prefer the first weight,
  // the eight tanks the second by a little each: 0.5 against 0.4. Counted a frame each the tanks
  // would always decide; weighing one half each, the samples' margin over the other two decides
  // where it is above 0.2 (their half's 0.25 a sample against the tanks' 0.05).
  KtcMethodResult r = two_weights();
  r.samples = {1, 2, 3};
  r.scores = {{{otsu_frame(0.9), otsu_frame(0.8), otsu_frame(0.7)}},
              {{otsu_frame(0.5), otsu_frame(0.5), otsu_frame(0.95)}}};
  tune_jointly(r);  // no tanks: nothing
  EXPECT_TRUE(r.tuned_jointly.empty());
  EXPECT_TRUE(r.joint_choice.empty());
  r.simulated = {{std::vector<KtcFrameScores>(8, otsu_frame(0.4))},
                 {std::vector<KtcFrameScores>(8, otsu_frame(0.5))}};
  tune_jointly(r);
  ASSERT_EQ(r.joint_choice.size(), 3u);
  ASSERT_EQ(r.tuned_jointly.size(), 1u);
  // Held out, sample 0's others gain 0.3 and lose 0.25 with the first weight (0.05 < 0.2): the
  // second; sample 1's gain 0.4 and lose 0.25 (0.15): the second; sample 2's gain 0.4 and 0.3
  // (0.7): the first, though the second would score it 0.95. Its own score never counts.
  const int chosen[3] = {1, 1, 0};
  const double score[3] = {0.5, 0.5, 0.7};
  for (std::size_t s = 0; s < 3; ++s) {
    EXPECT_EQ(r.joint_choice[s].candidate, chosen[s]) << s;
    EXPECT_EQ(r.joint_choice[s].rule.kind, SegmentationKind::otsu) << s;
    EXPECT_NEAR(r.tuned_jointly[0][s], score[s], 1e-12) << s;
  }
  // The first weight on sample 2's pool: (0.9 + 0.8) / 4 + 8 x 0.4 / 16.
  EXPECT_NEAR(r.joint_choice[2].tuning_score, 0.625, 1e-12);
  // On all three samples and the tanks: the first weight, 2.4 / 6 + 0.2 against 1.95 / 6 + 0.25;
  // each sample scored with it in sample.
  EXPECT_EQ(r.joint_best.candidate, 0);
  EXPECT_NEAR(r.joint_best.tuning_score, 0.6, 1e-12);
  for (std::size_t s = 0; s < 3; ++s)
    EXPECT_NEAR(r.joint_in_sample[0][s], r.scores[0][0][s].otsu, 1e-12) << s;
  // Counted a frame each (unweighted), the tanks decide sample 2's setting too.
  EXPECT_EQ(tune_ktc(r, {0, 1}, KtcRules::otsu).candidate, 0);  // the samples alone: the first
  KtcMethodResult pooled = r;
  for (std::size_t c = 0; c < 2; ++c)
    pooled.scores[c][0].insert(pooled.scores[c][0].end(), r.simulated[c][0].begin(),
                               r.simulated[c][0].end());
  EXPECT_EQ(tune_ktc(pooled, {0, 1, 3, 4, 5, 6, 7, 8, 9, 10}, KtcRules::otsu).candidate, 1);
  // With one sample there are no others: the tanks alone, as the tuning on simulation.
  r.samples = {1};
  r.scores = {{{otsu_frame(0.9)}}, {{otsu_frame(0.5)}}};
  tune_jointly(r);
  tune_on_simulation(r);
  ASSERT_EQ(r.joint_choice.size(), 1u);
  EXPECT_EQ(r.joint_choice[0].candidate, r.simulation_choice.candidate);
  EXPECT_NEAR(r.tuned_jointly[0][0], r.tuned_on_simulation[0][0], 1e-12);
}

TEST(KtcTuning, WeightsScaleEachSamplesScoresInTheSum) {
  // Otsu scores 0.4 everywhere; weights 1 and 3 give 1.6, as two samples of 0.4 and 1.2 would.
  KtcMethodResult r = made({2, 9, 15}, 0.3);
  EXPECT_NEAR(tune_ktc(r, {0, 1}, KtcRules::otsu, -1, {1.0, 3.0}).tuning_score, 1.6, 1e-12);
  EXPECT_THROW(tune_ktc(r, {0, 1}, KtcRules::otsu, -1, {1.0}), std::invalid_argument);
  // Unit weights are no weights: the same choice and nested scores.
  const KtcChoice a = choose_ktc_rules(r, {0, 1, 2}), b = choose_ktc_rules(r, {0, 1, 2}, {1, 1, 1});
  EXPECT_EQ(a.rule.kind, b.rule.kind);
  EXPECT_DOUBLE_EQ(a.nested_otsu, b.nested_otsu);
  EXPECT_DOUBLE_EQ(a.nested_levels, b.nested_levels);
}

}  // namespace
}  // namespace eitbench
