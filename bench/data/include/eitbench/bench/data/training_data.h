#pragma once
// A data set's splits as the learned reconstructor's training input.
#include <cstdint>
#include <vector>

#include "eitbench/augment/augmented_set.h"
#include "eitbench/bench/data/dataset.h"

namespace eitbench {

// `limit` of `rows` drawn at random by `seed`, in their order (all of them when limit <= 0 or
// there are no more). Nested: the rows drawn for a smaller limit are among those for a larger.
// Not the first `limit`: a simulated set stores its frames by touch count, so its first 7,035
// training frames hold one touch each.
std::vector<int> subset_rows(std::vector<int> rows, int limit, std::uint64_t seed);

// The difference frames (reduced layout), labels and circles of one split; `limit` of them,
// subset_rows(..., seed), when limit > 0 (the data-efficiency sweep, train --train-size).
LabelledFrames labelled_frames(const Dataset& data, Split split, int limit = 0,
                               std::uint64_t seed = 1);
// The sensor the data were taken on, for augmentation: electrodes, image size, radius.
AugmentSetup sensor_of(const Dataset& data, AugmentGroup group = AugmentGroup::none);

}  // namespace eitbench
