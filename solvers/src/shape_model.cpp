#include "shape_model.h"

#include <tbb/parallel_for.h>

#include <array>
#include <cmath>

namespace eitbench::detail {
namespace {

Eigen::Matrix2Xd element_centroids(const Mesh& mesh) {
  Eigen::Matrix2Xd c(2, mesh.num_triangles());
  for (int t = 0; t < mesh.num_triangles(); ++t) c.col(t) = triangle_centroid(mesh, t);
  return c;
}

// The indicator of one circle at one element and its derivatives by d and r.
struct Indicator {
  double h, dh_dr;  // dh/dd = -dh_dr
};
Indicator indicator(double r, double d, double w) {
  const double t = std::tanh((r - d) / w);
  return {0.5 * (1 + t), 0.5 * (1 - t * t) / w};
}

}  // namespace

ShapeModel::ShapeModel(const LinearProblem& problem, double width)
    : problem_(problem), centroids_(element_centroids(problem.model->mesh())) {
  const Mesh& mesh = problem.model->mesh();
  const double mean_size = std::sqrt(triangle_areas(mesh).cwiseAbs().mean() * 2);
  width_ = width > 0 ? width : 0.5 * mean_size;
  const auto background = Eigen::VectorXd::Constant(mesh.num_triangles(), problem.background);
  const ForwardSolution s0 = problem.model->solve(background);
  J0_ = problem.model_jacobian(s0);
  v0_ = problem.model_inputs(s0);
}

Eigen::VectorXd ShapeModel::relative_sigma(const std::vector<const double*>& circles) const {
  Eigen::VectorXd s = Eigen::VectorXd::Ones(centroids_.cols());
  for (const double* p : circles) {
    const double reach = p[2] + kReach * width_;
    for (Eigen::Index t = 0; t < s.size(); ++t) {
      const double d = distance(t, p);
      if (d < reach) s[t] *= 1 - p[3] * indicator(p[2], d, width_).h;
    }
  }
  return s;
}

Eigen::Vector4d ShapeModel::scaled_derivatives(Eigen::Index t, const double* p, double d, double h,
                                               double dh_dr, double f) const {
  const double c = p[3], dh_dd = -dh_dr;
  // d d / d cx = (cx - x) / d: zero at the centre itself, where d has no gradient.
  const double ux = d > 0 ? (p[0] - centroids_(0, t)) / d : 0.0;
  const double uy = d > 0 ? (p[1] - centroids_(1, t)) / d : 0.0;
  return {f * c * dh_dd * ux, f * c * dh_dd * uy, f * c * dh_dr, f * h};
}

Eigen::MatrixXd ShapeModel::relative_sigma_jacobian(const std::vector<const double*>& circles,
                                                    const std::vector<int>& elements) const {
  const bool all = elements.empty();
  const Eigen::Index n = all ? centroids_.cols() : static_cast<Eigen::Index>(elements.size());
  const Eigen::Index K = static_cast<Eigen::Index>(circles.size());
  Eigen::MatrixXd ds = Eigen::MatrixXd::Zero(n, kCircleParameters * K);
  std::vector<Indicator> h(static_cast<std::size_t>(K));
  std::vector<double> d(static_cast<std::size_t>(K));
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index t = all ? k : elements[static_cast<std::size_t>(k)];
    for (Eigen::Index j = 0; j < K; ++j) {  // as relative_sigma: nothing beyond a circle's reach
      const double* p = circles[j];
      d[j] = distance(t, p);
      h[j] = d[j] < p[2] + kReach * width_ ? indicator(p[2], d[j], width_) : Indicator{0, 0};
    }
    for (Eigen::Index j = 0; j < K; ++j) {
      double others = 1;  // prod over i != j of (1 - c_i H_i)
      for (Eigen::Index i = 0; i < K; ++i)
        if (i != j) others *= 1 - circles[i][3] * h[i].h;
      ds.block<1, kCircleParameters>(k, kCircleParameters * j) =
          scaled_derivatives(t, circles[j], d[j], h[j].h, h[j].dh_dr, -others).transpose();
    }
  }
  return ds;
}

std::vector<int> ShapeModel::reached_elements(const std::vector<const double*>& circles) const {
  std::vector<int> out;
  for (Eigen::Index t = 0; t < centroids_.cols(); ++t)
    for (const double* p : circles) {
      const double reach = p[2] + kReach * width_;
      if ((centroids_.col(t) - Eigen::Vector2d(p[0], p[1])).squaredNorm() < reach * reach) {
        out.push_back(static_cast<int>(t));
        break;
      }
    }
  return out;
}

