#pragma once
// A protocol given by current patterns (docs/protocols.md#current-patterns), as EIDORS's
// stimulation patterns and KTC2023's Inj and Mpat give it: each pattern drives any currents through
// any electrodes at once, and the same differences are read under every pattern. A frame holds
// patterns() x differences() values, pattern-major: value p * differences() + m is difference m
// under pattern p. MeasurementProtocol (measurement_protocol.h) carries one in place of channels.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace eitbench {

struct CurrentPatterns {
  // L x P: column p is the current into each electrode under pattern p (the unit of
  // ForwardOptions::current; negative out). Each column sums to zero and has a non-zero entry.
  Eigen::MatrixXd injection;
  // L x M: column m weights the electrode potentials of difference m, v = measurement(:, m)^T U.
  // Each column sums to zero (so no value depends on the ground) and has a non-zero entry.
  Eigen::MatrixXd measurement;

  int electrodes() const { return static_cast<int>(injection.rows()); }
  int patterns() const { return static_cast<int>(injection.cols()); }
  int differences() const { return static_cast<int>(measurement.cols()); }
  int size() const { return patterns() * differences(); }

  // InputError(source, field) for: fewer than 2 electrodes, no pattern or no difference, the two
  // matrices on different electrode counts, a value that is not finite, a column of zeros, or a
  // column whose sum is not zero to 1e-9 of its largest entry ("injection column 4: sums to ...").
  void validate(const std::string& source, const std::string& injection_field = "injection",
                const std::string& measurement_field = "measurement") const;

  // The electrodes a pattern drives and a difference reads (non-zero entries), 0-based.
  std::vector<int> driven(int pattern) const;
  std::vector<int> read(int difference) const;

  // The values that need none of `removed` (0-based electrodes, as KTC's levels remove them):
  // false for every value whose pattern drives or whose difference reads a removed electrode.
  std::vector<bool> values_without(const std::vector<int>& removed) const;
};

bool operator==(const CurrentPatterns& a, const CurrentPatterns& b);

}  // namespace eitbench
