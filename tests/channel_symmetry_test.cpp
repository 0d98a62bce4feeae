// The group acting on any protocol: its signed channel permutation against the forward model on a
// symmetric mesh, against FrameSymmetry's tables for the adjacent protocol, and its refusal of a
// protocol that an element does not map onto itself.
#include <gtest/gtest.h>

#include "eitbench/augment.h"
#include "eitbench/jacobian.h"
#include "group_support.h"
#include "test_support.h"

namespace eitbench {
namespace {

TEST(ChannelSymmetry, AdjacentEqualsFrameSymmetrysReducedTables) {
  for (int L : {8, 16}) {
    const FrameSymmetry frames(L);
    for (auto order : {MeasurementOrder::rotating, MeasurementOrder::ascending}) {
      const MeasurementProtocol p = adjacent_protocol(L, order);
      for (const GroupElement& g : group_elements(AugmentGroup::dihedral, L)) {
        const SignedPermutation a = channel_action(p, g);
        EXPECT_EQ(a.index, frames.permutation(g, FrameLayout::reduced)) << g.to_string();
        EXPECT_EQ(a.sign, std::vector<double>(a.sign.size(), 1.0)) << g.to_string();
      }
    }
  }
}

// For every element of D16, the inputs of the moved conductivity equal the signed permutation of
// the inputs: the forward model and the channel action agree.
void expect_equivariant(const MeasurementProtocol& protocol, bool expect_signs) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  ForwardOptions o;
  o.protocol = std::make_shared<MeasurementProtocol>(protocol);
  const ForwardModel model(mesh, o);
  const Eigen::VectorXd sigma = testing::random_conductivity(mesh.num_triangles(), 23);
  const Eigen::VectorXd v = model.inputs(sigma);
  bool negated = false;
  for (const GroupElement& g : group_elements(AugmentGroup::dihedral, 16)) {
    const SignedPermutation a = channel_action(protocol, g);
    negated = negated || a.sign != std::vector<double>(a.sign.size(), 1.0);
    const Eigen::VectorXd simulated = model.inputs(testing::move_conductivity(mesh, sigma, g));
    EXPECT_LT((a.apply(v) - simulated).norm() / v.norm(), 1e-10)
        << protocol.name() << " " << g.to_string();
  }
  EXPECT_EQ(negated, expect_signs) << protocol.name();
}

TEST(ChannelSymmetry, OppositeFramesCommuteWithEveryElementOfD16) {
  // The mirror reverses each (k+1, k) measurement pair: signed values change sign.
  expect_equivariant(opposite_protocol(16), true);
  expect_equivariant(opposite_protocol(16).with_magnitude(true), false);  // |-v| = |v|
}

TEST(ChannelSymmetry, SkipAndAdjacentFramesCommuteWithEveryElementOfD16) {
  // The mirror reverses drive and measurement pairs alike: no sign survives.
  expect_equivariant(skip_protocol(16, 3), false);
  expect_equivariant(skip_protocol(16, 0), false);  // reciprocal: 104 inputs
  expect_equivariant(adjacent_protocol(16), false);
}

TEST(ChannelSymmetry, AnAsymmetricProtocolIsRefusedNamingTheChannel) {
  // Opposite drives from electrodes 0..7 only: rot:1 maps drive 0 -> 8 onto drive 15 -> 7, which
  // is drive 7 -> 15 reversed and listed; rot:8 maps electrode 0 to 8 (also listed). A drive set
  // 0..3 breaks under rot:4, at the first channel.
  std::vector<Channel> channels;
  const MeasurementProtocol opposite = opposite_protocol(16);
  for (const Channel& c : opposite.channels())
    if (c.drive_plus < 4) channels.push_back(c);
  const MeasurementProtocol p("four-drives", 16, channels);
  EXPECT_NO_THROW(channel_action(p, {0, false}));
  try {
    channel_action(p, {4, false});
    ADD_FAILURE() << "rot:4 accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "protocol");
    EXPECT_EQ(e.field(), "channel 0");
    EXPECT_NE(e.message().find("rot:4"), std::string::npos) << e.what();
  }
  const auto kept = protocol_elements(p, group_elements(AugmentGroup::dihedral, 16));
  // Its subgroup: the identity, the half turn (drives 0..3 -> 8..11 = the same lines reversed),
  // and the mirrors that keep the drive lines 0..3 as a set.
  ASSERT_FALSE(kept.empty());
  EXPECT_EQ(kept.front(), (GroupElement{0, false}));
  for (const GroupElement& g : kept) EXPECT_NO_THROW(channel_action(p, g)) << g.to_string();
  EXPECT_LT(kept.size(), 32u);
}

TEST(ChannelSymmetry, AugmentingOppositeFramesGives32PerFrame) {
  const auto protocol = std::make_shared<MeasurementProtocol>(opposite_protocol(16));
  AugmentSetup setup;
  setup.protocol = protocol;
  LabelledFrames set;
  set.frames = SampleMatrix::Random(3, 192);
  const LabelledFrames out = expand_by_group(set, setup);
  EXPECT_EQ(out.frames.rows(), 3 * 32);
  EXPECT_EQ(out.frames.cols(), 192);
  EXPECT_EQ(out.frames.row(0), set.frames.row(0));  // the identity first
  set.frames = SampleMatrix::Random(3, 208);
  EXPECT_EQ(testing::input_error_at([&] { expand_by_group(set, setup); }), "frames.columns");
  setup.group = AugmentGroup::paper;
  EXPECT_EQ(testing::input_error_at([&] { setup.validate(); }), "AugmentSetup.group");
}

}  // namespace
}  // namespace eitbench
