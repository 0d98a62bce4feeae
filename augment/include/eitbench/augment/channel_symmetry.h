#pragma once
// The symmetry group acting on any protocol's frames (docs/protocols.md). An element moves the
// electrodes, so it moves each channel's four electrodes onto another channel's; a pair whose
// orientation reverses negates the value. The action on a frame of the protocol's inputs is
// therefore a signed permutation, built from the protocol and the electrode permutation alone.
// For the adjacent protocol it equals FrameSymmetry's reduced tables (every sign +1).
#include <Eigen/Core>
#include <vector>

#include "eitbench/augment/symmetry.h"
#include "eitbench/jacobian/measurement_protocol.h"

namespace eitbench {

// out[i] = sign[i] * in[index[i]].
struct SignedPermutation {
  std::vector<int> index;
  std::vector<double> sign;  // +1 or -1

  // InputError("frame", "values") for a frame of another length (a frame is data).
  Eigen::VectorXd apply(const Eigen::VectorXd& frame) const;
};

// The action of g on a frame of `protocol`'s inputs: the frame of the touch g moves, as
// FrameSymmetry::apply (v'(c) = v(P(c)) with P the electrode map that undoes g's). Throws
// InputError("protocol", "channel N") naming the first input channel whose image the protocol
// lacks: such a protocol is not mapped onto itself by g, and g cannot augment it; and
// InputError("protocol", "patterns") for a protocol of current patterns (no channels to permute).
// With `over_channels`, the action on whole frames (every channel, in protocol order) instead.
SignedPermutation channel_action(const MeasurementProtocol& protocol, const GroupElement& g,
                                 bool over_channels = false);

// The actions of `elements`, in their order.
std::vector<SignedPermutation> channel_actions(const MeasurementProtocol& protocol,
                                               const std::vector<GroupElement>& elements);

// The elements among `candidates` that map the protocol onto itself, in their order: the subgroup
// a protocol read from a file keeps (all of D_L for adjacent, opposite and skip-K on the disk; the
// quarter turns and four mirrors for KTC2023's current patterns, by pattern_action).
std::vector<GroupElement> protocol_elements(const MeasurementProtocol& protocol,
                                            const std::vector<GroupElement>& candidates);

}  // namespace eitbench
