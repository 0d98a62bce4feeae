#include "eitbench/augment/pattern_symmetry.h"

#include <Eigen/QR>
#include <cmath>
#include <string>
#include <tuple>

#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

constexpr double kTolerance = 1e-9;  // relative: the matrices are read from files as doubles

// Rows moved by the electrode map: out.row(e) = in.row(pi(e)), so out.col(j) is in.col(j) o pi.
Eigen::MatrixXd moved_rows(const Eigen::MatrixXd& in, const GroupElement& g) {
  const int L = static_cast<int>(in.rows());
  Eigen::MatrixXd out(in.rows(), in.cols());
  for (int e = 0; e < L; ++e) out.row(e) = in.row(electrode_image(g, e, L));
  return out;
}

// The pattern that `image` is a multiple of, and the factor, -1 when none is. Where several are
// (KTC drives the pair 7-9 and "9 against 7"), the action should still be a permutation of the
// measured patterns, each used once, and the identity the identity: an unused one first, then a
// positive factor, then the factor nearest 1 (the same pattern at its own amplitude), then the
// first.
int parallel_pattern(const Eigen::MatrixXd& injection, const Eigen::VectorXd& image,
                     const std::vector<bool>& used, double& factor) {
  int found = -1;
  std::tuple<bool, bool, double> best;
  for (int k = 0; k < injection.cols(); ++k) {
    const Eigen::VectorXd column = injection.col(k);
    const double s = column.dot(image) / column.squaredNorm();
    if ((image - s * column).norm() > kTolerance * image.norm()) continue;
    const std::tuple<bool, bool, double> rank{used[k], s < 0, std::abs(s - 1)};
    if (found < 0 || rank < best) found = k, factor = s, best = rank;
  }
  return found;
}

std::string dropped_to(const GroupElement& g) {
  return " under " + g.to_string() + ": the protocol is not symmetric under that element";
}

}  // namespace

Eigen::VectorXd PatternAction::apply(const Eigen::VectorXd& frame) const {
  const Eigen::Index M = differences.rows(), P = static_cast<Eigen::Index>(source.size());
  if (frame.size() != P * M)
    throw InputError("frame", "values",
                     "has " + std::to_string(frame.size()) + " values, not the protocol's " +
                         std::to_string(P * M) + " (" + std::to_string(P) + " patterns x " +
                         std::to_string(M) + " differences)");
  Eigen::VectorXd out(frame.size());
  for (Eigen::Index p = 0; p < P; ++p)
    out.segment(p * M, M) = scale[p] * (differences * frame.segment(source[p] * M, M));
  return out;
}

PatternAction pattern_action(const CurrentPatterns& patterns, const GroupElement& g) {
  PatternAction out;
  const Eigen::MatrixXd injection = moved_rows(patterns.injection, g);
  std::vector<bool> used(patterns.patterns(), false);
  for (int j = 0; j < patterns.patterns(); ++j) {
    double factor = 0;
    const int k = parallel_pattern(patterns.injection, injection.col(j), used, factor);
    if (k < 0)
      throw InputError("protocol", "pattern " + std::to_string(j),
                       "moves to currents that are no pattern of the set" + dropped_to(g));
    out.source.push_back(k), out.scale.push_back(factor), used[k] = true;
  }
  // Each moved difference as a combination of the set's: W A = W o pi, by least squares, checked.
  const Eigen::MatrixXd& W = patterns.measurement;
  const Eigen::MatrixXd moved = moved_rows(W, g);
  const Eigen::MatrixXd A = W.completeOrthogonalDecomposition().solve(moved);
  for (int m = 0; m < patterns.differences(); ++m)
    if ((W * A.col(m) - moved.col(m)).norm() > kTolerance * moved.col(m).norm())
      throw InputError("protocol", "difference " + std::to_string(m),
                       "moves to a difference the set's differences do not give" + dropped_to(g));
  // v'(m) = (m o pi)^T U = sum_n A(n, m) v(n): the rows of the action are A's columns.
  out.differences = A.transpose();
  for (Eigen::Index i = 0; i < out.differences.size(); ++i)  // exact zeros and ones, not 1e-17
    if (std::abs(out.differences.data()[i]) < kTolerance) out.differences.data()[i] = 0;
  return out;
}

}  // namespace eitbench
