#pragma once
// The three layouts a frame of one adjacent-protocol measurement comes in.
#include <Eigen/Core>
#include <string>

#include "eitbench/jacobian/protocol.h"

namespace eitbench {

enum class FrameLayout {
  rotating,   // L(L-3) values, drive-major, m = d+2 ... (the canonical order)
  ascending,  // L(L-3) values, m = 0 ... L-1 skipping d-1, d, d+1
  reduced,    // L(L-3)/2 reciprocity-reduced values (the paper's sequential 104)
};

std::string to_string(FrameLayout layout);
// The layout of a frame of `size` values for L electrodes: reduced for L(L-3)/2 values, `order`
// for L(L-3). Throws InputError(source, "frame", ...) for any other size.
FrameLayout frame_layout(Eigen::Index size, int electrodes, MeasurementOrder order,
                         const std::string& source);
Eigen::Index frame_size(FrameLayout layout, int electrodes);

}  // namespace eitbench
