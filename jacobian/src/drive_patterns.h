#pragma once
// Any current pattern between two electrodes is a sum of adjacent drives (internal to jacobian/):
// e_p - e_q = sum_{k=p}^{q-1} (e_k - e_{k+1}), indices mod L. The CEM is linear in its current
// vector, so the field of drive p -> q is that sum of the L adjacent drives' fields: the forward
// model solves the L adjacent drives once and serves every protocol from them. The adjoint field
// of a measurement U(a) - U(b) is that of the drive a -> b, so one table serves both.
#include <Eigen/Core>
#include <utility>
#include <vector>

#include "eitbench/jacobian/current_patterns.h"
#include "eitbench/jacobian/measurement_protocol.h"

namespace eitbench::detail {

struct DrivePatterns {
  // The distinct electrode pairs (p, q) the channels drive or measure between (none for current
  // patterns), and for each pattern the adjacent drives k it sums, with their weights (for a pair
  // the shorter way round the ring).
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
                                                                               terms.size());
    for (std::size_t p = 0; p < terms.size(); ++p) {
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

// Current patterns as sums of adjacent drives of amplitude `current`: a current vector c is
// sum_k a_k (e_k - e_{k+1}) with a_k = c_0 + ... + c_k, so its field is sum_k (a_k / current)
// times adjacent drive k's. Patterns 0..P-1 are the injections' fields; P..P+M-1 the differences'
// adjoint fields at `current` (the Jacobian's 1 / current then makes them unit), the differences'
// as the channels' measurement pairs are. Value p * M + m drives p and measures P + m.
DrivePatterns pattern_drives(const CurrentPatterns& patterns, double current);

}  // namespace eitbench::detail
