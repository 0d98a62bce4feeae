#pragma once
// A data set's splits as the learned reconstructor's training input.
#include "eitbench/augment/augmented_set.h"
#include "eitbench/bench/data/dataset.h"

namespace eitbench {

// The difference frames (reduced layout), labels and circles of one split; the first `limit`
// samples of it when limit > 0 (the data-efficiency sweep).
LabelledFrames labelled_frames(const Dataset& data, Split split, int limit = 0);
// The sensor the data were taken on, for augmentation: electrodes, image size, radius.
AugmentSetup sensor_of(const Dataset& data, AugmentGroup group = AugmentGroup::none);

}  // namespace eitbench
