// The contrasts of KTC's targets, measured on its labelled training samples.
#include <Eigen/Core>
#include <cmath>

#include "eitbench/bench/ktc/tank_simulation.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

// Each element's class: the truth's pixel under its centroid (KTC's 256 x 256 over [-R, R]^2).
std::vector<std::uint8_t> element_classes(const Mesh& mesh, const ClassImage& truth, double R,
                                          const KtcOrientation& orientation) {
  const int n = static_cast<int>(truth.rows());
  const double w = 2 * R / n;
  std::vector<std::uint8_t> classes(mesh.num_triangles(), 0);
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector2d q = orientation.to_image(triangle_centroid(mesh, t));
    const int i = static_cast<int>(std::floor((R - q.y()) / w));
    const int j = static_cast<int>(std::floor((q.x() + R) / w));
    if (i >= 0 && j >= 0 && i < n && j < n) classes[t] = truth(i, j);
  }
  return classes;
}

}  // namespace

KtcContrasts fit_ktc_contrasts(const KtcTank& tank, const std::vector<Eigen::VectorXd>& changes,
                               const std::vector<ClassImage>& truths,
                               const KtcOrientation& orientation, int steps) {
  if (changes.size() != truths.size() || changes.empty())
    throw InputError("fit_ktc_contrasts", "truths", "one truth a measured change, at least one");
  if (steps < 2) throw InputError("fit_ktc_contrasts", "steps", "must be at least 2");
  const double s0 = tank.background;
  const Eigen::VectorXd empty =
      tank.model->measured(Eigen::VectorXd::Constant(tank.mesh.num_triangles(), s0));
  std::vector<std::vector<std::uint8_t>> classes;
  double measured = 0;
  for (std::size_t k = 0; k < truths.size(); ++k) {
    classes.push_back(element_classes(tank.mesh, truths[k], tank.options.radius, orientation));
    measured += changes[k].squaredNorm();
  }
  // Ratios 10^-3 ... 10^-0.1 resistive and 10^0.1 ... 10^3 conductive, log-spaced.
  auto ratio = [&](int i, double low, double high) {
    return std::pow(10.0, low + (high - low) * i / (steps - 1));
  };
  KtcContrasts best;
  double best_misfit = INFINITY;
  for (int a = 0; a < steps; ++a)
    for (int b = 0; b < steps; ++b) {
      const double r = ratio(a, -3, -0.1), c = ratio(b, 0.1, 3);
      double misfit = 0;
      for (std::size_t k = 0; k < truths.size(); ++k) {
        Eigen::VectorXd sigma(tank.mesh.num_triangles());
        for (int t = 0; t < sigma.size(); ++t)
          sigma[t] = s0 * (classes[k][t] == 1 ? r : classes[k][t] == 2 ? c : 1.0);
        misfit += (tank.model->measured(sigma) - empty - changes[k]).squaredNorm();
      }
      if (misfit < best_misfit) best_misfit = misfit, best = {r, c, std::sqrt(misfit / measured)};
    }
  return best;
}

}  // namespace eitbench
