#include "eitbench/augment/impedance_map.h"

#include <limits>

#include "eitbench/jacobian/error.h"

namespace eitbench {

namespace {
// Any layout to the rotating order.
Eigen::VectorXd to_rotating(const Eigen::VectorXd& frame, const Protocol& p, FrameLayout layout) {
  if (frame.size() != frame_size(layout, p.electrodes()))
    throw InputError("frame", "values",
                     "has " + std::to_string(frame.size()) + " values, not the " +
                         std::to_string(frame_size(layout, p.electrodes())) + " of the " +
                         to_string(layout) + " layout");
  switch (layout) {
    case FrameLayout::rotating:
      return frame;
    case FrameLayout::ascending:
      return p.reorder(frame, MeasurementOrder::ascending, MeasurementOrder::rotating);
    case FrameLayout::reduced:
      return p.expand(frame, MeasurementOrder::rotating);
  }
  return frame;
}
}  // namespace

Eigen::MatrixXd impedance_map(const Eigen::VectorXd& frame, const Protocol& p, FrameLayout layout) {
  const Eigen::VectorXd rotating = to_rotating(frame, p, layout);
  const int L = p.electrodes();
  // The rotating frame is the map read row by row.
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      rotating.data(), L, L - 3);
}

Eigen::MatrixXd full_impedance_map(const Eigen::VectorXd& frame, const Protocol& p,
                                   FrameLayout layout) {
  const Eigen::VectorXd rotating = to_rotating(frame, p, layout);
  const int L = p.electrodes();
  Eigen::MatrixXd full = Eigen::MatrixXd::Constant(L, L, std::numeric_limits<double>::quiet_NaN());
  const auto& pairs = p.pairs(MeasurementOrder::rotating);
  for (std::size_t i = 0; i < pairs.size(); ++i)
    full(pairs[i].drive, pairs[i].measure) = rotating[i];
  return full;
}

Eigen::VectorXd frame_from_map(const Eigen::MatrixXd& map, const Protocol& p, FrameLayout layout) {
  const int L = p.electrodes();
  if (map.rows() != L || map.cols() != L - 3)
    throw InputError("map", "shape",
                     std::to_string(map.rows()) + " x " + std::to_string(map.cols()) +
                         ", not L x (L-3) = " + std::to_string(L) + " x " + std::to_string(L - 3));
  Eigen::VectorXd rotating(p.frame_size());
  for (int d = 0; d < L; ++d)
    for (int k = 0; k < L - 3; ++k) rotating[d * (L - 3) + k] = map(d, k);
  switch (layout) {
    case FrameLayout::rotating:
      return rotating;
    case FrameLayout::ascending:
      return p.reorder(rotating, MeasurementOrder::rotating, MeasurementOrder::ascending);
    case FrameLayout::reduced:
      return p.reduce(rotating, MeasurementOrder::rotating);
  }
  return rotating;
}

}  // namespace eitbench
