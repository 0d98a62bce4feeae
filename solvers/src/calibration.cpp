#include "eitbench/solvers/calibration.h"

#include <ceres/ceres.h>

#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include "eitbench/jacobian/error.h"

namespace eitbench {

void CalibrationOptions::validate() const {
  if (max_iterations < 1)
    throw InputError("CalibrationOptions", "max_iterations", "must be at least 1");
  if (!(max_factor > 1) || !std::isfinite(max_factor))
    throw InputError("CalibrationOptions", "max_factor", "must be finite and above 1");
}

namespace {

// The model's frame for p = [log sigma_0, log z_1, ..., log z_L], relative to the reference, on
// the reference's finite values.
struct FrameMisfit {
  const ForwardModel& base;  // the start's model: each evaluation changes its impedances alone
  const Eigen::VectorXd& reference;
  std::function<Eigen::VectorXd(const ForwardModel&, const Eigen::VectorXd&)> frame;
  std::vector<int> used;  // the reference's finite values
  double scale;           // 1 / ||reference||

  bool operator()(double const* const* parameters, double* residuals) const {
    const int L = base.mesh().num_electrodes();
    const double* p = parameters[0];
    Eigen::VectorXd z(L);
    for (int e = 0; e < L; ++e) z[e] = std::exp(p[1 + e]);
    const ForwardModel model = base.with_contact_impedances(z);
    const Eigen::VectorXd v =
        frame(model, Eigen::VectorXd::Constant(base.mesh().num_triangles(), std::exp(p[0])));
    bool finite = true;
    for (std::size_t i = 0; i < used.size(); ++i) {
      residuals[i] = (v[used[i]] - reference[used[i]]) * scale;
      finite = finite && std::isfinite(residuals[i]);
    }
    return finite;
  }
};

Calibration fit(const Mesh& mesh, const ForwardOptions& forward, double background,
                const Eigen::VectorXd& reference,
                std::function<Eigen::VectorXd(const ForwardModel&, const Eigen::VectorXd&)> frame,
                const CalibrationOptions& options, const std::string& source) {
  const int L = mesh.num_electrodes();
  std::vector<int> used;
  double norm2 = 0;
  for (Eigen::Index i = 0; i < reference.size(); ++i)
    if (std::isfinite(reference[i]))
      used.push_back(static_cast<int>(i)), norm2 += reference[i] * reference[i];
  if (used.empty() || norm2 == 0) throw InputError(source, "", "needs finite values, not all zero");
  if (!(background > 0) || !std::isfinite(background))
    throw InputError("background", "", "the start must be positive and finite");
  std::vector<double> p(static_cast<std::size_t>(L) + 1);
  p[0] = std::log(background);
  for (int e = 0; e < L; ++e)
    p[1 + e] = std::log(forward.contact_impedances.size() == L ? forward.contact_impedances[e]
                                                               : forward.contact_impedance);
  const int residuals = static_cast<int>(used.size());
  const ForwardModel base(mesh, forward);
  auto* cost = new ceres::DynamicNumericDiffCostFunction<FrameMisfit, ceres::CENTRAL>(
      new FrameMisfit{base, reference, std::move(frame), std::move(used), 1 / std::sqrt(norm2)});
  cost->AddParameterBlock(L + 1);
  cost->SetNumResiduals(residuals);
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
  return fit(
      mesh, forward, background, reference,
      [map, order](const ForwardModel& model, const Eigen::VectorXd& sigma) {
        return map ? model.adjacent_map(model.solve(sigma)) : model.frame(sigma, order);
      },
      options, source);
}

Calibration calibrate_measured(const Mesh& mesh, const ForwardOptions& forward, double background,
                               const Eigen::VectorXd& reference, const CalibrationOptions& options,
                               const std::string& source) {
  options.validate();
  forward.validate();
  const ForwardModel probe(mesh, forward);  // checks the protocol against the mesh
  const int size = probe.measurement_protocol().size();
  if (reference.size() != size)
    throw InputError(source, "",
                     "has " + std::to_string(reference.size()) + " values; the " +
                         probe.measurement_protocol().name() + " protocol reads " +
                         std::to_string(size) + ", absolute");
  for (Eigen::Index i = 0; i < reference.size(); ++i)
    if (std::isinf(reference[i]))
      throw InputError(source, "value " + std::to_string(i),
                       "is infinite (NaN marks a missing one)");
  return fit(
      mesh, forward, background, reference,
      [](const ForwardModel& model, const Eigen::VectorXd& sigma) { return model.measured(sigma); },
      options, source);
}

}  // namespace eitbench
