#pragma once
// The symmetry group acting on the frames of a protocol of current patterns (docs/protocols.md),
// as KTC2023's tank is driven. An element g moves the electrodes (e to pi(e)); the frame of the
// moved conductivity under pattern j is the frame of the unmoved one under the pattern j o pi,
// read through the differences m o pi. Where j o pi is a pattern of the set up to a factor s (its
// own measured amplitude, or a reversed pair) and each m o pi a combination of the set's
// differences, the action is linear: a permutation of the patterns, scaled, with one
// differences x differences matrix. KTC's 31 adjacent differences are not permuted by a quarter
// turn (the 32nd, minus the sum of the 31, takes a place): that matrix is not a permutation.
#include <Eigen/Core>
#include <vector>

#include "eitbench/augment/symmetry.h"
#include "eitbench/jacobian/current_patterns.h"

namespace eitbench {

// out[p * M + m] = scale[p] * sum_n differences(m, n) * in[source[p] * M + n], M = differences.
struct PatternAction {
  std::vector<int> source;    // the pattern each pattern's values come from
  std::vector<double> scale;  // its amplitude ratio (negative where the pair is reversed)
  Eigen::MatrixXd differences;

  // InputError("frame", "values") for a frame of another length. A missing value (NaN) spreads
  // to every value it enters: act on whole frames, then remove what a level removes.
  Eigen::VectorXd apply(const Eigen::VectorXd& frame) const;
};

// The action of g (on `patterns.electrodes()` electrodes equally spaced) on a frame of `patterns`:
// the frame of the touch g moves, as channel_action's. Throws InputError("protocol",
// "pattern N") naming the first pattern whose image is no pattern of the set up to a factor, and
// InputError("protocol", "difference N") for the first difference whose image the set's
// differences do not span (to 1e-9 of its size).
PatternAction pattern_action(const CurrentPatterns& patterns, const GroupElement& g);

}  // namespace eitbench
