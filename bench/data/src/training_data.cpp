#include "eitbench/bench/data/training_data.h"

namespace eitbench {

LabelledFrames labelled_frames(const Dataset& data, Split split, int limit) {
  std::vector<int> rows = data.indices(split);
  if (limit > 0 && static_cast<int>(rows.size()) > limit) rows.resize(limit);
  const Eigen::Index n = static_cast<Eigen::Index>(rows.size());
  LabelledFrames out;
  out.background = data.background;
  out.frames.resize(n, data.differences.cols());
  out.labels.resize(n, data.labels.cols());
  for (Eigen::Index k = 0; k < n; ++k) {
    out.frames.row(k) = data.differences.row(rows[k]);
    if (data.has_labels()) out.labels.row(k) = data.labels.row(rows[k]);
  }
  if (!data.circles.empty())
    for (int r : rows) out.circles.push_back(data.circles[r]);
  return out;
}

AugmentSetup sensor_of(const Dataset& data, AugmentGroup group) {
  AugmentSetup s;
  s.group = group;
  s.layout = FrameLayout::reduced;
  s.electrodes = data.electrodes;
  s.image_size = data.image_size;
  s.radius = data.radius;
  return s;
}

}  // namespace eitbench
