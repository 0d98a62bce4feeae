#include "eitbench/augment/channel_symmetry.h"

#include <numeric>

#include "eitbench/augment/pattern_symmetry.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

Eigen::VectorXd SignedPermutation::apply(const Eigen::VectorXd& frame) const {
  if (frame.size() != static_cast<Eigen::Index>(index.size()))
    throw InputError("frame", "values",
                     "has " + std::to_string(frame.size()) + " values, not the protocol's " +
                         std::to_string(index.size()) + " inputs");
  Eigen::VectorXd out(frame.size());
  for (std::size_t i = 0; i < index.size(); ++i) out[i] = sign[i] * frame[index[i]];
  return out;
}

SignedPermutation channel_action(const MeasurementProtocol& protocol, const GroupElement& g,
                                 bool over_channels) {
  // Current patterns move by a linear map, not a permutation of channels: pattern_action.
  if (protocol.has_patterns())
    throw InputError("protocol", "patterns",
                     "the " + protocol.name() +
                         " protocol is given by current patterns; its symmetry acts on them "
                         "linearly (pattern_action), not as a permutation of channels");
  const int L = protocol.electrodes();
  // P undoes g's move of the electrodes: v'(c) = v(P(c)), as FrameSymmetry's p(d) = d + s.
  std::vector<int> P(L);
  for (int e = 0; e < L; ++e) P[electrode_image(g, e, L)] = e;
  // The values acted on: the inputs, or every channel (each its own position).
  std::vector<int> values = protocol.inputs(), input_of(protocol.size(), -1);
  if (over_channels) {
    values.resize(protocol.size());
    std::iota(values.begin(), values.end(), 0);
  }
  for (std::size_t i = 0; i < values.size(); ++i) input_of[values[i]] = static_cast<int>(i);
  SignedPermutation out;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const Channel& c = protocol.channels()[values[i]];
    const Channel image{P[c.drive_plus], P[c.drive_minus], P[c.meas_plus], P[c.meas_minus]};
    int sign = 1, j = protocol.find(image, &sign);
    if (j >= 0 && input_of[j] < 0) {  // a reciprocal protocol's second of a pair: its partner
      const Channel& d = protocol.channels()[j];
      int partner_sign = 1;
      j = protocol.find({d.meas_plus, d.meas_minus, d.drive_plus, d.drive_minus}, &partner_sign);
      sign *= partner_sign;
    }
    if (j < 0 || input_of[j] < 0)
      throw InputError("protocol", "channel " + std::to_string(values[i]),
                       "(" + std::to_string(c.drive_plus) + "," + std::to_string(c.drive_minus) +
                           "," + std::to_string(c.meas_plus) + "," + std::to_string(c.meas_minus) +
                           ") has no image under " + g.to_string() + " in the " + protocol.name() +
                           " protocol: the protocol is not symmetric under that element");
    out.index.push_back(input_of[j]);
    out.sign.push_back(protocol.magnitude() ? 1 : sign);  // |-v| = |v|
  }
  return out;
}

std::vector<SignedPermutation> channel_actions(const MeasurementProtocol& protocol,
                                               const std::vector<GroupElement>& elements) {
  std::vector<SignedPermutation> out;
  out.reserve(elements.size());
  for (const GroupElement& g : elements) out.push_back(channel_action(protocol, g));
  return out;
}

std::vector<GroupElement> protocol_elements(const MeasurementProtocol& protocol,
                                            const std::vector<GroupElement>& candidates) {
  std::vector<GroupElement> out;
  for (const GroupElement& g : candidates) try {
      if (protocol.has_patterns())
        pattern_action(protocol.patterns(), g);
      else
        channel_action(protocol, g);
      out.push_back(g);
    } catch (const InputError&) {
      // g breaks the protocol: not in its subgroup
    }
  return out;
}

}  // namespace eitbench
