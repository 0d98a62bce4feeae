#include "drive_patterns.h"

#include <map>
#include <stdexcept>

namespace eitbench::detail {

DrivePatterns drive_patterns(const std::vector<Channel>& channels, int L) {
  DrivePatterns out;
  std::map<std::pair<int, int>, int> index;
  auto pattern = [&](int p, int q) {
    if (p < 0 || p >= L || q < 0 || q >= L || p == q)
      throw std::invalid_argument("drive_patterns: a channel names no electrode pair");
    const auto [it, fresh] =
        index.emplace(std::make_pair(p, q), static_cast<int>(out.pairs.size()));
    if (fresh) {
      out.pairs.emplace_back(p, q);
      const int forward = ((q - p) % L + L) % L;  // adjacent drives p .. q-1
      std::vector<std::pair<int, double>> t;
      if (2 * forward <= L)
        for (int k = 0; k < forward; ++k) t.emplace_back((p + k) % L, 1.0);
      else  // e_p - e_q = -(e_q - e_p): the drives q .. p-1, negated
        for (int k = 0; k < L - forward; ++k) t.emplace_back((q + k) % L, -1.0);
      out.terms.push_back(std::move(t));
    }
    return it->second;
  };
  for (const Channel& c : channels) {
    out.drive.push_back(pattern(c.drive_plus, c.drive_minus));
    out.measure.push_back(pattern(c.meas_plus, c.meas_minus));
  }
  return out;
}

namespace {

// The adjacent drives whose sum, each scaled by its weight, carries current vector c.
std::vector<std::pair<int, double>> adjacent_terms(const Eigen::VectorXd& c, double scale) {
  std::vector<std::pair<int, double>> t;
  double a = 0;
  for (Eigen::Index k = 0; k + 1 < c.size(); ++k) {
    a += c[k];
    if (a != 0) t.emplace_back(static_cast<int>(k), a * scale);
  }
  return t;
}

}  // namespace

DrivePatterns pattern_drives(const CurrentPatterns& patterns, double current) {
  DrivePatterns out;
  const int P = patterns.patterns(), M = patterns.differences();
  for (int p = 0; p < P; ++p)
    out.terms.push_back(adjacent_terms(patterns.injection.col(p), 1 / current));
  for (int m = 0; m < M; ++m) out.terms.push_back(adjacent_terms(patterns.measurement.col(m), 1.0));
  out.drive.reserve(static_cast<std::size_t>(P) * M);
  out.measure.reserve(static_cast<std::size_t>(P) * M);
  for (int p = 0; p < P; ++p)
    for (int m = 0; m < M; ++m) {
      out.drive.push_back(p);
      out.measure.push_back(P + m);
    }
  return out;
}

}  // namespace eitbench::detail
