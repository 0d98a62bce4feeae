#pragma once
// Any current pattern between two electrodes is a sum of adjacent drives (internal to jacobian/):
// e_p - e_q = sum_{k=p}^{q-1} (e_k - e_{k+1}), indices mod L. The CEM is linear in its current
// vector, so the field of drive p -> q is that sum of the L adjacent drives' fields: the forward
// model solves the L adjacent drives once and serves every protocol from them. The adjoint field
// of a measurement U(a) - U(b) is that of the drive a -> b, so one table serves both.
#include <Eigen/Core>
#include <utility>
#include <vector>

#include "eitbench/jacobian/measurement_protocol.h"

namespace eitbench::detail {

struct DrivePatterns {
  // The distinct electrode pairs (p, q) the channels drive or measure between, and for each the
  // adjacent drives k it sums, with their signs (the shorter way round the ring).
  std::vector<std::pair<int, int>> pairs;
  std::vector<std::vector<std::pair<int, double>>> terms;
  std::vector<int> drive, measure;  // per channel: its drive's and its measurement's pattern

  // Columns of `adjacent` (one per adjacent drive k) combined into one per pattern. A pattern of
  // one forward term is that column exactly (no arithmetic), so the adjacent protocol's values
  // are bit for bit those of the adjacent drives.
  template <typename Matrix>
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> combine(
      const Matrix& adjacent) const {
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> out(adjacent.rows(),
                                                                               pairs.size());
    for (std::size_t p = 0; p < pairs.size(); ++p) {
      const auto& t = terms[p];
      if (t.size() == 1 && t[0].second == 1.0) {
        out.col(p) = adjacent.col(t[0].first);
        continue;
      }
      out.col(p).setZero();
      for (const auto& [k, s] : t) out.col(p) += s * adjacent.col(k);
    }
    return out;
  }
};

DrivePatterns drive_patterns(const std::vector<Channel>& channels, int electrodes);

}  // namespace eitbench::detail
