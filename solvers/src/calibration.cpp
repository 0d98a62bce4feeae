#include "eitbench/solvers/calibration.h"

#include <ceres/ceres.h>

#include <cmath>
#include <memory>

#include "eitbench/jacobian/error.h"

namespace eitbench {

void CalibrationOptions::validate() const {
  if (max_iterations < 1)
    throw InputError("CalibrationOptions", "max_iterations", "must be at least 1");
  if (!(max_factor > 1) || !std::isfinite(max_factor))
    throw InputError("CalibrationOptions", "max_factor", "must be finite and above 1");
}

namespace {

// The model's frame for p = [log sigma_0, log z_1, ..., log z_L], relative to the reference.
struct FrameMisfit {
  const Mesh& mesh;
  ForwardOptions forward;
  const Eigen::VectorXd& reference;
  MeasurementOrder order;
  bool map;      // reference is an L x L adjacent map (ForwardModel::adjacent_map)
  double scale;  // 1 / ||reference||

  bool operator()(double const* const* parameters, double* residuals) const {
    const int L = mesh.num_electrodes();
    const double* p = parameters[0];
    ForwardOptions o = forward;
    o.contact_impedances.resize(L);
    for (int e = 0; e < L; ++e) o.contact_impedances[e] = std::exp(p[1 + e]);
    const ForwardModel model(mesh, o);
    const Eigen::VectorXd sigma = Eigen::VectorXd::Constant(mesh.num_triangles(), std::exp(p[0]));
    const Eigen::VectorXd v =
        map ? model.adjacent_map(model.solve(sigma)) : model.frame(sigma, order);
    Eigen::Map<Eigen::VectorXd>(residuals, v.size()) = (v - reference) * scale;
    return v.allFinite();
  }
};

}  // namespace

Calibration calibrate(const Mesh& mesh, const ForwardOptions& forward, double background,
                      const Eigen::VectorXd& reference, MeasurementOrder order,
                      const CalibrationOptions& options, const std::string& source) {
  options.validate();
  forward.validate();
  const int L = mesh.num_electrodes();
  const bool map = reference.size() == L * L;
  if (reference.size() != L * (L - 3) && !map)
    throw InputError(source, "",
                     "has " + std::to_string(reference.size()) + " values; " +
                         std::to_string(L * (L - 3)) + " (L(L-3)) or " + std::to_string(L * L) +
                         " (an L x L adjacent map) expected, absolute");
  if (!reference.allFinite() || reference.norm() == 0)
    throw InputError(source, "", "needs finite values, not all zero");
  if (!(background > 0) || !std::isfinite(background))
    throw InputError("background", "", "the start must be positive and finite");
  std::vector<double> p(static_cast<std::size_t>(L) + 1);
  p[0] = std::log(background);
  for (int e = 0; e < L; ++e)
    p[1 + e] = std::log(forward.contact_impedances.size() == L ? forward.contact_impedances[e]
                                                               : forward.contact_impedance);
  auto* cost = new ceres::DynamicNumericDiffCostFunction<FrameMisfit, ceres::CENTRAL>(
      new FrameMisfit{mesh, forward, reference, order, map, 1 / reference.norm()});
  cost->AddParameterBlock(L + 1);
  cost->SetNumResiduals(static_cast<int>(reference.size()));
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, p.data());
  const double room = std::log(options.max_factor);
  for (int k = 0; k <= L; ++k) {
    problem.SetParameterLowerBound(p.data(), k, p[k] - room);
    problem.SetParameterUpperBound(p.data(), k, p[k] + room);
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = options.max_iterations;
  so.function_tolerance = 1e-12;
  so.parameter_tolerance = 1e-10;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  Calibration out;
  out.background = std::exp(p[0]);
  out.contact_impedances.resize(L);
  for (int e = 0; e < L; ++e) out.contact_impedances[e] = std::exp(p[1 + e]);
  out.relative_residual = std::sqrt(2 * summary.final_cost);
  out.iterations = static_cast<int>(summary.iterations.size());
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  return out;
}

}  // namespace eitbench
