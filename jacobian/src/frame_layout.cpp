#include "eitbench/jacobian/frame_layout.h"

#include "eitbench/jacobian/error.h"

namespace eitbench {

std::string to_string(FrameLayout layout) {
  switch (layout) {
    case FrameLayout::rotating:
      return "rotating";
    case FrameLayout::ascending:
      return "ascending";
    case FrameLayout::reduced:
      return "reduced";
  }
  return "?";
}

Eigen::Index frame_size(FrameLayout layout, int L) {
  return layout == FrameLayout::reduced ? L * (L - 3) / 2 : L * (L - 3);
}

FrameLayout frame_layout(Eigen::Index size, int L, MeasurementOrder order,
                         const std::string& source) {
  if (size == L * (L - 3))
    return order == MeasurementOrder::rotating ? FrameLayout::rotating : FrameLayout::ascending;
  if (size == L * (L - 3) / 2) return FrameLayout::reduced;
  throw InputError(source, "frame",
                   "has " + std::to_string(size) + " values; " + std::to_string(L) +
                       " electrodes give " + std::to_string(L * (L - 3)) + " or " +
                       std::to_string(L * (L - 3) / 2) + " (reduced)");
}

}  // namespace eitbench
