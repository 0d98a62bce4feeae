// The group acting on a protocol of current patterns (KTC2023's): against the forward model on a
// symmetric 32-electrode mesh, with per-pattern amplitudes, and its refusal of a protocol that an
// element does not map onto itself.
#include <gtest/gtest.h>

#include <random>

#include "eitbench/augment.h"
#include "eitbench/jacobian.h"
#include "group_support.h"
#include "ktc_synthetic.h"
#include "test_support.h"

namespace eitbench {
namespace {

std::vector<GroupElement> quarter_turns_and_their_mirrors() {
  std::vector<GroupElement> out;
  for (bool mirror : {false, true})
    for (int s : {0, 8, 16, 24}) out.push_back({s, mirror});
  return out;
}

// KTC's injections (odd pairs, and 1, 9, 17, 25 against the other odd electrodes) are mapped onto
// themselves by the quarter turns and the mirrors through electrodes 1, 9, 17, 25 (and between
// them), and by no other element of D32: an eighth turn moves electrode 1 to 5, which drives no
// "against the others" pattern.
TEST(PatternSymmetry, KtcsPatternsKeepTheQuarterTurnsAndTheirMirrors) {
  const MeasurementProtocol ktc("ktc", testing::ktc_patterns());
  const auto kept = protocol_elements(ktc, group_elements(AugmentGroup::dihedral, 32));
  EXPECT_EQ(kept.size(), 8u);
  for (const GroupElement& g : quarter_turns_and_their_mirrors())
    EXPECT_NE(std::find(kept.begin(), kept.end(), g), kept.end()) << g.to_string();
}

// For each kept element, the frame of the moved conductivity equals the action on the frame, with
// every pattern at its own amplitude (as KTC measured them): the amplitude ratios scale the
// moved patterns' values.
TEST(PatternSymmetry, TheActionCommutesWithTheForwardModel) {
  CurrentPatterns patterns = testing::ktc_patterns();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> amplitude(0.8, 1.2);
  for (int p = 0; p < patterns.patterns(); ++p) patterns.injection.col(p) *= amplitude(rng);
  const Mesh& mesh = testing::disk(32, MeshDensity::coarse);
  ForwardOptions o;
  o.protocol = std::make_shared<MeasurementProtocol>("ktc", patterns);
  const ForwardModel model(mesh, o);
  const Eigen::VectorXd sigma = testing::random_conductivity(mesh.num_triangles(), 29);
  const Eigen::VectorXd v = model.inputs(sigma);
  ASSERT_EQ(v.size(), 76 * 31);
  bool mixed = false;  // some element's differences are no signed permutation
  for (const GroupElement& g : quarter_turns_and_their_mirrors()) {
    const PatternAction a = pattern_action(patterns, g);
    const Eigen::VectorXd moved = model.inputs(testing::move_conductivity(mesh, sigma, g));
    EXPECT_LT((a.apply(v) - moved).norm() / v.norm(), 1e-10) << g.to_string();
    for (Eigen::Index m = 0; m < a.differences.rows(); ++m)
      mixed = mixed || (a.differences.row(m).array() != 0).count() > 1;
  }
  EXPECT_TRUE(mixed) << "the 32nd difference (minus the sum of the 31) never entered";
}

TEST(PatternSymmetry, AnAsymmetricProtocolIsRefusedNamingThePatternOrDifference) {
  CurrentPatterns patterns = testing::ktc_patterns();
  const GroupElement eighth{4, false};
  try {
    pattern_action(patterns, eighth);
    ADD_FAILURE() << "an eighth turn was taken for a symmetry";
  } catch (const InputError& e) {
    // Patterns 16 and 17 (1 against 3, 1 against 5) move onto an odd pair and onto "1 against 29";
    // 18 (1 against 7) moves to 29 against 3, which no pattern drives.
    EXPECT_EQ(e.field(), "pattern 18") << e.what();
  }
  // Differences of the pairs (1,2), (3,4), ...: a mirror through electrode 1 makes (1,32).
  patterns.measurement = Eigen::MatrixXd::Zero(32, 16);
  for (int m = 0; m < 16; ++m)
    patterns.measurement(2 * m, m) = 1, patterns.measurement(2 * m + 1, m) = -1;
  EXPECT_NO_THROW(pattern_action(patterns, {8, false}));
  try {
    pattern_action(patterns, {0, true});
    ADD_FAILURE() << "the mirror was taken for a symmetry of paired differences";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "difference 0") << e.what();
  }
  EXPECT_THROW(pattern_action(testing::ktc_patterns(), {8, false}).apply(Eigen::VectorXd(10)),
               InputError);
}

// Training on current patterns: the group none is the identity; a larger group is refused (the set
// is expanded by pattern_action beforehand: bench/ktc/tank_augmentation.h).
TEST(PatternSymmetry, ALearnedSetOnCurrentPatternsTakesTheIdentityOnly) {
  AugmentSetup setup;
  setup.group = AugmentGroup::none;
  setup.electrodes = 32, setup.image_size = 8;
  setup.protocol = std::make_shared<MeasurementProtocol>("ktc", testing::ktc_patterns());
  LabelledFrames set;
  set.frames = SampleMatrix::Random(3, 76 * 31);
  set.labels = SampleMatrix::Random(3, 64);
  const LabelledFrames same = expand_by_group(set, setup);
  EXPECT_EQ(same.frames, set.frames);
  // The labels as they were, inside the disk (the pixels outside are masked to 0).
  EXPECT_EQ((same.labels.array() == set.labels.array() || same.labels.array() == 0).count(),
            set.labels.size());
  EXPECT_GT((same.labels.array() == set.labels.array()).count(), set.labels.size() / 2);
  setup.group = AugmentGroup::dihedral;
  try {
    expand_by_group(set, setup);
    ADD_FAILURE() << "D32 taken as permutations of current patterns";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "group") << e.what();
  }
}

}  // namespace
}  // namespace eitbench