// The linear model element by element: each circle's indicator only where it reaches, each
// element's column of J0 added once to the frame and once to each reaching circle's four Jacobian
// columns. A dense product over the union of the supports cost 4K columns on every element of it
// (three of them zero away from the circle's edge), and the copy of J0's columns as much again.
// The elements go in kBlocks fixed ranges, in parallel, their sums added in block order: the same
// bits on any number of threads.
Eigen::VectorXd ShapeModel::linear_difference(const std::vector<const double*>& circles,
                                              Eigen::MatrixXd* jacobian) const {
  const Eigen::Index K = static_cast<Eigen::Index>(circles.size()), m = J0_.rows();
  const Eigen::Index n = centroids_.cols();
  constexpr int kBlocks = 4;
  struct Sums {
    Eigen::VectorXd v;
    Eigen::MatrixXd J;
  };
  std::array<Sums, kBlocks> sums;
  tbb::parallel_for(0, kBlocks, [&](int b) {
    Sums& s = sums[static_cast<std::size_t>(b)];
    s.v = Eigen::VectorXd::Zero(m);
    if (jacobian) s.J = Eigen::MatrixXd::Zero(m, kCircleParameters * K);
    add_linear_terms(circles, n * b / kBlocks, n * (b + 1) / kBlocks, s.v,
                     jacobian ? &s.J : nullptr);
  });
  for (int b = 1; b < kBlocks; ++b) {
    sums[0].v += sums[static_cast<std::size_t>(b)].v;
    if (jacobian) sums[0].J += sums[static_cast<std::size_t>(b)].J;
  }
  if (jacobian) *jacobian = std::move(sums[0].J);
  return std::move(sums[0].v);
}

void ShapeModel::add_linear_terms(const std::vector<const double*>& circles, Eigen::Index first,
                                  Eigen::Index last, Eigen::VectorXd& v,
                                  Eigen::MatrixXd* jacobian) const {
  const double sigma0 = problem_.background;
  const Eigen::Index K = static_cast<Eigen::Index>(circles.size());
  std::vector<Indicator> h(static_cast<std::size_t>(K));
  std::vector<double> d(static_cast<std::size_t>(K));
  std::vector<char> reaches(static_cast<std::size_t>(K));
  for (Eigen::Index t = first; t < last; ++t) {
    bool any = false;
    double s = 1;
    for (Eigen::Index j = 0; j < K; ++j) {
      const double* p = circles[j];
      const double dx = centroids_(0, t) - p[0], dy = centroids_(1, t) - p[1];
      const double reach = p[2] + kReach * width_, d2 = dx * dx + dy * dy;
      reaches[j] = d2 < reach * reach;
      if (!reaches[j]) continue;
      any = true;
      d[j] = std::sqrt(d2);
      h[j] = indicator(p[2], d[j], width_);
      s *= 1 - p[3] * h[j].h;
    }
    if (!any) continue;
    const auto column = J0_.col(t);
    v.noalias() += (sigma0 * (s - 1)) * column;
    if (!jacobian) continue;
    for (Eigen::Index j = 0; j < K; ++j) {
      if (!reaches[j]) continue;
      double others = 1;  // prod over the other reaching circles of (1 - c_i H_i)
      for (Eigen::Index i = 0; i < K; ++i)
        if (i != j && reaches[i]) others *= 1 - circles[i][3] * h[i].h;
      const Eigen::Vector4d g =
          scaled_derivatives(t, circles[j], d[j], h[j].h, h[j].dh_dr, -sigma0 * others);
      jacobian->middleCols<kCircleParameters>(kCircleParameters * j).noalias() +=
          column * g.transpose();
    }
  }
}

Eigen::VectorXd ShapeModel::difference(const std::vector<const double*>& circles, bool full,
                                       Eigen::MatrixXd* jacobian) const {
  if (!full) return linear_difference(circles, jacobian);
  const double sigma0 = problem_.background;
  const Eigen::VectorXd s = relative_sigma(circles);
  const ForwardModel& model = *problem_.model;
  const ForwardSolution solution = model.solve(sigma0 * s);
  if (jacobian) {
    // Only the elements the circles reach move: the element Jacobian's other columns would meet
    // zero rows of ds/dp (below 1.3e-5 of them), and computing them and their product took two
    // fifths of a full fit.
    const std::vector<int> reached = reached_elements(circles);
    *jacobian = sigma0 * (problem_.model_jacobian(solution, reached) *
                          relative_sigma_jacobian(circles, reached));
  }
  return problem_.model_inputs(solution) - v0_;
}

}  // namespace eitbench::detail
