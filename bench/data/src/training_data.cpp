#include "eitbench/bench/data/training_data.h"

#include <algorithm>

#include "eitbench/bench/data/sensor.h"
#include "eitbench/jacobian/random.h"

namespace eitbench {

std::vector<int> subset_rows(std::vector<int> rows, int limit, std::uint64_t seed) {
  if (limit <= 0 || static_cast<int>(rows.size()) <= limit) return rows;
  // Fisher-Yates on the first `limit` places: the first n of one seed's shuffle, so a smaller
  // subset lies inside a larger one.
  RandomStream rng(seed, 0x5eb5e7ULL);
  for (int k = 0; k < limit; ++k) {
    const int left = static_cast<int>(rows.size()) - k;
    const int pick = k + static_cast<int>(rng.next() % static_cast<std::uint64_t>(left));
    std::swap(rows[k], rows[pick]);
  }
  rows.resize(limit);
  std::sort(rows.begin(), rows.end());  // the data set's order within the subset
  return rows;
}

LabelledFrames labelled_frames(const Dataset& data, Split split, int limit, std::uint64_t seed) {
  const std::vector<int> rows = subset_rows(data.indices(split), limit, seed);
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
  s.sensor = shaped_sensor_of(data);
  s.protocol = std::make_shared<const MeasurementProtocol>(measurement_protocol(data));
  return s;
}

}  // namespace eitbench
