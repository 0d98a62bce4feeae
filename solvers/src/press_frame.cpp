#include "eitbench/solvers/press_frame.h"

#include <tbb/parallel_for.h>

#include <cmath>

#include "eitbench/jacobian/constants.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

void PressFrameOptions::validate() const {
  if (!(step_degrees > 0 && step_degrees <= 90))
    throw InputError("PressFrameOptions", "step_degrees", "must lie in (0, 90]");
  if (!(touch_radius > 0 && touch_radius < 1))
    throw InputError("PressFrameOptions", "touch_radius", "must lie in (0, 1) (x R)");
}

namespace {

void check_inputs(const LinearProblem& p, const SampleMatrix& differences,
                  const Eigen::MatrixX2d& positions) {
  p.check_frame_size(differences.cols());
  if (differences.rows() != positions.rows())
    throw InputError("presses", "positions", "need one position a frame");
  if (differences.rows() < 3) throw InputError("presses", "", "need at least 3 presses");
  if (!differences.allFinite() || !positions.allFinite())
    throw InputError("presses", "", "hold a value that is not finite");
}

// The model's change for a disc of contrast 1 at `at`: the columns of A whose pixel it covers.
Eigen::VectorXd disc_change(const LinearProblem& p, const std::vector<Eigen::Vector2d>& centres,
                            const Eigen::Vector2d& at, double radius) {
  Eigen::VectorXd v = Eigen::VectorXd::Zero(p.A.rows());
  for (std::size_t j = 0; j < centres.size(); ++j)
    if ((centres[j] - at).squaredNorm() < radius * radius)
      v += p.A.col(static_cast<Eigen::Index>(j));
  return v;
}

// The mean cosine between measured and predicted changes with the positions turned by `degrees`.
double mean_cosine(const LinearProblem& p, const std::vector<Eigen::Vector2d>& centres,
                   const SampleMatrix& differences, const Eigen::MatrixX2d& positions,
                   double degrees, bool mirror, double radius) {
  const double a = degrees * kPi / 180, c = std::cos(a), s = std::sin(a);
  double total = 0;
  for (Eigen::Index i = 0; i < positions.rows(); ++i) {
    const double x = positions(i, 0), y = mirror ? -positions(i, 1) : positions(i, 1);
    const Eigen::VectorXd v = disc_change(p, centres, {c * x - s * y, s * x + c * y}, radius);
    const double norms = v.norm() * differences.row(i).norm();
    if (norms > 0) total += differences.row(i).dot(v) / norms;
  }
  return total / static_cast<double>(positions.rows());
}

double angle_between(double a, double b) {
  const double d = std::fmod(std::abs(a - b), 360.0);
  return std::min(d, 360 - d);
}

}  // namespace

PressFrame fit_press_frame(const LinearProblem& problem, const SampleMatrix& differences,
                           const Eigen::MatrixX2d& positions, const PressFrameOptions& options) {
  options.validate();
  check_inputs(problem, differences, positions);
  std::vector<Eigen::Vector2d> centres;
  for (Eigen::Index j = 0; j < problem.unknowns(); ++j) centres.push_back(problem.pixel_centre(j));
  const double radius = options.touch_radius * problem.grid.radius();
  const int turns = static_cast<int>(std::ceil(360 / options.step_degrees - 1e-9));
  std::vector<double> cosine(static_cast<std::size_t>(2 * turns));  // [mirror][turn]
  tbb::parallel_for(0, 2 * turns, [&](int k) {
    cosine[static_cast<std::size_t>(k)] =
        mean_cosine(problem, centres, differences, positions, (k % turns) * options.step_degrees,
                    k >= turns, radius);
  });
  const auto best = std::max_element(cosine.begin(), cosine.end()) - cosine.begin();
  PressFrame f;
  f.mirror = best >= turns;
  f.rotate_degrees = static_cast<double>(best % turns) * options.step_degrees;
  f.cosine = cosine[static_cast<std::size_t>(best)];
  f.other_mirror_cosine = f.other_turn_cosine = -1;
  for (int k = 0; k < 2 * turns; ++k) {
    const double v = cosine[static_cast<std::size_t>(k)];
    if ((k >= turns) != f.mirror)
      f.other_mirror_cosine = std::max(f.other_mirror_cosine, v);
    else if (angle_between((k % turns) * options.step_degrees, f.rotate_degrees) >= 45)
      f.other_turn_cosine = std::max(f.other_turn_cosine, v);
  }
  return f;
}

}  // namespace eitbench
