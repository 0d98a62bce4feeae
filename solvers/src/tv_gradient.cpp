#include "tv_gradient.h"

#include <algorithm>
#include <cmath>

#include "neighbour_graphs.h"
#include "operator_norm.h"

namespace eitbench::detail {

TvGradient TvGradient::pixels(const LinearProblem& problem, const Eigen::VectorXd& sensitivity) {
  TvGradient d;
  const int n = problem.grid.size();
  const std::vector<int> column = unknown_of_pixel(problem.pixels, n * n);
  for (int pixel : problem.pixels) {
    const int i = pixel / n, k = pixel % n;
    d.right_.push_back(k + 1 < n ? column[pixel + 1] : -1);
    d.down_.push_back(i + 1 < n ? column[pixel + n] : -1);
  }
  d.weight_ = sensitivity;
  d.duals_ = static_cast<Eigen::Index>(problem.pixels.size());
  return d;
}

TvGradient TvGradient::elements(const LinearProblem& problem, const Eigen::VectorXd& sensitivity) {
  TvGradient d;
  const Mesh& mesh = problem.model->mesh();
  const double h = problem.grid.pixel_width();
  const Eigen::VectorXd element_sensitivity = problem.element_from_pixels * sensitivity;
  std::vector<Eigen::Triplet<double>> entries;
  std::vector<double> weights;
  for (const InteriorEdge& edge : interior_edges(mesh)) {
    const int e = static_cast<int>(weights.size()), t = edge.second, u = edge.first;
    entries.insert(entries.end(), {{e, t, 1.0}, {e, u, -1.0}});
    weights.push_back((mesh.nodes.row(edge.a) - mesh.nodes.row(edge.b)).norm() / h * 0.5 *
                      (element_sensitivity[t] + element_sensitivity[u]));
  }
  Eigen::SparseMatrix<double, Eigen::RowMajor> D(static_cast<Eigen::Index>(weights.size()),
                                                 mesh.num_triangles());
  D.setFromTriplets(entries.begin(), entries.end());
  d.K_ = D * problem.element_from_pixels;
  d.Kt_ = d.K_.transpose();
  d.weight_ =
      Eigen::Map<const Eigen::VectorXd>(weights.data(), static_cast<Eigen::Index>(weights.size()));
  d.duals_ = d.K_.rows();
  d.norm2_ = squared_operator_norm(d.K_);
  return d;
}

void TvGradient::subtract_adjoint(const Eigen::VectorXd& zx, const Eigen::VectorXd& zy, double tau,
                                  Eigen::VectorXd& v) const {
  if (K_.rows() > 0) {
    v.noalias() -= tau * (Kt_ * zx);
    return;
  }
  for (Eigen::Index p = 0; p < v.size(); ++p) {
    if (right_[p] >= 0) v[right_[p]] -= tau * zx[p], v[p] += tau * zx[p];
    if (down_[p] >= 0) v[down_[p]] -= tau * zy[p], v[p] += tau * zy[p];
  }
}

void TvGradient::dual_step(const Eigen::VectorXd& bar, double sigma, double alpha, double rho,
                           Eigen::VectorXd& zx, Eigen::VectorXd& zy, Eigen::VectorXd& kbar) const {
  if (K_.rows() > 0) {  // anisotropic: each edge on its own interval
    kbar.noalias() = K_ * bar;
    for (Eigen::Index e = 0; e < kbar.size(); ++e) {
      const double bound = alpha * weight_[e];
      zx[e] += rho * (std::clamp(zx[e] + sigma * kbar[e], -bound, bound) - zx[e]);
    }
    return;
  }
  for (Eigen::Index p = 0; p < bar.size(); ++p) {  // isotropic: each pixel's pair on a disc
    const double bx = bar[p];
    const double dx = right_[p] >= 0 ? bar[right_[p]] - bx : 0.0;
    const double dy = down_[p] >= 0 ? bar[down_[p]] - bx : 0.0;
    double a = zx[p] + sigma * dx, b = zy[p] + sigma * dy;
    const double norm = std::sqrt(a * a + b * b), bound = alpha * weight_[p];
    if (norm > bound) a *= bound / norm, b *= bound / norm;
    zx[p] += rho * (a - zx[p]), zy[p] += rho * (b - zy[p]);
  }
}

double TvGradient::total_variation(const Eigen::VectorXd& x) const {
  if (K_.rows() > 0) return (K_ * x).cwiseAbs().dot(weight_);
  double tv = 0;  // isotropic: the pair's norm
  for (Eigen::Index p = 0; p < x.size(); ++p) {
    const double dx = right_[p] >= 0 ? x[right_[p]] - x[p] : 0.0;
    const double dy = down_[p] >= 0 ? x[down_[p]] - x[p] : 0.0;
    tv += weight_[p] * std::sqrt(dx * dx + dy * dy);
  }
  return tv;
}

}  // namespace eitbench::detail
