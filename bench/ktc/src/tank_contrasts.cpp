// The contrasts of KTC's targets, measured on its labelled training samples.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

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

KtcContrastFits fit_ktc_contrasts_held_out(const KtcTank& tank,
                                           const std::vector<Eigen::VectorXd>& changes,
                                           const std::vector<ClassImage>& truths,
                                           const KtcOrientation& orientation, int steps) {
  if (changes.size() != truths.size() || changes.empty())
    throw InputError("fit_ktc_contrasts", "truths", "one truth a measured change, at least one");
  if (steps < 2) throw InputError("fit_ktc_contrasts", "steps", "must be at least 2");
  const double s0 = tank.background;
  const Eigen::VectorXd empty =
      tank.model->measured(Eigen::VectorXd::Constant(tank.mesh.num_triangles(), s0));
  const std::size_t S = truths.size();
  std::vector<std::vector<std::uint8_t>> classes;
  // A value a change lacks (NaN) counts in no misfit: the change and its present values.
  std::vector<Eigen::VectorXd> change, present;
  KtcContrastFits fits;
  for (std::size_t k = 0; k < S; ++k) {
    classes.push_back(element_classes(tank.mesh, truths[k], tank.options.radius, orientation));
    present.push_back(changes[k].array().isFinite().cast<double>().matrix());
    change.push_back(changes[k].array().isFinite().select(changes[k], 0.0).matrix());
    fits.measured.push_back(change[k].squaredNorm());
    fits.values.push_back(static_cast<int>(present[k].sum()));
  }
  const std::vector<double>& measured = fits.measured;
  // Ratios 10^-3 ... 10^-0.1 resistive and 10^0.1 ... 10^3 conductive, log-spaced; each sample's
  // misfit at each pair once, so that any subset's fit is a sum over it.
  auto ratio = [&](int i, double low, double high) {
    return std::pow(10.0, low + (high - low) * i / (steps - 1));
  };
  for (int a = 0; a < steps; ++a)
    for (int b = 0; b < steps; ++b) {
      KtcContrastFits::Point p{ratio(a, -3, -0.1), ratio(b, 0.1, 3), {}};
      for (std::size_t k = 0; k < S; ++k) {
        Eigen::VectorXd sigma(tank.mesh.num_triangles());
        for (int t = 0; t < sigma.size(); ++t)
          sigma[t] = s0 * (classes[k][t] == 1   ? p.resistive
                           : classes[k][t] == 2 ? p.conductive
                                                : 1.0);
        p.misfit.push_back((tank.model->measured(sigma) - empty - change[k])
                               .cwiseProduct(present[k])
                               .squaredNorm());
      }
      fits.grid.push_back(std::move(p));
    }
  auto best_without = [&](std::size_t left_out) {  // S: none left out
    KtcContrasts best;
    double best_misfit = INFINITY, norm = 0;
    for (std::size_t k = 0; k < S; ++k)
      if (k != left_out) norm += measured[k];
    for (const auto& p : fits.grid) {
      double misfit = 0;
      for (std::size_t k = 0; k < S; ++k)
        if (k != left_out) misfit += p.misfit[k];
      if (misfit < best_misfit)
        best_misfit = misfit, best = {p.resistive, p.conductive, std::sqrt(misfit / norm)};
    }
    return best;
  };
  fits.all = best_without(S);
  if (S > 1)
    for (std::size_t k = 0; k < S; ++k) fits.without.push_back(best_without(k));
  return fits;
}

KtcContrasts KtcContrastFits::best_within(double r_low, double r_high, double c_low,
                                          double c_high) const {
  KtcContrasts best;
  best.relative_residual = INFINITY;
  double norm = 0;
  for (double m : measured) norm += m;
  for (const Point& p : grid) {
    if (p.resistive < r_low || p.resistive > r_high || p.conductive < c_low ||
        p.conductive > c_high)
      continue;
    double misfit = 0;
    for (double m : p.misfit) misfit += m;
    const double residual = std::sqrt(misfit / norm);
    if (residual < best.relative_residual) best = {p.resistive, p.conductive, residual};
  }
  return best;
}

std::vector<KtcMisfit> KtcContrastFits::own_misfits() const {
  std::vector<KtcMisfit> out;
  for (std::size_t k = 0; k < measured.size(); ++k) {
    double best = INFINITY;
    for (const Point& p : grid) best = std::min(best, p.misfit[k]);
    out.push_back({measured[k] > 0 ? std::sqrt(best / measured[k]) : 0.0,
                   values[k] > 0 ? std::sqrt(best / values[k]) : 0.0, values[k]});
  }
  return out;
}

double ktc_misfit_noise(const std::vector<KtcMisfit>& misfits, std::size_t held_out) {
  double squares = 0, values = 0;
  for (std::size_t k = 0; k < misfits.size(); ++k)
    if (k != held_out && misfits[k].relative <= kKtcMisfitExplained) {
      squares += misfits[k].rms * misfits[k].rms * misfits[k].values;
      values += misfits[k].values;
    }
  return values > 0 ? std::sqrt(squares / values) : std::numeric_limits<double>::quiet_NaN();
}

KtcContrasts fit_ktc_contrasts(const KtcTank& tank, const std::vector<Eigen::VectorXd>& changes,
                               const std::vector<ClassImage>& truths,
                               const KtcOrientation& orientation, int steps) {
  return fit_ktc_contrasts_held_out(tank, changes, truths, orientation, steps).all;
}

}  // namespace eitbench
