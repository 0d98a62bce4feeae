#include "eitbench/jacobian/protocol.h"

#include <cmath>
#include <stdexcept>

#include "eitbench/jacobian/error.h"

namespace eitbench {

MeasurementOrder parse_order(const std::string& name) {
  if (name == "rotating") return MeasurementOrder::rotating;
  if (name == "ascending") return MeasurementOrder::ascending;
  throw InputError("MeasurementOrder", "name",
                   "unknown measurement order '" + name + "' (rotating or ascending)");
}

std::string to_string(MeasurementOrder order) {
  return order == MeasurementOrder::rotating ? "rotating" : "ascending";
}

Protocol::Protocol(int electrodes) : electrodes_(electrodes) {
  const int L = electrodes;
  if (L < 4)
    throw InputError("Protocol", "electrodes",
                     "the adjacent protocol needs at least 4 electrodes, got " + std::to_string(L));
  auto mod = [L](int i) { return ((i % L) + L) % L; };
  rotating_index_.assign(L * L, -1);
  ascending_index_.assign(L * L, -1);
  for (int d = 0; d < L; ++d)
    for (int k = 0; k < L - 3; ++k) {
      rotating_index_[d * L + mod(d + 2 + k)] = static_cast<int>(rotating_.size());
      rotating_.push_back({d, mod(d + 2 + k)});
    }
  for (int d = 0; d < L; ++d)
    for (int m = 0; m < L; ++m) {
      if (m == mod(d - 1) || m == d || m == mod(d + 1)) continue;
      ascending_index_[d * L + m] = static_cast<int>(ascending_.size());
      ascending_.push_back({d, m});
    }
  for (int d = 0; d < L; ++d)
    for (int m = d + 2; m < L; ++m) {
      if (d == 0 && m == L - 1) continue;
      reduced_to_rotating_.push_back(rotating_index_[d * L + m]);
      reduced_.push_back({d, m});
    }
  rotating_to_reduced_.assign(rotating_.size(), -1);
  for (std::size_t r = 0; r < reduced_.size(); ++r) {
    const auto [d, m] = reduced_[r];
    rotating_to_reduced_[rotating_index_[d * L + m]] = static_cast<int>(r);
    rotating_to_reduced_[rotating_index_[m * L + d]] = static_cast<int>(r);
  }
}

const std::vector<MeasurementPair>& Protocol::pairs(MeasurementOrder order) const {
  return order == MeasurementOrder::rotating ? rotating_ : ascending_;
}

int Protocol::index(int drive, int measure, MeasurementOrder order) const {
  const int L = electrodes_;
  if (drive < 0 || drive >= L || measure < 0 || measure >= L) return -1;
  return (order == MeasurementOrder::rotating ? rotating_index_
                                              : ascending_index_)[drive * L + measure];
}

Eigen::VectorXd Protocol::reorder(const Eigen::VectorXd& frame, MeasurementOrder from,
                                  MeasurementOrder to) const {
  if (frame.size() != frame_size())
    throw InputError("frame", "values",
                     "has " + std::to_string(frame.size()) + " values, not the protocol's " +
                         std::to_string(frame_size()));
  if (from == to) return frame;
  Eigen::VectorXd out(frame_size());
  const auto& target = pairs(to);
  for (int i = 0; i < frame_size(); ++i)
    out[i] = frame[index(target[i].drive, target[i].measure, from)];
  return out;
}

Eigen::VectorXd Protocol::reduce(const Eigen::VectorXd& frame, MeasurementOrder order) const {
  const Eigen::VectorXd rotating = reorder(frame, order, MeasurementOrder::rotating);
  Eigen::VectorXd out(reduced_size());
  for (int r = 0; r < reduced_size(); ++r) out[r] = rotating[reduced_to_rotating_[r]];
  return out;
}

Eigen::VectorXd Protocol::expand(const Eigen::VectorXd& reduced, MeasurementOrder order) const {
  if (reduced.size() != reduced_size())
    throw InputError("frame", "values",
                     "has " + std::to_string(reduced.size()) +
                         " values, not the reduced layout's " + std::to_string(reduced_size()));
  Eigen::VectorXd rotating(frame_size());
  for (int i = 0; i < frame_size(); ++i) rotating[i] = reduced[rotating_to_reduced_[i]];
  return reorder(rotating, MeasurementOrder::rotating, order);
}

Eigen::MatrixXd Protocol::select_rows(const Eigen::MatrixXd& rotating_rows, MeasurementOrder order,
                                      bool reduced) const {
  if (rotating_rows.rows() != frame_size())
    throw std::invalid_argument("select_rows: wrong row count");
  const int n = reduced ? reduced_size() : frame_size();
  Eigen::MatrixXd out(n, rotating_rows.cols());
  for (int i = 0; i < n; ++i) {
    const int source =
        reduced ? reduced_to_rotating_[i]
                : index(pairs(order)[i].drive, pairs(order)[i].measure, MeasurementOrder::rotating);
    out.row(i) = rotating_rows.row(source);
  }
  return out;
}

double Protocol::reciprocity_error(const Eigen::VectorXd& frame, MeasurementOrder order) const {
  const Eigen::VectorXd v = reorder(frame, order, MeasurementOrder::rotating);
  double diff = 0;
  for (int i = 0; i < frame_size(); ++i) {
    const auto [d, m] = rotating_[i];
    diff += std::pow(v[i] - v[index(m, d, MeasurementOrder::rotating)], 2);
  }
  const double norm = v.norm();
  return norm > 0 ? std::sqrt(diff / 2) / norm : 0.0;
}

}  // namespace eitbench
