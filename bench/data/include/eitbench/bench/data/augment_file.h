#pragma once
// Augmenting a data-set file: the chosen splits expanded by a group (or moved by one element),
// the others copied, streamed block by block so that paper-scale sets need not fit in memory.
#include <string>
#include <vector>

#include "eitbench/augment/symmetry.h"
#include "eitbench/bench/data/dataset.h"

namespace eitbench {

struct FileAugmentOptions {
  AugmentGroup group = AugmentGroup::dihedral;
  std::vector<GroupElement> elements;  // empty: all of the group's, identity first
  std::vector<Split> splits{Split::train};
  int block = 64;  // input samples per block (64 x 32 rows of 4,096 pixels: 67 MB)
};

// Returns the number of samples written.
long long augment_dataset_file(const std::string& in, const std::string& out,
                               const FileAugmentOptions& options);

}  // namespace eitbench
