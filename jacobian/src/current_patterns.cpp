#include "eitbench/jacobian/current_patterns.h"

#include <cmath>
#include <cstdio>

#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

// Each column finite, not all zero, and summing to zero relative to its largest entry.
void check_columns(const Eigen::MatrixXd& m, const std::string& source, const std::string& field,
                   const char* what) {
  for (Eigen::Index c = 0; c < m.cols(); ++c) {
    const std::string where = field + " column " + std::to_string(c);
    if (!m.col(c).allFinite()) throw InputError(source, where, "holds a value that is not finite");
    const double largest = m.col(c).cwiseAbs().maxCoeff();
    if (largest == 0) throw InputError(source, where, std::string("is all zero: ") + what);
    const double sum = m.col(c).sum();
    if (std::abs(sum) > 1e-9 * largest) {
      char text[160];
      std::snprintf(text, sizeof text,
                    "sums to %.6g, not zero (largest entry %.6g): %s must sum to zero", sum,
                    largest, what);
      throw InputError(source, where, text);
    }
  }
}

std::vector<int> nonzero(const Eigen::VectorXd& column) {
  std::vector<int> out;
  for (Eigen::Index e = 0; e < column.size(); ++e)
    if (column[e] != 0) out.push_back(static_cast<int>(e));
  return out;
}

}  // namespace

void CurrentPatterns::validate(const std::string& source, const std::string& injection_field,
                               const std::string& measurement_field) const {
  if (injection.rows() < 2)
    throw InputError(
        source, injection_field,
        "has " + std::to_string(injection.rows()) + " rows; one an electrode, at least 2");
  if (injection.cols() == 0) throw InputError(source, injection_field, "has no pattern");
  if (measurement.rows() != injection.rows())
    throw InputError(source, measurement_field,
                     "has " + std::to_string(measurement.rows()) + " rows, the " + injection_field +
                         " " + std::to_string(injection.rows()) +
                         ": both have one row an electrode");
  if (measurement.cols() == 0) throw InputError(source, measurement_field, "has no difference");
  check_columns(injection, source, injection_field, "the currents of a pattern");
  check_columns(measurement, source, measurement_field, "the weights of a voltage difference");
}

std::vector<int> CurrentPatterns::driven(int pattern) const {
  return nonzero(injection.col(pattern));
}

std::vector<int> CurrentPatterns::read(int difference) const {
  return nonzero(measurement.col(difference));
}

std::vector<bool> CurrentPatterns::values_without(const std::vector<int>& removed) const {
  std::vector<bool> gone(static_cast<std::size_t>(electrodes()), false);
  for (int e : removed)
    if (e >= 0 && e < electrodes()) gone[static_cast<std::size_t>(e)] = true;
  auto uses = [&](const Eigen::VectorXd& column) {
    for (Eigen::Index e = 0; e < column.size(); ++e)
      if (column[e] != 0 && gone[static_cast<std::size_t>(e)]) return true;
    return false;
  };
  std::vector<bool> keep(static_cast<std::size_t>(size()), true);
  for (int p = 0; p < patterns(); ++p)
    for (int m = 0; m < differences(); ++m)
      keep[static_cast<std::size_t>(p * differences() + m)] =
          !uses(injection.col(p)) && !uses(measurement.col(m));
  return keep;
}

bool operator==(const CurrentPatterns& a, const CurrentPatterns& b) {
  return a.injection.rows() == b.injection.rows() && a.injection.cols() == b.injection.cols() &&
         a.measurement.rows() == b.measurement.rows() &&
         a.measurement.cols() == b.measurement.cols() && a.injection == b.injection &&
         a.measurement == b.measurement;
}

}  // namespace eitbench
